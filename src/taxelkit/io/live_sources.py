"""Live frame sources (serial port, UDP socket, any file descriptor) and a simulated device.

A source turns what a device sends, in the protocol of
:mod:`taxelkit.io.frame_protocol`, into :class:`~taxelkit.io.frame_protocol.DecodedFrame`
objects. Sources are named on the command line as

``serial:PORT[@BAUD]``
    A serial port read with pyserial (``serial:/dev/ttyUSB0``,
    ``serial:/dev/ttyACM0@921600``, ``serial:COM3@115200``); default
    :data:`DEFAULT_BAUD`. Needs the optional dependency: ``pip install "taxelkit[live]"``.
``udp:HOST:PORT``
    Listen for datagrams on a local address (``udp:0.0.0.0:9000`` on every
    interface, ``udp:127.0.0.1:9000``, ``udp:[::1]:9000``).

:class:`SimulatedDevice` plays a recording into a pseudo-terminal or to a UDP
address from a background thread, optionally damaging a seeded fraction of
the packets, so that the whole chain can be tested without hardware.
"""

from __future__ import annotations

import errno
import os
import select
import time
from abc import ABC, abstractmethod
from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass
from types import TracebackType
from typing import Any, Literal, Self

from taxelkit.errors import InputError, TaxelkitError, check_positive
from taxelkit.io.datagram_batch import FrameBatch, batches_from_frames
from taxelkit.io.frame_protocol import (
    DEFAULT_MAX_TAXELS,
    DecodedFrame,
    DecoderStats,
    FrameDecoder,
)

__all__ = [
    "DEFAULT_BAUD",
    "ByteStreamSource",
    "FrameSource",
    "LiveDependencyError",
    "LiveSourceError",
    "LiveTimeoutError",
    "SourceSpec",
    "SourceSpecError",
    "StreamSource",
    "one_line_message",
    "open_source",
    "parse_source",
]

#: Serial baud rate when ``serial:PORT`` names none: the common 115200 Bd.
DEFAULT_BAUD = 115_200
#: Bytes asked for per read of a byte stream.
_READ_SIZE = 65_536
_SOURCE_SYNTAX = "serial:PORT[@BAUD] or udp:HOST:PORT"


class LiveSourceError(TaxelkitError):
    """A live source cannot be opened or read."""


class SourceSpecError(LiveSourceError, InputError):
    """A SOURCE string does not follow ``serial:PORT[@BAUD]`` or ``udp:HOST:PORT``."""


class LiveDependencyError(LiveSourceError, ImportError):
    """An optional dependency of live sources (pyserial) is not installed."""


class LiveTimeoutError(LiveSourceError, TimeoutError):
    """No frame arrived within the allowed time."""


# ----------------------------------------------------------------------------- specs
@dataclass(frozen=True)
class SourceSpec:
    """A parsed SOURCE string.

    Attributes
    ----------
    kind : {"serial", "udp"}
    address : str
        Serial port name, or the host to listen on.
    port : int
        UDP port (0 for serial).
    baud : int
        Serial baud rate (0 for UDP).
    """

    kind: Literal["serial", "udp"]
    address: str
    port: int = 0
    baud: int = 0

    def __str__(self) -> str:
        if self.kind == "serial":
            return f"serial:{self.address}@{self.baud}"
        host = f"[{self.address}]" if ":" in self.address else self.address
        return f"udp:{host}:{self.port}"


