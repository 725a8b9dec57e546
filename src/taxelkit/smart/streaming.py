"""The smart sensor streamed: frames pushed as they come, events emitted as they happen.

:class:`SmartSensor` has two ways to run Levels 1-2:

* ``batch_frames=1`` (default): each frame is processed when pushed, in plain
  Python (one 16 x 16 frame is too small for NumPy to pay off): the lowest
  latency, about 50 us of work per frame;
* ``batch_frames=B``: frames are buffered and every ``B``-th push (or
  :meth:`SmartSensor.flush`) runs the batch's vectorised Levels 1-2 over the
  buffer (:class:`~taxelkit.smart.levels12.ChunkLevels12`, state carried):
  an event waits up to ``B`` frames (``B / rate`` seconds) before it is
  emitted, and costs a fraction of the per-frame work.

Either way the debounce and Levels 3-4 run incrementally
(:class:`~taxelkit.smart.stream_state.ArrayStream`), so the cost per frame
does not grow with a contact's length and the memory stays bounded; events
carry the frame index at which they occurred, the same events as
:func:`~taxelkit.smart.recogniser.recognise` on the same frames.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive, check_shape, check_threshold
from taxelkit.frames import DEFAULT_FRAME_INTERVAL_S
from taxelkit.smart.cleaning import CleaningConfig
from taxelkit.smart.cleaning_stream import ImageCleaner
from taxelkit.smart.contact_classes import (
    DEFAULT_CONFIDENCE,
    HAND_SET,
    OUTPUT_CLASSES,
    REFERENCE_AREA_MM2,
    ContactClass,
    ContactNetwork,
)
from taxelkit.smart.contact_limits import ContactLimits, LimitState, limit_one
from taxelkit.smart.elimination import Event
from taxelkit.smart.index_sums import index_basis
from taxelkit.smart.levels12 import (
    DEFAULT_CLEANING,
    DEFAULT_LIMITS,
    DEFAULT_THRESHOLD_MM,
    ChunkLevels12,
)
from taxelkit.smart.levels34 import Recognition
from taxelkit.smart.moments import CELL_SECOND_MOMENT
from taxelkit.smart.stream_state import ArrayStream, ClassHistory
from taxelkit.smart.tactemes import TactemeConfig

__all__ = ["SmartSensor", "check_count"]

_hypot, _arctan2 = np.hypot, np.arctan2


def check_count(name: str, value: object) -> int:
    """``value`` as an integer >= 1, or :class:`~taxelkit.errors.InputError` naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise InputError(f"{name} must be an integer >= 1, got {value!r}")
    return int(value)


