"""A bank of smart sensors: many taxel arrays streamed at once.

A robot hand or a skin carries many arrays, each streaming frames. One
:class:`~taxelkit.smart.streaming.SmartSensor` per array costs one Python call
per frame per array; :class:`SensorBank` takes one frame of every array per
push, ``(N, rows, cols)``, buffers ``batch_frames`` of them and runs:

* Levels 1-2 vectorised across arrays and buffered time
  (:class:`~taxelkit.smart.levels12.ChunkLevels12`: cleaning and hysteresis
  state per array, held in arrays);
* the debounce and Levels 3-4 per array
  (:class:`~taxelkit.smart.stream_state.ArrayStream`, one Python step per run
  of equal classes; an array with no contact in the chunk and none pending
  costs a counter update), but for the segments that begin and end within
  the chunk (their Level 3 computed for all the arrays in one
  :func:`~taxelkit.smart.levels34.track_segments` call) and the slip
  scanners' features and window motions of the open segments' new frames,
  computed for all the arrays at once
  (:func:`~taxelkit.smart.bank_slips.slip_inputs`).

Each array gets the events that a ``SmartSensor`` of its own, or
:func:`~taxelkit.smart.recogniser.recognise` on its frames, gives (tested).
Latency: an event is emitted at most ``batch_frames`` pushes after it
occurred (:meth:`SensorBank.flush` forces it out); throughput grows with
``batch_frames`` (``benchmarks/bench_bank.py``).

Arrays of different shapes or pitches go to one bank each;
:class:`SkinBank` groups them and numbers the arrays as given.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive, check_shape, check_threshold
from taxelkit.frames import DEFAULT_FRAME_INTERVAL_S
from taxelkit.smart.bank_slips import slip_inputs
from taxelkit.smart.cleaning import CleaningConfig
from taxelkit.smart.contact_classes import (
    DEFAULT_CONFIDENCE,
    HAND_SET,
    ContactClass,
    ContactNetwork,
)
from taxelkit.smart.contact_limits import ContactLimits
from taxelkit.smart.elimination import Event
from taxelkit.smart.levels12 import (
    DEFAULT_CLEANING,
    DEFAULT_LIMITS,
    DEFAULT_THRESHOLD_MM,
    ChunkLevels12,
)
from taxelkit.smart.levels34 import Recognition, track_segments
from taxelkit.smart.stream_state import ArrayStream, ClassHistory, WholeItem
from taxelkit.smart.streaming import check_count
from taxelkit.smart.tactemes import TactemeConfig

__all__ = ["SensorBank", "SkinBank"]

_NONE = int(ContactClass.NONE)


class SensorBank:
    """``n_arrays`` smart sensors of one shape, streamed together.

    Parameters
    ----------
    n_arrays : int
        Arrays in the bank.
    shape : (rows, cols)
        Frame shape of every array.
    pitch_mm : float
        Taxel pitch, mm.
    threshold, network, confidence, config, cleaning, limits
        As :class:`~taxelkit.smart.streaming.SmartSensor`.
    batch_frames : int
        Pushes buffered before Levels 1-4 run over them (the latency bound,
        in frames of each array).
    evaluate_every : int
        Frames of an array's open contact segment gathered before its motion
        tactemes are looked for (1: every batch). Each look costs the same
        whatever its length, so a larger value trades the emission delay of
        motion tactemes (never their frame numbers) for throughput; contacts
        and lifts are still reported after each batch.

    Examples
    --------
    >>> import numpy as np
    >>> bank = SensorBank(3, (16, 16), pitch_mm=1.7625, batch_frames=8)
    >>> frames = np.zeros((3, 16, 16), bool)
    >>> events = bank.push(frames)  # every array starts clear
    >>> frames[1, 7:9, 7:9] = True  # array 1 is touched
    >>> events += [e for _ in range(3) for e in bank.push(frames)]
    >>> [(i, e.kind, e.frame) for i, e in events + bank.flush()]
    [(1, 'contact', 2), (1, 'tacteme', 2)]
    """

    def __init__(
        self,
        n_arrays: int,
        shape: tuple[int, int],
        *,
        pitch_mm: float,
        threshold: float = DEFAULT_THRESHOLD_MM,
        network: ContactNetwork = HAND_SET,
        confidence: float = DEFAULT_CONFIDENCE,
        config: TactemeConfig | None = None,
        cleaning: CleaningConfig | None = DEFAULT_CLEANING,
        limits: ContactLimits | None = DEFAULT_LIMITS,
        batch_frames: int = 64,
        evaluate_every: int = 1,
    ) -> None:
        self.n_arrays = check_count("n_arrays", n_arrays)
        rows, cols = check_shape("shape", shape)
        self.shape = (rows, cols)
        self.pitch_mm = check_positive("pitch_mm", pitch_mm)
        self.threshold = check_threshold("threshold", threshold)
        self.batch_frames = check_count("batch_frames", batch_frames)
        self.evaluate_every = check_count("evaluate_every", evaluate_every)
        self.config = TactemeConfig() if config is None else config
        self._levels12 = ChunkLevels12(
            self.n_arrays,
            self.shape,
            pitch_mm=self.pitch_mm,
            threshold=self.threshold,
            network=network,
            confidence=float(confidence),
            cleaning=cleaning,
            limits=limits,
        )
        self.reset()

    def reset(self) -> None:
        """Start afresh (no frames seen by any array)."""
        self.frame_index = 0
        self._levels12.reset()
        self._streams = [
            ArrayStream(self.config, chunk_every=self.evaluate_every, pitch_mm=self.pitch_mm)
            for _ in range(self.n_arrays)
        ]
        self._buf: NDArray[Any] | None = None
        self._buf_kind: np.dtype[Any] | None = None  # the dtype of the frames buffered
        self._buf_packed = False  # bool frames, buffered packed
        self._buf_t = np.empty((self.batch_frames, self.n_arrays))
        self._buf_n = 0

    def classes(self, i: int) -> ClassHistory:
        """Level 2 classes of array ``i`` (processed frames, as runs)."""
        return self._streams[i].classes

    def _times(self, t_s: ArrayLike | None, frames: int) -> NDArray[np.float64]:
        """Timestamps ``(N, frames)`` from None, one per frame, or one per array and frame."""
        if t_s is None:
            t_s = (self.frame_index + np.arange(frames)) * DEFAULT_FRAME_INTERVAL_S
        t: NDArray[np.float64] = np.asarray(t_s, dtype=np.float64)
        if t.shape in ((), (frames,)):
            return np.broadcast_to(t, (self.n_arrays, frames)).astype(np.float64)
        if t.shape == (self.n_arrays,) and frames == 1:
            return t[:, None]
        if t.shape == (self.n_arrays, frames):
            return t
        raise InputError(
            f"t_s must be one time, one per frame ({frames},) or one per array and frame "
            f"({self.n_arrays}, {frames}), got shape {t.shape}"
        )

    def push(self, frames: ArrayLike, t_s: ArrayLike | None = None) -> list[tuple[int, Event]]:
        """Take one frame of every array; return the events emitted now.

        Parameters
        ----------
        frames : (N, rows, cols) bool or float
        t_s : float or (N,) float, optional
            Timestamp for all arrays or one per array, s (default: the frame
            index times :data:`~taxelkit.frames.DEFAULT_FRAME_INTERVAL_S`).

        Returns
        -------
        list of (array index, Event)
            Events carry each array's own frame index.
        """
        f = frames if type(frames) is np.ndarray else np.asarray(frames)
        if f.shape != (self.n_arrays, *self.shape):
            raise InputError(
                f"frames must have shape ({self.n_arrays}, {self.shape[0]}, {self.shape[1]}), "
                f"got {f.shape}"
            )
        t = self._times(t_s, 1)
        events: list[tuple[int, Event]] = []
        buf = self._buf
        packed = f.dtype == bool and self._levels12.packs
        if buf is None or self._buf_kind != f.dtype:
            events = self._run()
            # time first: a push copies one contiguous block (bool frames packed, an
            # eighth of the bytes: the cleaning starts from packed rows anyway)
            ops = self._levels12.ops
            size = (self.batch_frames, self.n_arrays, *self.shape)
            buf = self._buf = np.empty(size[:3], ops.dtype) if packed else np.empty(size, f.dtype)
            self._buf_kind, self._buf_packed = f.dtype, packed
        k = self._buf_n
        buf[k] = self._levels12.ops.pack(f) if packed else f
        self._buf_t[k] = t[:, 0]
        self._buf_n = k + 1
        self.frame_index += 1
        if k + 1 == self.batch_frames:
            events += self._run()
        return events

    def push_many(self, frames: ArrayLike, t_s: ArrayLike | None = None) -> list[tuple[int, Event]]:
        """Take ``T`` frames of every array at once, ``(N, T, rows, cols)``; the events emitted.

        ``t_s`` is None, ``(T,)`` (all arrays) or ``(N, T)``, s.
        """
        f = np.asarray(frames)
        if f.ndim != 4 or f.shape[0] != self.n_arrays or f.shape[2:] != self.shape:
            raise InputError(
                f"frames must have shape ({self.n_arrays}, T, {self.shape[0]}, "
                f"{self.shape[1]}), got {f.shape}"
            )
        t = self._times(t_s, f.shape[1])
        events = self._run()
        self.frame_index += f.shape[1]
        return events + self._process(f, t)

    def flush(self) -> list[tuple[int, Event]]:
        """Process the buffered frames now, and look at every open segment; the events caused."""
        out = self._run()
        for i, stream in enumerate(self._streams):
            out += [(i, e) for e in stream.look()]
        return out

    def _run(self) -> list[tuple[int, Event]]:
        """Levels 1-4 over the buffered frames."""
        if not self._buf_n or self._buf is None:
            return []
        n, self._buf_n = self._buf_n, 0
        t = np.ascontiguousarray(self._buf_t[:n].T)
        if self._buf_packed:
            levels = self._levels12.process_packed_time_major(self._buf[:n], t)
        else:
            levels = self._levels12.process_time_major(self._buf[:n], t)
        return self._levels34(*levels, t)

    def _process(self, frames: NDArray[Any], t: NDArray[np.float64]) -> list[tuple[int, Event]]:
        if frames.shape[1] == 0:
            return []
        return self._levels34(*self._levels12.process(frames, t), t)

    def _levels34(
        self, classes: NDArray[np.int8], rows: NDArray[np.float64], t: NDArray[np.float64]
    ) -> list[tuple[int, Event]]:
        """Debounce and Levels 3-4 of every array's chunk: classes, rows ``(N, T, 9)``, times.

        Every touched array is debounced; the segments that began and ended
        within the chunk, of all arrays, are computed at once
        (:func:`~taxelkit.smart.levels34.track_segments`); each array is then
        shown to Levels 3-4 up to its open segment's last feed; the slip
        scanners' part of those feeds is computed for all of them at once
        (:func:`~taxelkit.smart.bank_slips.slip_inputs`), then each feed is made.
        """
        quiet = (~np.any(classes != _NONE, axis=1)).tolist()
        touched: list[tuple[int, list[Event]]] = []
        whole: list[list[WholeItem]] = []
        for i, (stream, still) in enumerate(zip(self._streams, quiet, strict=True)):
            if still and stream.idle:
                stream.push_quiet(t[i])
                continue
            touched.append((i, []))
            whole.append(stream.debounce_chunk(classes[i], rows[i], t[i]))
        # the segments that began and ended within the chunk, of every array at once
        segs = track_segments([w for items in whole for w in items], self.config)
        at = 0
        for (i, events), items in zip(touched, whole, strict=True):
            events += self._streams[i].settle_chunk(segs[at : at + len(items)])
            at += len(items)
        feeds = [(k, self._streams[i].tail_feed) for k, (i, _) in enumerate(touched)]
        fed = [(k, f) for k, f in feeds if f is not None]
        inputs = slip_inputs([f for _, f in fed])
        for (k, _), slip in zip(fed, inputs, strict=True):
            i, events = touched[k]
            events += self._streams[i].end_chunk(slip)
        return [(i, e) for i, events in touched for e in events]

    def forget_history(self, *, events_kept: int = 1024) -> None:
        """Bound memory on endless streams: drop the per-frame class runs, and old contacts' events.

        The class history (:meth:`classes`) starts afresh; an array holding
        more than ``events_kept`` events forgets those before its last two
        lifts (the verdict looks at the last contact only). Call it between
        pushes; the events still to come are unchanged.
        """
        for stream in self._streams:
            stream.classes = ClassHistory()
            events = stream.state.events
            if len(events) > events_kept:
                lifts = [k for k, e in enumerate(events) if e.kind == "lifted"]
                if len(lifts) >= 2:
                    del events[: lifts[-2] + 1]

    def result(self, i: int) -> Recognition:
        """Everything array ``i`` has seen, as a :class:`Recognition` (buffered frames included)."""
        self.flush()
        return self._streams[i].result()


class SkinBank:
    """Arrays of several shapes or pitches, one :class:`SensorBank` per kind.

    Parameters
    ----------
    arrays : sequence of ((rows, cols), pitch_mm)
        Every array's shape and pitch, in the order frames will be given.
    **options
        Passed to every :class:`SensorBank` (``batch_frames``, ``config``...).

    Examples
    --------
    >>> import numpy as np
    >>> skin = SkinBank([((16, 16), 1.7625), ((8, 8), 2.5), ((16, 16), 1.7625)], batch_frames=4)
    >>> len(skin.banks), skin.where(2)
    (2, (0, 1))
    >>> frames = [np.zeros((16, 16), bool), np.zeros((8, 8), bool), np.zeros((16, 16), bool)]
    >>> skin.push(frames)
    []
    """

    def __init__(self, arrays: Sequence[tuple[tuple[int, int], float]], **options: Any) -> None:
        kinds: dict[tuple[tuple[int, int], float], list[int]] = {}
        for i, (shape, pitch) in enumerate(arrays):
            rows, cols = check_shape("shape", shape)
            kinds.setdefault(((rows, cols), float(pitch)), []).append(i)
        self.members = list(kinds.values())  # global array indices of each bank
        self.banks = [
            SensorBank(len(idx), shape, pitch_mm=pitch, **options)
            for (shape, pitch), idx in kinds.items()
        ]
        self._where = {g: (b, k) for b, idx in enumerate(self.members) for k, g in enumerate(idx)}

    def where(self, i: int) -> tuple[int, int]:
        """Bank and position within it of array ``i``."""
        return self._where[i]

    def push(
        self, frames: Sequence[ArrayLike], t_s: ArrayLike | None = None
    ) -> list[tuple[int, Event]]:
        """One frame per array, in the given order (``t_s``: one time, or one per array)."""
        if len(frames) != len(self._where):
            raise InputError(f"frames must hold {len(self._where)} arrays, got {len(frames)}")
        t = None if t_s is None else np.asarray(t_s, dtype=np.float64)
        out: list[tuple[int, Event]] = []
        for idx, bank in zip(self.members, self.banks, strict=True):
            tb = t if t is None or t.ndim == 0 else t[idx]
            stack = np.stack([np.asarray(frames[g]) for g in idx])
            out += [(idx[k], e) for k, e in bank.push(stack, tb)]
        return out

    def flush(self) -> list[tuple[int, Event]]:
        """Process every bank's buffered frames now."""
        return [
            (idx[k], e)
            for idx, b in zip(self.members, self.banks, strict=True)
            for k, e in b.flush()
        ]

    def result(self, i: int) -> Recognition:
        """Everything array ``i`` has seen."""
        b, k = self._where[i]
        return self.banks[b].result(k)