def parse_source(spec: str) -> SourceSpec:
    """Parse ``serial:PORT[@BAUD]`` or ``udp:HOST:PORT``.

    Raises
    ------
    SourceSpecError
        With a one-line message giving the expected syntax and the string received.

    Examples
    --------
    >>> parse_source("serial:/dev/ttyUSB0@921600")
    SourceSpec(kind='serial', address='/dev/ttyUSB0', port=0, baud=921600)
    >>> parse_source("udp:127.0.0.1:9000")
    SourceSpec(kind='udp', address='127.0.0.1', port=9000, baud=0)
    """

    def bad(why: str) -> SourceSpecError:
        return SourceSpecError(f"SOURCE must be {_SOURCE_SYNTAX} ({why}), got {spec!r}")

    if not isinstance(spec, str):
        raise bad("not a string")
    kind, sep, rest = spec.partition(":")
    if not sep or kind.lower() not in ("serial", "udp"):
        raise bad("unknown kind")
    if any(c.isspace() for c in rest) or not rest:
        raise bad("empty or blank address")
    if kind.lower() == "serial":
        port, at, baud_text = rest.rpartition("@")
        if not at:
            return SourceSpec("serial", rest, baud=DEFAULT_BAUD)
        if not port or not baud_text.isdigit() or int(baud_text) < 1:
            raise bad("BAUD must be a positive integer")
        return SourceSpec("serial", port, baud=int(baud_text))
    host, colon, port_text = rest.rpartition(":")
    if host.startswith("[") and host.endswith("]"):
        host = host[1:-1]
    if not colon or not host or not port_text.isdigit() or int(port_text) > 65_535:
        raise bad("PORT must be an integer in 0..65535")
    return SourceSpec("udp", host, port=int(port_text))


def open_source(
    spec: str | SourceSpec,
    *,
    shape: tuple[int, int] | None = None,
    max_taxels: int = DEFAULT_MAX_TAXELS,
) -> FrameSource:
    """Open the source named by a SOURCE string (see the module docstring).

    Parameters
    ----------
    spec : str or SourceSpec
    shape, max_taxels
        Passed to the :class:`~taxelkit.io.frame_protocol.FrameDecoder`.

    Raises
    ------
    SourceSpecError, LiveDependencyError, LiveSourceError
    """
    from taxelkit.io.live_transports import SerialSource, UdpSource  # they build on this module

    s = parse_source(spec) if isinstance(spec, str) else spec
    if s.kind == "serial":
        return SerialSource(s.address, s.baud, shape=shape, max_taxels=max_taxels)
    return UdpSource(s.address, s.port, shape=shape, max_taxels=max_taxels)


# ----------------------------------------------------------------------------- sources
class FrameSource(ABC):
    """Something that yields decoded frames; a context manager that closes it."""

    #: How the source is named in messages, e.g. ``"udp:127.0.0.1:9000"``.
    description: str

    def __init__(self, description: str, decoder: FrameDecoder) -> None:
        self.description = description
        self.decoder = decoder
        self.at_end = False
        self._backlog: deque[DecodedFrame] = deque()  # decoded but not yet yielded

    @abstractmethod
    def poll(self, timeout_s: float) -> list[DecodedFrame]:
        """Wait up to ``timeout_s`` for data; return the frames it completed (maybe none).

        At the end of the stream :attr:`at_end` becomes True and later calls return [].
        """

    @abstractmethod
    def close(self) -> None:
        """Release the port, socket or descriptor (idempotent)."""

    def poll_batches(self, timeout_s: float) -> list[FrameBatch]:
        """:meth:`poll`, the frames grouped into arrays: batches of one shape and payload type.

        Frames left over by :meth:`frames` come first. Sources that can decode
        many packets at once (UDP) override it.
        """
        frames = list(self._backlog)
        self._backlog.clear()
        if not frames or not self.at_end:
            frames.extend(self.poll(0.0 if frames else timeout_s))
        return batches_from_frames(frames)

    @property
    def stats(self) -> DecoderStats:
        """The decoder's counters."""
        return self.decoder.stats

    def frames(
        self, *, max_frames: int | None = None, idle_timeout_s: float | None = None
    ) -> Iterator[DecodedFrame]:
        """Yield frames until ``max_frames``, the end of the stream, or a timeout.

        Frames decoded together with the last one asked for are kept for the
        next call, so consecutive calls see every frame once.

        Parameters
        ----------
        max_frames : int, optional
            Stop after this many frames.
        idle_timeout_s : float, optional
            Longest wait for the next frame, s; None waits for ever.

        Raises
        ------
        LiveTimeoutError
            When no frame arrived for ``idle_timeout_s``; the message gives the
            byte and damage counts, which tell a silent device from a wrong baud rate.
        """
        if max_frames is not None and max_frames < 1:
            return
        idle = None if idle_timeout_s is None else check_positive("idle_timeout_s", idle_timeout_s)
        count = 0
        last = time.monotonic()
        while True:
            if not self._backlog:
                if self.at_end:
                    return
                wait = 0.1 if idle is None else max(0.0, min(0.1, last + idle - time.monotonic()))
                self._backlog.extend(self.poll(wait))
            if not self._backlog:
                if idle is not None and time.monotonic() - last >= idle and not self.at_end:
                    s = self.stats
                    raise LiveTimeoutError(
                        f"no frame from {self.description} for {idle:g} s ({s.bytes_received} "
                        f"bytes received, {s.frames} frames, {s.corrupted} damaged packets)"
                    )
                continue
            while self._backlog:
                yield self._backlog.popleft()
                count += 1
                if max_frames is not None and count >= max_frames:
                    return
            last = time.monotonic()  # the wait starts once the consumer is done

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()