class _FrameLevels12:
    """Levels 1-2 of one frame in plain Python (the per-frame path)."""

    def __init__(self, sensor: SmartSensor) -> None:
        rows, cols = sensor.shape
        self.pitch_mm, self.threshold = sensor.pitch_mm, sensor.threshold
        self.confidence, self.limits = sensor.confidence, sensor.limits
        basis = index_basis(rows, cols)
        net = sensor.network
        # the network as plain floats: per hidden unit (w_area, w_elong, bias),
        # per output its weight column and bias (one frame is too small for NumPy)
        self._hidden = list(
            zip(
                net.w_hidden[0].tolist(),
                net.w_hidden[1].tolist(),
                net.b_hidden.tolist(),
                strict=True,
            )
        )
        self._outputs = list(zip(net.w_output.T.tolist(), net.b_output.tolist(), strict=True))
        self._basis_t = np.ascontiguousarray(basis.T)
        self._u_mm = basis[:, 1] * self.pitch_mm  # taxel centres, mm
        self._v_mm = basis[:, 2] * self.pitch_mm
        self._limit_state = LimitState()
        self._cleaner = (
            None if sensor.cleaning is None else ImageCleaner(sensor.shape, config=sensor.cleaning)
        )

    def classify(self, frame: NDArray[Any], t_s: float) -> tuple[int, tuple[float, ...]]:
        b = frame if frame.dtype == bool else frame.astype(np.float64) > self.threshold
        if self._cleaner is not None:
            b = self._cleaner.push(b, t_s)
        n, su, sv, suu, svv, suv = (self._basis_t @ b.ravel()).tolist()
        if n == 0:
            self._limit_state.long = False  # as the batch path: no contact, no length
            self._limit_state.big = False
            self._limit_state.run = 0  # no area either
            self._limit_state.line_run = 0
            self._limit_state.length_mm = 0.0
            self._limit_state.t_prev = t_s
            return int(ContactClass.NONE), ()
        p = self.pitch_mm
        cuu = (n * suu - su * su) / (n * n) + CELL_SECOND_MOMENT
        cvv = (n * svv - sv * sv) / (n * n) + CELL_SECOND_MOMENT
        cuv = (n * suv - su * sv) / (n * n)
        # NumPy's hypot and arctan2, the batch path's (math's differ in the last bit
        # for about 1 % and 8 % of arguments), and its order of operations: the
        # same floats, so that a tie at a threshold falls the same way in both
        radius = float(_hypot(0.5 * (cuu - cvv), cuv))
        lam_max = 0.5 * (cuu + cvv) + radius
        lam_min = (cuu * cvv - cuv * cuv) / lam_max
        elong = math.sqrt(max(lam_max / lam_min, 1.0))  # >= 1 despite rounding
        theta = 0.5 * math.degrees(float(_arctan2(2.0 * cuv, cuu - cvv)))
        if theta <= -90.0:
            theta += 180.0
        p2 = p * p
        area = n * p2  # areas are multiples of p2: ratios of them tie with area_step
        x0, x1 = math.log(area / REFERENCE_AREA_MM2), math.log(elong)
        tanh = math.tanh
        h = [tanh(x0 * wa + x1 * we + bb) for wa, we, bb in self._hidden]
        z = [math.fsum(map(float.__mul__, h, w)) + bo for w, bo in self._outputs]
        top = max(z)
        e = [math.exp(v - top) for v in z]
        best = max(range(len(e)), key=e.__getitem__)
        prob = e[best] / sum(e)
        cls = (
            int(OUTPUT_CLASSES[best]) if prob > self.confidence else int(ContactClass.INDETERMINATE)
        )
        vx, vy, cxy = cuu * p2, cvv * p2, cuv * p2  # as levels12.half_length
        half = math.sqrt(3.0 * (0.5 * (vx + vy) + float(_hypot(0.5 * (vx - vy), cxy))))
        if self.limits is not None:
            cls = limit_one(
                cls, int(n), 2.0 * half, elong, area, self.limits, self._limit_state, t_s
            )
        cx, cy = su / n * p, sv / n * p
        lo = hi = math.nan
        if cls == ContactClass.LINE:  # the drawn ends along the axis (the pivot's yardstick)
            t = math.radians(theta)
            on = b.ravel()
            proj = (self._u_mm[on] - cx) * math.cos(t) + (self._v_mm[on] - cy) * math.sin(t)
            lo, hi = float(proj.min()) - 0.5 * p, float(proj.max()) + 0.5 * p
        return cls, (cx, cy, theta, area, elong, half, lo, hi, t_s)


