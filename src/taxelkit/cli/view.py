"""``--view``, ``--view-url`` and ``--save-view``: where a command's rerun log goes.

The commands that log to rerun (``recognize``, ``show``, ``trace``) share these
options through :func:`view_options`, which hands the command one
:class:`ViewTarget`. :func:`with_view` runs the command's logging with a
recording stream open on that target; an ``.rrd`` file is written through a
temporary file, so a failed run leaves no partial file.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import click

from taxelkit.errors import InputError

__all__ = ["ViewTarget", "view_options", "with_view"]

F = TypeVar("F", bound=Callable[..., Any])
T = TypeVar("T")

_INSTALL = 'needs the viewer extra: pip install "taxelkit[viewer]"'


@dataclass(frozen=True)
class ViewTarget:
    """Where the rerun log goes.

    Attributes
    ----------
    spawn : bool
        Show it in a rerun viewer on this machine (``--view``).
    url : str or None
        Stream it to the viewer at this address (``--view-url``).
    save_path : pathlib.Path or None
        Write it to this ``.rrd`` file (``--save-view``).
    """

    spawn: bool = False
    url: str | None = None
    save_path: Path | None = None

    @property
    def wanted(self) -> bool:
        """Whether any log was asked for."""
        return self.spawn or self.url is not None or self.save_path is not None

    def check(self) -> None:
        """Check the options before any work: rerun installed, an ``.rrd`` suffix.

        Raises
        ------
        ViewerDependencyError
            If rerun-sdk is not installed (the message gives the install command).
        InputError
            If ``--view`` and ``--view-url`` are both given, or ``--save-view``
            does not end in ``.rrd``.
        """
        if not self.wanted:
            return
        from taxelkit.viewer.rerun_view import check_viewer_available

        check_viewer_available()
        if self.spawn and self.url is not None:
            raise InputError("give --view (a viewer here) or --view-url URL, not both")
        if self.save_path is not None and self.save_path.suffix.lower() != ".rrd":
            raise InputError(f"--save-view must end in .rrd, got {self.save_path.name!r}")


def view_options(f: F) -> F:
    """Add ``--view``, ``--view-url`` and ``--save-view``; the command receives ``view``."""

    @click.option(
        "--view",
        "view_spawn",
        is_flag=True,
        help="Show the run in a rerun viewer as it happens (starts one, or uses the one "
        f"already running; {_INSTALL}).",
    )
    @click.option(
        "--view-url",
        default=None,
        metavar="URL",
        help="Stream the run to the rerun viewer at URL instead (rerun+http://HOST:9876/proxy).",
    )
    @click.option(
        "--save-view",
        type=click.Path(path_type=Path),
        default=None,
        help=f"Also save the rerun log to this .rrd file ({_INSTALL}).",
    )
    @functools.wraps(f)
    def command(
        *args: Any, view_spawn: bool, view_url: str | None, save_view: Path | None, **kwargs: Any
    ) -> Any:
        view = ViewTarget(view_spawn, view_url, save_view)
        view.check()
        return f(*args, view=view, **kwargs)

    return command  # type: ignore[return-value]


def with_view(target: ViewTarget, log: Callable[[ViewTarget], T], *, force: bool) -> T:
    """Run ``log(target)``, with a ``--save-view`` file written atomically.

    Parameters
    ----------
    target : ViewTarget
        Where the log goes.
    log : callable
        Logs to rerun (:mod:`taxelkit.viewer`), given a target whose
        ``save_path`` is the temporary file to write.
    force : bool
        Replace an existing ``--save-view`` file.

    Returns
    -------
    Whatever ``log`` returns.
    """
    if target.save_path is None:
        return log(target)
    from taxelkit.io.atomic import atomic_write

    out: list[T] = []

    def writer(tmp: Path) -> None:
        out.append(log(ViewTarget(target.spawn, target.url, tmp)))

    atomic_write(target.save_path, writer, force=force)
    return out[0]