class StreamSource(FrameSource):
    """A source of bytes without packet boundaries: the magic delimits packets.

    Subclasses implement ``_read``; :class:`ByteStreamSource` and
    :class:`~taxelkit.io.live_transports.SerialSource` are two.
    """

    @abstractmethod
    def _read(self, timeout_s: float) -> bytes | None:
        """Bytes that arrived within ``timeout_s`` (maybe b""), or None at the end."""

    def poll(self, timeout_s: float) -> list[DecodedFrame]:
        if self.at_end:
            return []
        data = self._read(timeout_s)
        if data is None:
            self.at_end = True
            return self.decoder.flush()
        return self.decoder.feed(data) if data else []


class ByteStreamSource(StreamSource):
    """Frames from a readable file descriptor: a pipe, a pseudo-terminal, a serial device.

    Parameters
    ----------
    fd : int
        Open descriptor (POSIX: anything :func:`select.select` accepts). A
        terminal must be in raw mode (:func:`open_pseudo_terminal` does it).
    description : str, optional
        Name in messages; default ``"fd:<fd>"``.
    close_fd : bool
        Close ``fd`` in :meth:`close` (default False: the caller owns it).
    shape, max_taxels
        Passed to the :class:`~taxelkit.io.frame_protocol.FrameDecoder`.

    Notes
    -----
    End of file, and ``EIO`` from a terminal whose other end has closed, end
    the stream.
    """

    def __init__(
        self,
        fd: int,
        *,
        description: str | None = None,
        close_fd: bool = False,
        shape: tuple[int, int] | None = None,
        max_taxels: int = DEFAULT_MAX_TAXELS,
    ) -> None:
        super().__init__(
            description or f"fd:{fd}", FrameDecoder(shape=shape, max_taxels=max_taxels)
        )
        self.fd = fd
        self._close_fd = close_fd
        self._closed = False

    def _read(self, timeout_s: float) -> bytes | None:
        try:
            ready, _, _ = select.select([self.fd], [], [], max(0.0, timeout_s))
            if not ready:
                return b""
            data = os.read(self.fd, _READ_SIZE)
        except OSError as e:
            if e.errno == errno.EIO:  # the other end of a terminal has closed
                return None
            raise LiveSourceError(f"cannot read {self.description}: {e.strerror or e}") from e
        return data if data else None

    def close(self) -> None:
        if self._close_fd and not self._closed:
            os.close(self.fd)
        self._closed = True


def one_line_message(exc: BaseException) -> str:
    """An exception's message on one line (its type's name if it has none)."""
    return " ".join(str(exc).split()) or type(exc).__name__


def __getattr__(name: str) -> Any:
    """``SerialSource`` and ``UdpSource``, which moved to :mod:`taxelkit.io.live_transports`."""
    if name in ("SerialSource", "UdpSource"):
        from taxelkit.io import live_transports

        return getattr(live_transports, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