class SmartSensor:
    """The smart sensor, streamed (Levels 1-4 as frames arrive).

    Parameters
    ----------
    shape : (rows, cols)
        Frame shape.
    pitch_mm : float
        Taxel pitch, mm.
    threshold : float
        Contact threshold for float frames.
    network : ContactNetwork
    confidence : float
    config : TactemeConfig, optional
    cleaning : CleaningConfig or None
        Image cleaning before Level 1, as in :func:`~taxelkit.smart.recogniser.recognise`.
    limits : ContactLimits or None
        Level 2 limits, as in :func:`~taxelkit.smart.recogniser.recognise`.
    evaluate_every : int
        With ``batch_frames=1``: the open segment's motion tactemes are looked
        for every this many of its frames and whenever it ends (each look
        costs the same at any age of the segment). Detection is causal, so
        events and their frame numbers are those of ``recognise``; only their
        emission waits (up to 67 ms at 240 Hz for the default 16). 1 emits
        every event on its own frame.
    batch_frames : int
        Frames buffered before Levels 1-4 run over them, vectorised (1: each
        frame at once). Latency: an event is emitted at most ``batch_frames``
        frames after it occurred (:meth:`flush` forces it out sooner).

    Examples
    --------
    >>> import numpy as np
    >>> sensor = SmartSensor((16, 16), pitch_mm=1.7625)
    >>> frame = np.zeros((16, 16), bool); frame[7:9, 7:9] = True
    >>> frames = [np.zeros_like(frame)] + [frame] * 3  # the array starts clear
    >>> [(e.kind, e.frame) for f in frames for e in sensor.push(f)]
    [('contact', 2), ('tacteme', 2)]
    >>> fast = SmartSensor((16, 16), pitch_mm=1.7625, batch_frames=256)
    >>> [e for f in frames for e in fast.push(f)], [(e.kind, e.frame) for e in fast.flush()]
    ([], [('contact', 2), ('tacteme', 2)])
    """

    def __init__(
        self,
        shape: tuple[int, int],
        *,
        pitch_mm: float,
        threshold: float = DEFAULT_THRESHOLD_MM,
        network: ContactNetwork = HAND_SET,
        confidence: float = DEFAULT_CONFIDENCE,
        config: TactemeConfig | None = None,
        cleaning: CleaningConfig | None = DEFAULT_CLEANING,
        limits: ContactLimits | None = DEFAULT_LIMITS,
        evaluate_every: int = 16,
        batch_frames: int = 1,
    ) -> None:
        rows, cols = check_shape("shape", shape)
        self.evaluate_every = check_count("evaluate_every", evaluate_every)
        self.batch_frames = check_count("batch_frames", batch_frames)
        self.shape = (rows, cols)
        self.pitch_mm = check_positive("pitch_mm", pitch_mm)
        self.threshold = check_threshold("threshold", threshold)
        self.network = network
        self.confidence = float(confidence)
        self.config = TactemeConfig() if config is None else config
        self.cleaning = cleaning
        self.limits = limits
        self.reset()

    def reset(self) -> None:
        """Start afresh (no frames seen)."""
        self.frame_index = 0
        self._stream = ArrayStream(self.config, self.evaluate_every, pitch_mm=self.pitch_mm)
        self._frame = _FrameLevels12(self)
        self._chunk = ChunkLevels12(
            1,
            self.shape,
            pitch_mm=self.pitch_mm,
            threshold=self.threshold,
            network=self.network,
            confidence=self.confidence,
            cleaning=self.cleaning,
            limits=self.limits,
        )
        self._buf: NDArray[Any] | None = None
        self._buf_t = np.empty(self.batch_frames)
        self._buf_n = 0

    @property
    def classes(self) -> ClassHistory:
        """Level 2 class of every processed frame (runs; ``classes[-1]`` is the latest)."""
        return self._stream.classes

    def push(self, frame: ArrayLike, t_s: float | None = None) -> list[Event]:
        """Take one frame; return the events emitted now (often none).

        Parameters
        ----------
        frame : (rows, cols) bool or float
        t_s : float, optional
            Timestamp, s (default: the frame index times
            :data:`~taxelkit.frames.DEFAULT_FRAME_INTERVAL_S`, as for a
            recording without ``t_s``). Events carry frame indices.
        """
        f = frame if type(frame) is np.ndarray else np.asarray(frame)
        if f.shape != self.shape:
            raise InputError(f"frame must have shape {self.shape}, got {f.shape}")
        j = self.frame_index
        self.frame_index += 1
        t = float(j) * DEFAULT_FRAME_INTERVAL_S if t_s is None else float(t_s)
        if self.batch_frames == 1:
            cls, row = self._frame.classify(f, t)
            return self._stream.push_one(cls, row, t)
        buf = self._buf
        events: list[Event] = []
        if buf is None or buf.dtype != f.dtype:
            events = self.flush()
            buf = self._buf = np.empty((self.batch_frames, *self.shape), dtype=f.dtype)
        k = self._buf_n
        buf[k] = f
        self._buf_t[k] = t
        self._buf_n = k + 1
        if k + 1 == self.batch_frames:
            events += self.flush()
        return events

    def push_many(self, frames: ArrayLike, t_s: ArrayLike | None = None) -> list[Event]:
        """Take frames ``(T, rows, cols)`` at once (times ``(T,)`` s); the events emitted now.

        With ``batch_frames > 1`` the frames go through the vectorised Levels
        1-2 together, after any frames buffered before them; with
        ``batch_frames=1`` they are pushed one by one.
        """
        f = np.asarray(frames)
        if f.ndim != 3 or f.shape[1:] != self.shape:
            raise InputError(
                f"frames must have shape (T, {self.shape[0]}, {self.shape[1]}), got {f.shape}"
            )
        j0 = self.frame_index
        t = np.asarray(
            (j0 + np.arange(f.shape[0])) * DEFAULT_FRAME_INTERVAL_S if t_s is None else t_s,
            dtype=np.float64,
        ).reshape(-1)
        if t.shape != (f.shape[0],):
            raise InputError(f"t_s must have shape ({f.shape[0]},), got {t.shape}")
        if self.batch_frames == 1:
            return [e for fr, tt in zip(f, t.tolist(), strict=True) for e in self.push(fr, tt)]
        events = self.flush()
        self.frame_index += f.shape[0]
        return events + self._process(f, t)

    def flush(self) -> list[Event]:
        """Process the buffered frames now; the events they cause."""
        if not self._buf_n or self._buf is None:
            return []
        n, self._buf_n = self._buf_n, 0
        return self._process(self._buf[:n], self._buf_t[:n].copy())

    def _process(self, frames: NDArray[Any], t: NDArray[np.float64]) -> list[Event]:
        if frames.shape[0] == 0:
            return []
        classes, rows = self._chunk.process(frames[None], t[None])
        return self._stream.push_chunk(classes[0], rows[0], t)

    def result(self) -> Recognition:
        """Everything so far as a :class:`Recognition` (buffered frames included)."""
        self.flush()
        return self._stream.result()
