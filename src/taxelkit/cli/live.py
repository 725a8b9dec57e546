"""``taxelkit recognize --live SOURCE``: the smart sensor on frames from a device, as they come.

SOURCE is ``serial:PORT[@BAUD]`` (pyserial; ``serial:/dev/ttyUSB0``,
``serial:COM3@921600``; default 115200 Bd) or ``udp:HOST:PORT`` (listen on a
local address, e.g. ``udp:0.0.0.0:9000``). The device must send the packets
of ``docs/live-protocol.md``. One line is printed per event; damaged packets
are skipped and counted in the closing summary line.

Every read takes all the frames that have arrived (a UDP source decodes its
datagrams together) and hands them to the smart sensor as one batch
(:class:`~taxelkit.smart.recognise_chunks.ChunkRecogniser` in streaming mode:
Levels 1-2 vectorised over the batch, events as they happen), so the cost per
frame falls as the rate rises. Frames whose time does not increase (a sender
that restarted) are skipped and counted. SIGINT (Ctrl-C) and SIGTERM end the
run within one read (at most 0.1 s), also while it waits for data: the summary is
printed, ``--record`` and ``--save-view`` files are closed complete, and the
exit code is 130 or 143. Memory does not grow with the run: the sender's
frame indices and times are kept for the last :data:`WIRE_HISTORY_FRAMES`
frames, the per-frame classes for the last batch.

With ``--arrays N`` the stream carries N arrays (version 2 packets, an array
id per frame): :class:`~taxelkit.cli.live_bank.BankRun` recognises each in a
sensor bank; events and the summary name the array.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from taxelkit.cli.live_loop import EXIT_INTERRUPTED, EXIT_OK, EXIT_TERMINATED, run_live
from taxelkit.cli.live_record import Recorder
from taxelkit.cli.view import ViewTarget, with_view
from taxelkit.errors import InputError, check_positive
from taxelkit.io.datagram_batch import FrameBatch
from taxelkit.io.frame_protocol import MAX_ARRAY_ID, PayloadType
from taxelkit.io.source_plugins import resolve_source
from taxelkit.smart.elimination import Event
from taxelkit.smart.recognise_chunks import ChunkRecogniser

__all__ = [
    "EXIT_INTERRUPTED",
    "EXIT_OK",
    "EXIT_TERMINATED",
    "WIRE_HISTORY_FRAMES",
    "format_event",
    "recognize_live",
]

#: Frames whose sender index and time are kept to print events (1 MiB): an event
#: about an older frame prints index -1 and time nan.
WIRE_HISTORY_FRAMES = 2**16

logger = logging.getLogger(__name__)

if TYPE_CHECKING:
    pass


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

    def __init__(
        self, pitch_mm: float, threshold: float | None, view: Any = None, recorder: Any = None
    ) -> None:
        self.view = view  # a taxelkit.viewer.RerunView, or None
        self.recorder: Recorder | None = recorder
        self.pitch_mm = pitch_mm
        self.threshold = threshold
        self.sensor: ChunkRecogniser | None = None
        self.frames = 0
        self.t_last = -math.inf
        self.out_of_order = 0  # frames whose time did not increase (a sender restart)
        self.wire_index = np.full(WIRE_HISTORY_FRAMES, -1, np.int64)  # a ring, by frame
        self.wire_t_s = np.full(WIRE_HISTORY_FRAMES, np.nan)
        self.wrong_shape = 0
        self.other_array = 0  # frames of array ids other than 0 (a bank: use --arrays)

    def push(self, batch: FrameBatch) -> list[str]:
        """Process a batch of frames; the lines of the events it caused."""
        if batch.array_id is not None and batch.array_id.any():
            mine = batch.array_id == 0
            self.other_array += int(np.count_nonzero(~mine))
            batch = batch.take(mine)
            if batch.n_frames == 0:
                return []
        if self.sensor is None:
            if batch.payload_type == PayloadType.UINT16 and self.threshold is None:
                raise InputError(
                    "the device sends raw uint16 counts: give a contact threshold in counts"
                )
            self.sensor = ChunkRecogniser(
                batch.shape, pitch_mm=self.pitch_mm, threshold=self.threshold, streaming=True
            )
        elif batch.shape != self.sensor.shape:
            self.wrong_shape += batch.n_frames
            logger.warning("skipped %d %s frames (the stream is %s)", batch.n_frames,
                           batch.shape, self.sensor.shape)  # fmt: skip
            return []
        batch = self._in_time_order(batch)
        if batch.n_frames == 0:
            return []
        if self.recorder is not None:
            self.recorder.append(batch)
        first, n = self.frames, batch.n_frames
        slots = np.arange(first, first + n) % WIRE_HISTORY_FRAMES
        self.wire_index[slots] = batch.index
        self.wire_t_s[slots] = batch.t_s
        self.frames += n
        events = self.sensor.push(batch.values, batch.t_s)
        if self.view is not None:
            classes = self.sensor.last_classes
            for j, (t, values, c) in enumerate(zip(batch.t_s, batch.values, classes, strict=True)):
                self.view.log_frame(first + j, float(t), values, int(c))
            for e in events:
                self.view.log_events([e], self._wire(e.frame)[1])
        return [format_event(e, *self._wire(e.frame)) for e in events]

    def _in_time_order(self, batch: FrameBatch) -> FrameBatch:
        """The frames whose time is after every earlier one (the rest are counted)."""
        t = batch.t_s
        keep = t > np.maximum.accumulate(np.concatenate([[self.t_last], t[:-1]]))
        if keep.all():
            self.t_last = float(t[-1])
            return batch
        self.out_of_order += int(np.count_nonzero(~keep))
        if keep.any():
            self.t_last = float(t[keep][-1])
        return batch.take(keep)

    def _wire(self, frame: int) -> tuple[int, float]:
        """The sender's index and time of a processed frame (-1, nan if forgotten)."""
        if frame < self.frames - WIRE_HISTORY_FRAMES:
            return -1, math.nan
        slot = frame % WIRE_HISTORY_FRAMES
        return int(self.wire_index[slot]), float(self.wire_t_s[slot])

    def finish(self) -> list[str]:
        """The stream has ended: nothing is held back (every batch is processed at once)."""
        return []

    def summary(self, source_stats: str, why: str) -> str:
        """The closing line."""
        outcome = "no frames"
        if self.sensor is not None:
            result = self.sensor.result()
            if result.identified is not None:
                outcome = f"identified {result.identified}"
            else:
                outcome = f"candidates {','.join(result.candidates) or '-'}"
        shape = f", {self.wrong_shape} of another shape" if self.wrong_shape else ""
        if self.other_array:
            shape += f", {self.other_array} of array ids > 0 (use --arrays)"
        if self.out_of_order:
            shape += f", {self.out_of_order} out of time order"
        return f"{why}: {self.frames} frames processed{shape}, {source_stats}; {outcome}"


