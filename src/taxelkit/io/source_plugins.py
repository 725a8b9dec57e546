"""Frame sources as plugins: the ``taxelkit.sources`` entry-point group.

A SOURCE string is ``KIND:ADDRESS``. ``KIND`` names a *source factory*:

    factory(address: str, *, shape: tuple[int, int] | None, max_taxels: int) -> FrameSource

which opens the device at ``address`` and returns a
:class:`~taxelkit.io.live_sources.FrameSource` (a ``poll``/``close`` pair that
yields :class:`~taxelkit.io.frame_protocol.DecodedFrame` objects). The
built-in kinds are

``serial``
    ``serial:PORT[@BAUD]``, a serial port (pyserial, ``taxelkit[live]``);
``udp``
    ``udp:HOST:PORT``, datagrams on a local address;
``file``
    ``file:PATH``, a file or named pipe holding the bytes a device sends
    (``docs/live-protocol.md``), e.g. a capture replayed later.

A package adds a kind without any change to taxelkit by declaring an entry
point in its own ``pyproject.toml``::

    [project.entry-points."taxelkit.sources"]
    acme = "acme_taxels.taxelkit_source:open_acme"

after which ``taxelkit recognize --live acme:SERIALNUMBER`` works and
``taxelkit sources`` lists it. :func:`register_source` does the same for one
process (a notebook, a test). A plugin cannot replace a built-in kind.
"""

from __future__ import annotations

import importlib
import logging
import os
from collections.abc import Callable
from dataclasses import dataclass
from importlib.metadata import entry_points
from typing import Protocol

from taxelkit.io.frame_protocol import DEFAULT_MAX_TAXELS
from taxelkit.io.live_sources import (
    ByteStreamSource,
    FrameSource,
    LiveSourceError,
    SourceSpecError,
    open_source,
    parse_source,
)

__all__ = [
    "BUILTIN_SOURCES",
    "ENTRY_POINT_GROUP",
    "SourceFactory",
    "SourcePlugin",
    "open_file",
    "open_plugin_source",
    "open_serial",
    "open_udp",
    "register_source",
    "resolve_source",
    "source_plugins",
]

logger = logging.getLogger(__name__)

#: The entry-point group plugins declare their source factories in.
ENTRY_POINT_GROUP = "taxelkit.sources"
#: Distribution name shown for the built-in kinds.
_BUILTIN_ORIGIN = "taxelkit (built-in)"


class SourceFactory(Protocol):
    """Opens a device: ``factory(address, *, shape, max_taxels) -> FrameSource``."""

    def __call__(
        self, address: str, *, shape: tuple[int, int] | None, max_taxels: int
    ) -> FrameSource:
        """Open the source at ``address``."""
        ...


def open_serial(
    address: str, *, shape: tuple[int, int] | None = None, max_taxels: int = DEFAULT_MAX_TAXELS
) -> FrameSource:
    """Serial port ``PORT[@BAUD]`` (pyserial; ``taxelkit[live]``)."""
    return open_source(parse_source(f"serial:{address}"), shape=shape, max_taxels=max_taxels)


def open_udp(
    address: str, *, shape: tuple[int, int] | None = None, max_taxels: int = DEFAULT_MAX_TAXELS
) -> FrameSource:
    """UDP datagrams on a local address ``HOST:PORT``."""
    return open_source(parse_source(f"udp:{address}"), shape=shape, max_taxels=max_taxels)


def open_file(
    address: str, *, shape: tuple[int, int] | None = None, max_taxels: int = DEFAULT_MAX_TAXELS
) -> FrameSource:
    """A file or named pipe ``PATH`` holding the device's byte stream (live protocol).

    Raises
    ------
    LiveSourceError
        If the file cannot be opened; the message names it.
    """
    try:
        fd = os.open(address, os.O_RDONLY)
    except OSError as exc:
        raise LiveSourceError(f"cannot open file:{address} ({exc.strerror or exc})") from None
    return ByteStreamSource(
        fd, description=f"file:{address}", close_fd=True, shape=shape, max_taxels=max_taxels
    )


#: The built-in kinds and their factories (also declared as entry points in
#: taxelkit's own ``pyproject.toml``).
BUILTIN_SOURCES: dict[str, str] = {
    "serial": "taxelkit.io.source_plugins:open_serial",
    "udp": "taxelkit.io.source_plugins:open_udp",
    "file": "taxelkit.io.source_plugins:open_file",
}
_REGISTERED: dict[str, SourceFactory] = {}


