"""Log the smart sensor to rerun: frames, contact classes, tactemes, candidates, verdicts.

Entity paths (every entry is on the ``frame`` timeline, the frame index, and
the ``time`` timeline, the frame time in s):

=========================== ============================================================
``sensor/frames``           the frame, a ``(rows, cols)`` tensor (mm, or 0/1 contact)
``sensor/contact_class``    the Level 2 contact class of every frame (text)
``sensor/contact``          each contact class accepted after debouncing (``contact`` events)
``sensor/tactemes``         each Level 3 tacteme, at the frame it was seen
``sensor/candidates``       the objects left after each elimination (Level 4)
``sensor/verdicts``         ``identified``, ``unknown`` and ``lifted`` events, and a last
                            ``result:`` line with the final verdict
=========================== ============================================================

:class:`RerunView` logs one frame and its events at a time (for streams);
:func:`view_recognition` logs a whole :class:`~taxelkit.smart.recogniser.Recognition`
of a recording. Open a saved ``.rrd`` with ``rerun FILE.rrd``.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from taxelkit.errors import TaxelkitError
from taxelkit.frames import TactileFrames
from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.elimination import Event
from taxelkit.smart.recogniser import Recognition

__all__ = [
    "ENTITY_PATHS",
    "RerunView",
    "ViewerConnectionError",
    "ViewerDependencyError",
    "check_viewer_available",
    "close_stream",
    "open_stream",
    "view_frames",
    "view_recognition",
]

#: Entity path of each kind of entry.
ENTITY_PATHS = {
    "frames": "sensor/frames",
    "contact_class": "sensor/contact_class",
    "contact": "sensor/contact",
    "tactemes": "sensor/tactemes",
    "candidates": "sensor/candidates",
    "verdicts": "sensor/verdicts",
}
#: Event kinds logged under ``sensor/verdicts``.
VERDICT_KINDS = ("identified", "unknown", "lifted")
_APPLICATION_ID = "taxelkit"
#: Port of the viewer ``spawn`` starts (rerun's default).
VIEWER_PORT = 9876
_INSTALL_HINT = 'pip install "taxelkit[viewer]"'
_EVENT_PATHS = {
    "contact": ENTITY_PATHS["contact"],
    "tacteme": ENTITY_PATHS["tactemes"],
    "candidates": ENTITY_PATHS["candidates"],
    **{kind: ENTITY_PATHS["verdicts"] for kind in VERDICT_KINDS},
}


class ViewerDependencyError(TaxelkitError, ImportError):
    """rerun-sdk, needed for the viewer, is not installed."""


class ViewerConnectionError(TaxelkitError):
    """The rerun viewer to stream to could not be reached."""


def _rerun() -> ModuleType:
    try:
        import rerun
    except ImportError:
        raise ViewerDependencyError(
            f"the viewer needs rerun-sdk, which is not installed: {_INSTALL_HINT}"
        ) from None
    return rerun


def check_viewer_available() -> None:
    """Raise :class:`ViewerDependencyError` (with the install command) if rerun is missing."""
    _rerun()


def event_text(event: Event) -> str:
    """One line for an event: its kind and value.

    Examples
    --------
    >>> event_text(Event("candidates", 12, ("cube", "tetrahedron")))
    'candidates: cube, tetrahedron'
    """
    value = event.value if isinstance(event.value, str) else ", ".join(event.value) or "-"
    return f"{event.kind}: {value}"


def open_stream(
    *,
    save_path: str | os.PathLike[str] | None = None,
    spawn: bool = False,
    connect_url: str | None = None,
    recording_id: str | None = None,
) -> tuple[ModuleType, Any]:
    """A rerun recording stream logging to a file, a viewer, or both.

    Parameters
    ----------
    save_path : str or os.PathLike, optional
        Write the recording to this ``.rrd`` file (the path is written as given).
    spawn : bool, optional
        Start a rerun viewer on this machine (or use the one already listening
        on rerun's default port) and stream to it.
    connect_url : str, optional
        Stream to the viewer at this address instead of spawning one
        (``rerun+http://HOST:PORT/proxy``).
    recording_id : str, optional
        rerun recording id (default: a random one).

    Returns
    -------
    (module, RecordingStream)
        The ``rerun`` module and the stream.

    Raises
    ------
    ViewerDependencyError
        If rerun-sdk is not installed.
    ValueError
        If both ``spawn`` and ``connect_url`` are given.
    """
    if spawn and connect_url is not None:
        raise ValueError("give spawn=True or connect_url, not both")
    rr = _rerun()
    stream: Any = rr.RecordingStream(_APPLICATION_ID, recording_id=recording_id)
    if spawn and save_path is None:
        stream.spawn()
    elif connect_url is not None and save_path is None:
        stream.connect_grpc(connect_url)
    elif spawn or connect_url is not None:  # a file and a viewer at once
        if spawn:
            stream.spawn(port=VIEWER_PORT, connect=False)
        url = connect_url or f"rerun+http://127.0.0.1:{VIEWER_PORT}/proxy"
        stream.set_sinks(rr.FileSink(str(Path(str(save_path)))), rr.GrpcSink(url))
    elif save_path is not None:
        stream.save(str(Path(save_path)))
    return rr, stream


class RerunView:
    """A rerun recording of the smart sensor, saved to a file and/or shown in a viewer.

    Parameters
    ----------
    save_path : str or os.PathLike, optional
        Write the recording to this ``.rrd`` file (the path is written as given).
    spawn : bool, optional
        Also start the rerun viewer (or use a running one) and stream to it.
    connect_url : str, optional
        Stream to the viewer at this address instead (``rerun+http://HOST:PORT/proxy``).
    recording_id : str, optional
        rerun recording id (default: a random one).

    Raises
    ------
    ViewerDependencyError
        If rerun-sdk is not installed.
    """

    def __init__(
        self,
        *,
        save_path: str | os.PathLike[str] | None = None,
        spawn: bool = False,
        connect_url: str | None = None,
        recording_id: str | None = None,
    ) -> None:
        self._rr, self._stream = open_stream(
            save_path=save_path, spawn=spawn, connect_url=connect_url, recording_id=recording_id
        )
        self.frames_logged = 0

    def _at(self, index: int, t_s: float) -> None:
        self._stream.set_time("frame", sequence=int(index))
        self._stream.set_time("time", duration=float(t_s))

    def log_frame(
        self, index: int, t_s: float, frame: ArrayLike, contact_class: int | None = None
    ) -> None:
        """Log one frame and, if given, its Level 2 contact class.

        Parameters
        ----------
        index : int
            Frame index (the ``frame`` timeline).
        t_s : float
            Frame time, s (the ``time`` timeline).
        frame : (rows, cols) bool or float
            Taxel values (mm, or contact).
        contact_class : int, optional
            A :class:`~taxelkit.smart.contact_classes.ContactClass` code.
        """
        self._at(index, t_s)
        values = np.asarray(frame)
        data = values.astype(np.uint8) if values.dtype == bool else values.astype(np.float32)
        self._stream.log(ENTITY_PATHS["frames"], self._rr.Tensor(data))
        if contact_class is not None:
            name = ContactClass(int(contact_class)).name.lower()
            self._stream.log(ENTITY_PATHS["contact_class"], self._rr.TextLog(name))
        self.frames_logged += 1

    def log_events(self, events: Iterable[Event], t_s: float | None = None) -> None:
        """Log events at their own frame index (and at ``t_s`` on the time line, if given)."""
        for event in events:
            path = _EVENT_PATHS.get(event.kind)
            if path is None:
                continue
            self._stream.set_time("frame", sequence=int(event.frame))
            if t_s is not None:
                self._stream.set_time("time", duration=float(t_s))
            self._stream.log(path, self._rr.TextLog(event_text(event)))

    def log_result(self, index: int, t_s: float, result: Recognition) -> None:
        """Log the final verdict as a ``result:`` line under ``sensor/verdicts``."""
        self._at(index, t_s)
        verdict = result.identified or f"undecided among {', '.join(result.candidates)}"
        self._stream.log(ENTITY_PATHS["verdicts"], self._rr.TextLog(f"result: {verdict}"))

    def close(self) -> None:
        """Flush everything to the file or viewer and end the recording.

        Raises
        ------
        ViewerConnectionError
            If the viewer could not be reached.
        """
        close_stream(self._stream)


def close_stream(stream: Any) -> None:
    """Flush a stream from :func:`open_stream` and disconnect it.

    Raises
    ------
    ViewerConnectionError
        If the viewer could not be reached (rerun gives up after a few seconds).
    """
    try:
        stream.flush()
    except RuntimeError as e:  # rerun reports an unreachable gRPC viewer so
        raise ViewerConnectionError(
            f"could not send the log to the rerun viewer ({' '.join(str(e).split())})"
        ) from None
    finally:
        stream.disconnect()


def view_recognition(
    rec: TactileFrames,
    result: Recognition,
    *,
    save_path: str | os.PathLike[str] | None = None,
    spawn: bool = False,
    connect_url: str | None = None,
) -> int:
    """Log a recording and what the smart sensor made of it to an ``.rrd`` file or a viewer.

    Parameters
    ----------
    rec : TactileFrames
        The recording, ``(T, rows, cols)``.
    result : Recognition
        :func:`~taxelkit.smart.recogniser.recognise` of ``rec``.
    save_path : str or os.PathLike, optional
        The ``.rrd`` file to write.
    spawn : bool, optional
        Also show it in a rerun viewer on this machine.
    connect_url : str, optional
        Also stream it to the viewer at this address.

    Returns
    -------
    int
        Number of entries under ``sensor/verdicts`` (every verdict event and the result line).

    Raises
    ------
    ViewerDependencyError
        If rerun-sdk is not installed.
    """
    view = RerunView(save_path=save_path, spawn=spawn, connect_url=connect_url)
    by_frame: dict[int, list[Event]] = {}
    for event in result.events:
        by_frame.setdefault(int(event.frame), []).append(event)
    for k in range(rec.n_frames):
        t = float(rec.t_s[k])
        view.log_frame(k, t, rec.frames[k], int(result.classes[k]))
        view.log_events(by_frame.pop(k, ()), t)
    for events in by_frame.values():  # events after the last frame, if any
        view.log_events(events, float(rec.t_s[-1]))
    last = rec.n_frames - 1
    view.log_result(last, float(rec.t_s[last]), result)
    view.close()
    return 1 + sum(e.kind in VERDICT_KINDS for e in result.events)


def view_frames(
    rec: TactileFrames,
    *,
    start: int = 0,
    stop: int | None = None,
    save_path: str | os.PathLike[str] | None = None,
    spawn: bool = False,
    connect_url: str | None = None,
) -> int:
    """Log the frames ``start:stop`` of a recording under ``sensor/frames``.

    Parameters
    ----------
    rec : TactileFrames
        The recording, ``(T, rows, cols)``.
    start, stop : int
        Frames to log (default: all).
    save_path : str or os.PathLike, optional
        The ``.rrd`` file to write.
    spawn : bool, optional
        Show them in a rerun viewer on this machine.
    connect_url : str, optional
        Stream them to the viewer at this address.

    Returns
    -------
    int
        Number of frames logged.
    """
    view = RerunView(save_path=save_path, spawn=spawn, connect_url=connect_url)
    for k in range(start, rec.n_frames if stop is None else stop):
        view.log_frame(k, float(rec.t_s[k]), rec.frames[k])
    view.close()
    return view.frames_logged