def recognize_live(
    source: str,
    *,
    pitch_mm: float | None,
    threshold: float | None = None,
    max_frames: int | None = None,
    timeout_s: float | None = 5.0,
    echo: Callable[[str], None],
    save_view: Path | None = None,
    record: Path | None = None,
    force: bool = False,
    spawn_view: bool = False,
    view_url: str | None = None,
    arrays: int = 1,
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
        device goes quiet, SIGINT (Ctrl-C) or SIGTERM.
    timeout_s : float or None
        Longest wait for a frame, s. Before the first frame a timeout is an
        error; after it, the device is taken to have finished. None waits for ever.
    echo : callable
        Receives each output line (events, then one summary line).
    save_view : pathlib.Path, optional
        Also log every frame, contact class and event to this rerun ``.rrd``
        file (:mod:`taxelkit.viewer`, the viewer extra), written atomically.
    record : pathlib.Path, optional
        Also append the received frames to this ``.h5`` recording
        (:class:`~taxelkit.io.chunked_write.RecordingAppender`), flushed every
        :data:`RECORD_CHUNK_FRAMES` frames: a crash loses at most that many.
    force : bool, optional
        Replace existing ``save_view`` and ``record`` files.
    spawn_view : bool, optional
        Also show the run in a rerun viewer on this machine, as it happens.
    view_url : str, optional
        Also stream the run to the rerun viewer at this address.
    arrays : int, optional
        Arrays carried by the stream (version 2 packets name theirs): above
        1, a :class:`~taxelkit.cli.live_bank.BankRun` recognises each array
        in a :class:`~taxelkit.smart.bank.SensorBank` and events name their
        array. Not with ``record`` or a view. With 1 (default), frames of
        other arrays are skipped and counted.

    Returns
    -------
    int
        :data:`EXIT_OK`, :data:`EXIT_INTERRUPTED` after SIGINT (Ctrl-C), or
        :data:`EXIT_TERMINATED` after SIGTERM.

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
        On a bad ``pitch_mm``, ``threshold``, ``max_frames``, ``timeout_s``,
        ``arrays`` or ``record`` name, or uint16 frames without a threshold.
    OutputExistsError
        If ``record`` exists and ``force`` is false.
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
    if arrays != 1:
        if not 1 <= arrays <= MAX_ARRAY_ID + 1:
            raise InputError(f"arrays must be in [1, {MAX_ARRAY_ID + 1}], got {arrays!r}")
        if record is not None or target.wanted:
            raise InputError("--record and the viewer take one array; not with --arrays")
        from taxelkit.cli.live_bank import BankRun, background

        bank = BankRun(arrays, pitch, threshold)
        return run_live(lambda: background(opener()), bank, max_frames, idle, echo)
    recorder = None
    if record is not None:
        if record.suffix.lower() not in (".h5", ".hdf5"):
            raise InputError(f"--record must end in .h5 or .hdf5, got {record.name!r}")
        if record.exists() and not force:
            from taxelkit.errors import OutputExistsError

            raise OutputExistsError(f"{record}: exists; pass --force to replace it")
        recorder = Recorder(record, pitch, force)
    if not target.wanted:
        return run_live(opener, _LiveRun(pitch, threshold, None, recorder), max_frames, idle, echo)
    from taxelkit.viewer.rerun_view import RerunView

    def session(where: ViewTarget) -> int:
        view = RerunView(save_path=where.save_path, spawn=where.spawn, connect_url=where.url)
        run = _LiveRun(pitch, threshold, view, recorder)
        try:
            return run_live(opener, run, max_frames, idle, echo)
        finally:
            if run.sensor is not None and run.frames:
                from taxelkit.smart.recogniser import Recognition

                last, r = run.frames - 1, run.sensor.result()
                verdict = Recognition(
                    np.empty(0, np.int8), r.tactemes, r.events, r.identified, r.candidates,
                    r.verdict,
                )  # fmt: skip
                view.log_result(last, run._wire(last)[1], verdict)
            view.close()

    return with_view(target, session, force=force)