@dataclass(frozen=True)
class SourcePlugin:
    """A source kind: its name, where its factory lives, and who provides it.

    Attributes
    ----------
    name : str
        The ``KIND`` of SOURCE strings.
    target : str
        ``"module:attribute"`` of the factory, or ``"<registered>"``.
    origin : str
        The distribution that declares it.
    """

    name: str
    target: str
    origin: str

    def load(self) -> SourceFactory:
        """Import the factory.

        Raises
        ------
        LiveSourceError
            If the plugin's module or attribute cannot be imported (named in the message).
        """
        if self.name in _REGISTERED and self.target == "<registered>":
            return _REGISTERED[self.name]
        module_name, _, attribute = self.target.partition(":")
        try:
            factory = importlib.import_module(module_name)
            for part in attribute.split(".") if attribute else ():
                factory = getattr(factory, part)
        except Exception as exc:
            raise LiveSourceError(
                f"source plugin {self.name!r} from {self.origin} cannot be loaded "
                f"({self.target}: {type(exc).__name__}: {exc})"
            ) from exc
        if not callable(factory):
            raise LiveSourceError(f"source plugin {self.name!r} ({self.target}) is not callable")
        loaded: SourceFactory = factory
        return loaded

    @property
    def summary(self) -> str:
        """First line of the factory's docstring, or ``""`` if it cannot be loaded."""
        try:
            doc = self.load().__doc__ or ""
        except LiveSourceError:
            return "(cannot be loaded)"
        return doc.strip().splitlines()[0] if doc.strip() else ""


def register_source(name: str, factory: SourceFactory) -> None:
    """Register a source kind for this process (what an entry point does for an install).

    Raises
    ------
    SourceSpecError
        If ``name`` is not a lower-case identifier, or is a built-in kind.
    """
    if not name.isidentifier() or name != name.lower():
        raise SourceSpecError(f"a source kind must be a lower-case identifier, got {name!r}")
    if name in BUILTIN_SOURCES:
        raise SourceSpecError(f"{name!r} is a built-in source kind and cannot be replaced")
    _REGISTERED[name] = factory


def source_plugins() -> dict[str, SourcePlugin]:
    """Every source kind: the built-ins, the installed entry points, the registered ones.

    Returns
    -------
    dict of str to SourcePlugin
        Sorted by name. An entry point that reuses a built-in name is ignored
        (logged as a warning).
    """
    found = {
        name: SourcePlugin(name, target, _BUILTIN_ORIGIN)
        for name, target in BUILTIN_SOURCES.items()
    }
    for ep in entry_points(group=ENTRY_POINT_GROUP):
        origin = ep.dist.name if ep.dist is not None else "an unknown distribution"
        if ep.name in BUILTIN_SOURCES:
            if ep.value != BUILTIN_SOURCES[ep.name]:
                logger.warning("ignoring %s's source %r: a built-in kind", origin, ep.name)
            continue
        found[ep.name] = SourcePlugin(ep.name, ep.value, origin)
    for name in _REGISTERED:
        found[name] = SourcePlugin(name, "<registered>", "register_source()")
    return dict(sorted(found.items()))


def resolve_source(
    spec: str, *, shape: tuple[int, int] | None = None, max_taxels: int = DEFAULT_MAX_TAXELS
) -> Callable[[], FrameSource]:
    """Check a SOURCE string now; return a function that opens it.

    Parameters
    ----------
    spec : str
        ``KIND:ADDRESS``.
    shape, max_taxels
        Passed to the factory.

    Returns
    -------
    callable
        ``opener()`` returns the opened :class:`FrameSource`.

    Raises
    ------
    SourceSpecError
        If ``KIND`` is unknown (the message lists the known kinds) or the
        address is empty or, for serial and UDP, malformed.
    LiveSourceError
        If the plugin cannot be loaded.
    """
    plugins = source_plugins()
    kind, sep, address = spec.partition(":") if isinstance(spec, str) else ("", "", "")
    if not sep or kind not in plugins:
        raise SourceSpecError(
            f"SOURCE must be KIND:ADDRESS with KIND one of {', '.join(plugins)} "
            f"(see 'taxelkit sources'), got {spec!r}"
        )
    if not address or address != address.strip():
        raise SourceSpecError(f"SOURCE {spec!r} has an empty or blank address")
    if kind in ("serial", "udp"):
        parse_source(spec)  # the syntax errors of the built-ins, before anything opens
    factory = plugins[kind].load()

    def opener() -> FrameSource:
        source = factory(address, shape=shape, max_taxels=max_taxels)
        if not isinstance(source, FrameSource):
            raise LiveSourceError(
                f"source plugin {kind!r} returned {type(source).__name__}, not a FrameSource"
            )
        return source

    return opener


def open_plugin_source(
    spec: str, *, shape: tuple[int, int] | None = None, max_taxels: int = DEFAULT_MAX_TAXELS
) -> FrameSource:
    """Open a SOURCE string of any kind (see :func:`resolve_source`)."""
    return resolve_source(spec, shape=shape, max_taxels=max_taxels)()
