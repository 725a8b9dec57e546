"""``taxelkit recognize --live SOURCE``: the smart sensor on frames from a device, as they come.

SOURCE is ``serial:PORT[@BAUD]`` (pyserial; ``serial:/dev/ttyUSB0``,
``serial:COM3@921600``; default 115200 Bd) or ``udp:HOST:PORT`` (listen on a
local address, e.g. ``udp:0.0.0.0:9000``). The device must send the packets
of ``docs/live-protocol.md``. One line is printed per event; damaged packets
are skipped and counted in the closing summary line.
"""

from __future__ import annotations

import logging
import math
from array import array
from collections.abc import Callable
from pathlib import Path
from typing import Any

from taxelkit.cli.view import ViewTarget, with_view
from taxelkit.errors import InputError, check_positive
from taxelkit.io.frame_protocol import DecodedFrame, PayloadType
from taxelkit.io.live_sources import LiveTimeoutError
from taxelkit.io.source_plugins import resolve_source
from taxelkit.smart.elimination import Event
from taxelkit.smart.recogniser import SmartSensor

__all__ = ["EXIT_INTERRUPTED", "EXIT_OK", "format_event", "recognize_live"]

#: Exit code after ``max_frames`` frames, the end of the stream, or a quiet device.
EXIT_OK = 0
#: Exit code after Ctrl-C (128 + SIGINT), once the summary has been printed.
EXIT_INTERRUPTED = 130

logger = logging.getLogger(__name__)


def format_event(event: Event, index: int, t_s: float) -> str:
    """One line for an event: sender's time and frame index, kind, value.

    Examples
    --------
    >>> format_event(Event("contact", 3, "point"), 103, 0.103)
    '     0.103 s  frame 103  contact point'
    """
    value = event.value if isinstance(event.value, str) else ",".join(event.value) or "-"
    return f"{t_s:10.3f} s  frame {index}  {event.kind} {value}"


class _LiveRun:
    """The state of one live recognition: the sensor, once the first frame gives its shape."""

    def __init__(self, pitch_mm: float, threshold: float | None, view: Any = None) -> None:
        self.view = view  # a taxelkit.viewer.RerunView, or None
        self.pitch_mm = pitch_mm
        self.threshold = threshold
        self.sensor: SmartSensor | None = None
        self.wire_index = array("q")  # sender's index and time of each processed frame
        self.wire_t_s = array("d")
        self.wrong_shape = 0

    def push(self, frame: DecodedFrame) -> list[str]:
        """Process one frame; the lines of the events it caused."""
        if self.sensor is None:
            if frame.payload_type == PayloadType.UINT16 and self.threshold is None:
                raise InputError(
                    "the device sends raw uint16 counts: give a contact threshold in counts"
                )
            if self.threshold is None:
                self.sensor = SmartSensor(frame.shape, pitch_mm=self.pitch_mm)
            else:
                self.sensor = SmartSensor(
                    frame.shape, pitch_mm=self.pitch_mm, threshold=self.threshold
                )
        elif frame.shape != self.sensor.shape:
            self.wrong_shape += 1
            logger.warning("skipped a %s frame (the stream is %s)", frame.shape, self.sensor.shape)
            return []
        self.wire_index.append(frame.index)
        self.wire_t_s.append(frame.t_s)
        events = self.sensor.push(frame.values, frame.t_s)
        if self.view is not None:
            j = self.sensor.frame_index - 1
            self.view.log_frame(j, frame.t_s, frame.values, self.sensor.classes[-1])
            self.view.log_events(events, frame.t_s)
        return [format_event(e, self.wire_index[e.frame], self.wire_t_s[e.frame]) for e in events]

    def summary(self, source_stats: str, why: str) -> str:
        """The closing line."""
        n = 0 if self.sensor is None else self.sensor.frame_index
        outcome = "no frames"
        if self.sensor is not None:
            result = self.sensor.result()
            if result.identified is not None:
                outcome = f"identified {result.identified}"
            else:
                outcome = f"candidates {','.join(result.candidates) or '-'}"
        shape = f", {self.wrong_shape} of another shape" if self.wrong_shape else ""
        return f"{why}: {n} frames processed{shape}, {source_stats}; {outcome}"


