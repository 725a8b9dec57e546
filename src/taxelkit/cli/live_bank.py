"""``taxelkit recognize --live SOURCE --arrays N``: a bank of arrays on one stream.

A skin or a hand sends the frames of many arrays on one stream, each frame
tagged with its array (version 2 packets, ``TXK2``, of ``docs/live-protocol.md``).
:class:`BankRun` sorts every received batch by array, queues each array's
frames (in its own time order) and, once every array has
:data:`BANK_MIN_PUSH_FRAMES` frames waiting (or the stream ends),
hands the common part to a :class:`~taxelkit.smart.bank.SensorBank`
(``push_many``: Levels 1-2 vectorised over the arrays and frames, Levels 3-4
per array), so each array is recognised as a smart sensor of its own would
recognise it. Events name their array.

The bank advances all arrays together, so a silent array holds the others
back: an array more than :data:`BANK_LAG_FRAMES` frames ahead of the slowest
drops its oldest frames (counted in the summary), which bounds the memory.
A frame lost on the way (a datagram dropped by the network or the receive
buffer) would leave its array one frame behind the others for the rest of
the run: a gap of at most :data:`BANK_FILL_FRAMES` in an array's sender
indices is filled with its last frame repeated (the usual hold of a sensor
read-out that missed a scan), timestamps interpolated, and counted in the
summary as repeated for missing frames.
At the end the frames every array has are processed; those some arrays
have and others lack are reported as waiting, not processed. A UDP source
is read in the background (:func:`background`, a receiver process where
processes can be forked), so that datagrams keep being received while the
bank works on a batch.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from taxelkit.cli.live import format_event
from taxelkit.errors import InputError
from taxelkit.io.datagram_batch import FrameBatch
from taxelkit.io.frame_protocol import PayloadType
from taxelkit.io.live_sources import FrameSource
from taxelkit.io.live_transports import UdpSource
from taxelkit.io.udp_receiver import BackgroundReceiver
from taxelkit.smart.bank import SensorBank
from taxelkit.smart.levels12 import DEFAULT_THRESHOLD_MM

__all__ = [
    "BANK_EVENTS_KEPT",
    "BANK_FILL_FRAMES",
    "BANK_LAG_FRAMES",
    "BANK_MIN_PUSH_FRAMES",
    "BANK_WIRE_FRAMES",
    "BankRun",
    "background",
]

#: Frames an array may run ahead of the slowest before its oldest are dropped
#: (2.1 s at 240 frames/s; 26 MB of queued 16 x 16 bool frames for 200 arrays).
BANK_LAG_FRAMES = 512
#: Frames per array whose sender index and time are kept to print events.
BANK_WIRE_FRAMES = 2048
#: Frames every array must have queued before the bank runs (533 ms at 240
#: frames/s): a push's fixed cost (Levels 3-4 of each touched array) is spread
#: over this many frames rather than the two or three of one read.
BANK_MIN_PUSH_FRAMES = 128
#: Events each array keeps (beyond its last contact's) once printed: the
#: verdict needs only the last contact. Measured with 200 arrays of rolls, 700
#: pushes of 128 frames (6.2 min at 240 frames/s): resident memory still grew
#: about 3 MB a minute at the end with 1,024 kept, and was flat from the fourth
#: minute with 64.
BANK_EVENTS_KEPT = 64
#: Longest gap in an array's sender indices filled by repeating its last frame
#: (0.27 s at 240 frames/s); a longer gap (a sender restarted, an array that was
#: silent) is left as it is.
BANK_FILL_FRAMES = 64


def background(source: FrameSource) -> FrameSource:
    """A UDP source read in the background (a BackgroundReceiver); others as given."""
    return BackgroundReceiver(source) if isinstance(source, UdpSource) else source


class BankRun:
    """The state of a live recognition of ``n_arrays`` arrays carried on one stream.

    Parameters
    ----------
    n_arrays : int
        Arrays of the bank; frames of array ids ``>= n_arrays`` are skipped and counted.
    pitch_mm : float
        Taxel pitch of every array, mm.
    threshold : float or None
        Contact threshold in the frames' units (required for uint16 counts).
    """

    def __init__(self, n_arrays: int, pitch_mm: float, threshold: float | None) -> None:
        self.n = int(n_arrays)
        self.pitch_mm = float(pitch_mm)
        self.threshold = threshold
        self.recorder = None  # a bank run is not recorded (one array per recording)
        self.sensor: SensorBank | None = None
        self.frames = 0  # processed, all arrays together
        self.wrong_shape = 0
        self.other_array = 0
        self.out_of_order = 0
        self.dropped = 0
        self.filled = 0  # frames repeated for missing ones
        self._last: list[tuple[NDArray[np.generic], int, float] | None] = [None] * self.n
        self._per_array = 0  # frames processed per array (the bank keeps them in step)
        self._t_last = np.full(self.n, -math.inf)
        self._queue: list[list[tuple[NDArray[np.generic], ...]]] = [[] for _ in range(self.n)]
        self._queued = np.zeros(self.n, np.int64)
        self._wire_index = np.full((self.n, BANK_WIRE_FRAMES), -1, np.int64)
        self._wire_t_s = np.full((self.n, BANK_WIRE_FRAMES), np.nan)

    def push(self, batch: FrameBatch) -> list[str]:
        """Queue a batch's frames by array and process what every array has; the event lines."""
        if self.sensor is None:
            if batch.payload_type == PayloadType.UINT16 and self.threshold is None:
                raise InputError(
                    "the device sends raw uint16 counts: give a contact threshold in counts"
                )
            thr = DEFAULT_THRESHOLD_MM if self.threshold is None else self.threshold
            self.sensor = SensorBank(self.n, batch.shape, pitch_mm=self.pitch_mm, threshold=thr)
        elif batch.shape != self.sensor.shape:
            self.wrong_shape += batch.n_frames
            return []
        ids = batch.array_ids
        known = ids < self.n
        self.other_array += int(np.count_nonzero(~known))
        pos = np.flatnonzero(known)
        order = pos[np.argsort(ids[pos], kind="stable")]  # by array, in arrival order
        if order.size:
            arrays, starts = np.unique(ids[order], return_index=True)
            for k, group in zip(arrays.tolist(), np.split(order, starts[1:]), strict=True):
                self._enqueue(k, batch, group)
        lines = self._advance()
        self._bound_lag()
        return lines

    def _enqueue(self, k: int, batch: FrameBatch, group: NDArray[np.intp]) -> None:
        """Queue the frames ``group`` of ``batch`` for array ``k`` (those later than its last)."""
        t = batch.t_s[group]
        keep = t > np.maximum.accumulate(np.concatenate([[self._t_last[k]], t[:-1]]))
        self.out_of_order += int(np.count_nonzero(~keep))
        if not keep.any():
            return
        sel = group[keep]
        self._t_last[k] = float(batch.t_s[sel[-1]])
        values, t_s, index = self._fill(k, batch.values[sel], batch.t_s[sel], batch.index[sel])
        self._last[k] = (values[-1], int(index[-1]), float(t_s[-1]))
        self._queue[k].append((values, t_s, index))
        self._queued[k] += index.size

    def _fill(
        self,
        k: int,
        values: NDArray[np.generic],
        t_s: NDArray[np.float64],
        index: NDArray[np.int64],
    ) -> tuple[NDArray[np.generic], NDArray[np.float64], NDArray[np.int64]]:
        """Array ``k``'s frames with the gaps of its sender indices filled (repeats)."""
        last = self._last[k]
        if last is None:  # the array's first frames: no gap before the first
            last = (values[0], int(index[0]) - 1, float(t_s[0]))
        before = np.concatenate([[last[1]], index[:-1]])
        gap = index - before - 1
        fill = (gap > 0) & (gap <= BANK_FILL_FRAMES)
        if not fill.any():
            return values, t_s, index
        reps = np.where(fill, gap, 0) + 1  # each frame, preceded by its gap's repeats
        n = int(reps.sum())
        pos = np.cumsum(reps) - 1  # where each received frame lands
        src = np.repeat(np.arange(index.size), reps)  # the received frame each slot waits for
        held = np.zeros(n, bool)
        held[pos] = True
        prev = np.maximum.accumulate(np.where(held, np.arange(n), -1))  # last received slot
        out_v = np.empty((n, *values.shape[1:]), values.dtype)
        out_v[pos] = values
        first = prev < 0  # repeats of the frame before this batch
        out_v[first] = last[0]
        out_v[~held & ~first] = out_v[prev[~held & ~first]]
        step = np.arange(n) - np.concatenate([[-1], pos])[src]  # 1.. within each gap
        t_prev = np.concatenate([[last[2]], t_s[:-1]])[src]
        i_prev = before[src]
        frac = step / reps[src]
        out_t = np.where(held, t_s[src], t_prev + frac * (t_s[src] - t_prev))
        out_i = np.where(held, index[src], i_prev + step)
        self.filled += n - index.size
        return out_v, out_t, out_i.astype(np.int64)

    def _take(self, k: int, m: int) -> tuple[NDArray[np.generic], ...]:
        """The oldest ``m`` queued frames of array ``k`` (values, times, indices), dequeued."""
        chunks = self._queue[k]
        joined = tuple(np.concatenate(parts) for parts in zip(*chunks, strict=True))
        rest = tuple(a[m:] for a in joined)
        self._queue[k] = [rest] if rest[0].shape[0] else []
        self._queued[k] -= m
        return tuple(a[:m] for a in joined)

    def finish(self) -> list[str]:
        """The stream has ended: process the frames every array has queued; the event lines."""
        return self._advance(BANK_MIN_PUSH_FRAMES)

    def _advance(self, ahead: int = 0) -> list[str]:
        t_n = int(self._queued.min())
        if t_n == 0 or t_n + ahead < BANK_MIN_PUSH_FRAMES or self.sensor is None:
            return []
        taken = [self._take(k, t_n) for k in range(self.n)]
        frames = np.stack([v for v, _, _ in taken])
        t_s = np.stack([t for _, t, _ in taken]).astype(np.float64)
        slots = (self._per_array + np.arange(t_n)) % BANK_WIRE_FRAMES
        self._wire_index[:, slots] = np.stack([i for _, _, i in taken])
        self._wire_t_s[:, slots] = t_s
        events = self.sensor.push_many(frames, t_s)
        self.sensor.forget_history(events_kept=BANK_EVENTS_KEPT)
        self._per_array += t_n
        self.frames += self.n * t_n
        return [f"array {k}: {format_event(e, *self._wire(k, e.frame))}" for k, e in events]

    def _bound_lag(self) -> None:
        for k in np.flatnonzero(self._queued > BANK_LAG_FRAMES).tolist():
            over = int(self._queued[k]) - BANK_LAG_FRAMES
            self._take(k, over)
            self.dropped += over

    def _wire(self, k: int, frame: int) -> tuple[int, float]:
        """Array ``k``'s sender index and time of its processed frame (-1, nan if forgotten)."""
        if frame < self._per_array - BANK_WIRE_FRAMES:
            return -1, math.nan
        slot = frame % BANK_WIRE_FRAMES
        return int(self._wire_index[k, slot]), float(self._wire_t_s[k, slot])

    def summary(self, source_stats: str, why: str) -> str:
        """The closing line: counts, then what each array identified."""
        found: dict[str, list[int]] = {}
        if self.sensor is not None:
            self.sensor.flush()
            for k in range(self.n):
                name = self.sensor.result(k).identified
                if name is not None:
                    found.setdefault(name, []).append(k)
        outcome = "; ".join(
            f"identified {name} on array{'s' if len(ks) > 1 else ''} {','.join(map(str, ks))}"
            for name, ks in found.items()
        )
        extra = [
            f"{count} {what}"
            for count, what in (
                (int(self._queued.sum()), "waiting for other arrays"),
                (self.dropped, "dropped while another array lagged"),
                (self.filled, "repeated for missing frames"),
                (self.other_array, f"of array ids >= {self.n}"),
                (self.wrong_shape, "of another shape"),
                (self.out_of_order, "out of time order"),
            )
            if count
        ]
        counts = "".join(f", {x}" for x in extra)
        return (
            f"{why}: {self.frames} frames processed from {self.n} arrays{counts}, {source_stats}; "
            f"{outcome or 'nothing identified'}"
        )