def recognize_live(
    source: str,
    *,
    pitch_mm: float | None,
    threshold: float | None = None,
    max_frames: int | None = None,
    timeout_s: float | None = 5.0,
    echo: Callable[[str], None],
    save_view: Path | None = None,
    force: bool = False,
    spawn_view: bool = False,
    view_url: str | None = None,
) -> int:
    """Run the streaming smart sensor on a live source, printing one line per event.

    Parameters
    ----------
    source : str
        ``serial:PORT[@BAUD]``, ``udp:HOST:PORT``, ``file:PATH``, or ``KIND:ADDRESS``
        of a source plugin (:mod:`taxelkit.io.source_plugins`, ``taxelkit sources``).
    pitch_mm : float
        Taxel pitch of the device, mm. Required (None is refused): packets do
        not carry it, and Level 2 classifies contacts by their area in mm².
    threshold : float, optional
        Contact threshold in the frames' units (mm for float32 frames, counts
        for uint16 frames, where it is required); default the smart sensor's
        0.03 mm. Ignored for bool frames.
    max_frames : int, optional
        Stop after this many frames; None runs until the stream ends, the
        device goes quiet, or Ctrl-C.
    timeout_s : float or None
        Longest wait for a frame, s. Before the first frame a timeout is an
        error; after it, the device is taken to have finished. None waits for ever.
    echo : callable
        Receives each output line (events, then one summary line).
    save_view : pathlib.Path, optional
        Also log every frame, contact class and event to this rerun ``.rrd``
        file (:mod:`taxelkit.viewer`, the viewer extra), written atomically.
    force : bool, optional
        Replace an existing ``save_view`` file.
    spawn_view : bool, optional
        Also show the run in a rerun viewer on this machine, as it happens.
    view_url : str, optional
        Also stream the run to the rerun viewer at this address.

    Returns
    -------
    int
        :data:`EXIT_OK`, or :data:`EXIT_INTERRUPTED` after Ctrl-C.

    Raises
    ------
    SourceSpecError
        If SOURCE is malformed.
    LiveDependencyError
        If a serial source is asked for without pyserial.
    LiveSourceError
        If the source cannot be opened or read.
    LiveTimeoutError
        If no frame arrives within ``timeout_s`` of starting.
    InputError
        On a bad ``pitch_mm``, ``threshold``, ``max_frames`` or ``timeout_s``, or uint16
        frames without a threshold.
    """
    opener = resolve_source(source)  # any kind of 'taxelkit sources', checked before opening
    if pitch_mm is None:
        raise InputError("--pitch-mm is required with --live: the stream does not carry the pitch")
    pitch = check_positive("pitch_mm", pitch_mm)
    if max_frames is not None and max_frames < 1:
        raise InputError(f"max_frames must be >= 1, got {max_frames!r}")
    idle = None if timeout_s is None else check_positive("timeout_s", timeout_s)
    if threshold is not None and not math.isfinite(threshold):
        raise InputError(f"threshold must be a finite number, got {threshold!r}")
    target = ViewTarget(spawn_view, view_url, save_view)
    if not target.wanted:
        return _run_live(opener, _LiveRun(pitch, threshold), max_frames, idle, echo)
    from taxelkit.viewer.rerun_view import RerunView

    def session(where: ViewTarget) -> int:
        view = RerunView(save_path=where.save_path, spawn=where.spawn, connect_url=where.url)
        run = _LiveRun(pitch, threshold, view)
        try:
            return _run_live(opener, run, max_frames, idle, echo)
        finally:
            if run.sensor is not None and run.sensor.frame_index:
                last = run.sensor.frame_index - 1
                view.log_result(last, float(run.wire_t_s[last]), run.sensor.result())
            view.close()

    return with_view(target, session, force=force)


def _run_live(
    opener: Callable[[], Any],
    run: _LiveRun,
    max_frames: int | None,
    idle: float | None,
    echo: Callable[[str], None],
) -> int:
    """The receive loop: frames to the sensor, lines to ``echo``, then the summary."""
    with opener() as src:
        why, code, received = "end of stream", EXIT_OK, 0
        try:
            for frame in src.frames(max_frames=max_frames, idle_timeout_s=idle):
                received += 1
                for line in run.push(frame):
                    echo(line)
            if received == max_frames:
                why = f"stopped after {max_frames} frames"
        except LiveTimeoutError:
            if run.sensor is None:
                raise
            why = f"no frame for {idle:g} s"
        except KeyboardInterrupt:
            why, code = "interrupted", EXIT_INTERRUPTED
        s = src.stats
        counts = (
            f"damaged packets skipped: {s.corrupted}, frame indices missing: {s.missing}, "
            f"bytes skipped: {s.bytes_skipped}"
        )
        echo(run.summary(counts, why))
    return code
