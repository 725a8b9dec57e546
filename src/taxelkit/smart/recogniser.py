"""The smart tactile sensor of paper 001: Levels 1-4, batch and streaming.

:func:`recognise` processes a whole recording (vectorised Levels 1-2, run-length
debounce, per-segment Level 3); :class:`SmartSensor` takes one frame at a time
and emits :class:`~taxelkit.smart.elimination.Event` objects as they happen.
Both see only frames, timestamps and the pitch; for the same frames they
produce the same events.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive, check_shape, check_threshold
from taxelkit.frames import DEFAULT_FRAME_INTERVAL_S, TactileFrames
from taxelkit.smart.cleaning import CleaningConfig, clean_images
from taxelkit.smart.cleaning_stream import ImageCleaner
from taxelkit.smart.contact_classes import (
    DEFAULT_CONFIDENCE,
    HAND_SET,
    OUTPUT_CLASSES,
    REFERENCE_AREA_MM2,
    ContactClass,
    ContactNetwork,
    classify_contacts,
)
from taxelkit.smart.contact_limits import ContactLimits, LimitState, apply_limits, limit_one
from taxelkit.smart.elimination import Eliminator, Event, Verdict, explain
from taxelkit.smart.moments import CELL_SECOND_MOMENT, ImageStats, binary_images, image_stats
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.tactemes import (
    SegmentTrack,
    TactemeConfig,
    accepted_runs,
    debounce_counts,
    segment_tactemes,
    transition_tactemes,
)
from taxelkit.smart.track_geometry import line_extents

__all__ = ["DEFAULT_CLEANING", "DEFAULT_LIMITS", "Recognition", "SmartSensor", "recognise"]

#: Default contact threshold, mm: the Bonneville preset's fixed threshold.
_DEFAULT_THRESHOLD_MM = 0.03
#: Image cleaning used unless switched off (``cleaning=None``: paper 001's pipeline).
DEFAULT_CLEANING = CleaningConfig()
#: Level 2 limits in mm and taxels used unless switched off (``limits=None``).
DEFAULT_LIMITS = ContactLimits()

_BASIC = {
    int(ContactClass.POINT): Tacteme.PC,
    int(ContactClass.LINE): Tacteme.LC,
    int(ContactClass.AREA): Tacteme.AC,
}


@dataclass(frozen=True, eq=False)
class Recognition:
    """What the smart sensor concluded from a recording.

    Attributes
    ----------
    classes : (T,) int8
        Level 2 class of every frame.
    tactemes : tuple of (str, int)
        Level 3 tactemes with the frame at which each was seen.
    events : tuple of Event
        Everything in order.
    identified : str or None
        The object of the last contact, ``"unknown"``, or None if undecided.
    candidates : tuple of str
        Objects not yet eliminated for the last contact.
    verdict : Verdict
        Why: what ruled out each object of the last contact and, when
        undecided, which tactemes (motions) would decide.
    """

    classes: NDArray[np.int8]
    tactemes: tuple[tuple[str, int], ...]
    events: tuple[Event, ...]
    identified: str | None
    candidates: tuple[str, ...]
    verdict: Verdict

    def class_names(self) -> list[str]:
        """Per-frame class names (``"none"``, ``"indeterminate"``, ``"point"``, ...)."""
        return [ContactClass(int(c)).name.lower() for c in self.classes]

    def to_json(self) -> dict[str, Any]:
        """``identified``, ``candidates``, ``tactemes`` and ``classes`` as JSON types."""
        return {
            "identified": self.identified,
            "candidates": list(self.candidates),
            "why": self.verdict.to_json(),
            "tactemes": [{"name": n, "frame": f} for n, f in self.tactemes],
            "classes": self.class_names(),
        }


def _half_length(stats: ImageStats) -> NDArray[np.float64]:
    vx, vy, cxy = stats.var_x_mm2, stats.var_y_mm2, stats.cov_xy_mm2
    lam = 0.5 * (vx + vy) + np.hypot(0.5 * (vx - vy), cxy)
    out: NDArray[np.float64] = np.sqrt(3.0 * lam)
    return out


class _Levels34:
    """Levels 3-4 state over accepted runs; shared by batch and streaming."""

    def __init__(self, config: TactemeConfig) -> None:
        self.config = config
        self.k = int(config.debounce_frames)
        self.elim = Eliminator()
        self.history: list[tuple[int, float]] = []
        self.in_contact = False
        self.events: list[Event] = []
        self._open: tuple[int, set[Tacteme]] | None = None  # class, motion tactemes emitted
        self._last_frame = -1  # last frame of the previous contact segment
        self._gap = 0  # frames between the previous contact segment and the open one
        self._len = 0  # frames of the open (then previous) segment
        self._prev_len = 0
        self._held = 0
        self._prev_held = 0
        self._transitions_done = True

    def open_run(self, cls: int, accept: int, track: SegmentTrack | None) -> None:
        """A new class was accepted at frame ``accept``."""
        self.close_run()
        if cls == ContactClass.NONE:
            if self.in_contact:
                self.events.append(Event("lifted", accept, self.elim.candidates))
                self.elim.reset()
                self.history = []
                self.in_contact = False
            return
        assert track is not None  # a contact class always has frames
        self.in_contact = True
        self.events.append(Event("contact", accept, ContactClass(cls).name.lower()))
        self.history.append((cls, _mean_axis_deg(track.orientation_deg[: self.k])))
        self._gap = int(track.frames[0]) - self._last_frame - 1
        self._prev_len = self._len
        self._prev_held = self._held
        self.events.extend(self.elim.apply(_BASIC[cls], accept))
        self._open = (cls, set())
        self._transitions_done = False
        self.update(track)

    def update(self, track: SegmentTrack) -> None:
        """The open segment grew: emit its new motion tactemes (detection is causal)."""
        if self._open is None:
            return
        cls, done = self._open
        # Transitions need a held edge (2 k frames of line): a round face tipping
        # onto its rim shrinks through a lens that reads as a line for a moment.
        held = track.frames_for(self.config.edge_hold_s, self.k)
        line_before = self.history[-2][0] == ContactClass.LINE if len(self.history) > 1 else False
        ready = (
            track.frames.size >= held
            if cls == ContactClass.LINE
            else (not line_before or self._prev_len >= self._prev_held)
        )
        if not self._transitions_done and ready:
            self._transitions_done = True
            if cls == ContactClass.LINE:  # the new edge's direction over its held frames
                self.history[-1] = (cls, _mean_axis_deg(track.orientation_deg[:held]))
            at = (
                int(track.frames[min(track.frames.size, held) - 1])
                if cls == ContactClass.LINE
                else (
                    int(track.frames[self.k - 1])
                    if track.frames.size >= self.k
                    else int(track.frames[-1])
                )
            )
            max_gap = max(2 * self.k, track.frames_for(self.config.transition_gap_s, self.k))
            found = transition_tactemes(
                self.history, self.config, gap_frames=self._gap, max_gap_frames=max_gap
            )
            for tac in found:
                self.events.extend(self.elim.apply(tac, at))
        for tac, frame in segment_tactemes(cls, track, self.config):
            if tac not in done:
                done.add(tac)
                self.events.extend(self.elim.apply(tac, frame))
        self._len = int(track.frames.size)
        self._held = held
        # a line's direction over all its frames (held still, an edge dominates its tips)
        self.history[-1] = (cls, _mean_axis_deg(track.orientation_deg))
        self._last_frame = int(track.frames[-1])

    def close_run(self) -> None:
        """The open segment ended."""
        self._open = None


def _events_for_runs(
    runs: list[tuple[int, int, NDArray[np.intp]]],
    track_of: Any,
    config: TactemeConfig,
) -> list[Event]:
    """Levels 3-4 over the accepted runs of a whole recording (batch)."""
    state = _Levels34(config)
    for cls, accept, frames in runs:
        state.open_run(cls, accept, track_of(frames) if cls != ContactClass.NONE else None)
    return state.events


def _mean_axis_deg(theta_deg: NDArray[np.float64]) -> float:
    if theta_deg.size == 0:
        return float("nan")
    t = np.deg2rad(2.0 * theta_deg)
    return float(0.5 * np.rad2deg(np.arctan2(np.sin(t).sum(), np.cos(t).sum())))


def _finish(classes: NDArray[np.int8], events: list[Event]) -> Recognition:
    """Summarise: the outcome is that of the current contact, or of the last one lifted."""
    tactemes = tuple((str(e.value), e.frame) for e in events if e.kind == "tacteme")
    state = Eliminator()
    current: tuple[str, ...] | None = None  # candidates of the ongoing contact
    lifted: tuple[str, ...] | None = None  # candidates when the last contact ended
    seen: list[tuple[str, int]] = []  # tactemes of the ongoing (or last) contact
    for e in events:
        if e.kind == "contact" and current is None:
            current, seen = state.objects, []
        elif e.kind == "candidates":
            current = tuple(e.value)
        elif e.kind == "lifted":
            lifted, current = tuple(e.value), None
        elif e.kind == "tacteme":
            seen.append((str(e.value), e.frame))
    final = current if current is not None else lifted
    state.candidates = state.objects if final is None else final
    verdict = explain(seen, objects=state.objects)
    assert verdict.candidates == state.candidates  # the same elimination, told twice
    return Recognition(classes, tactemes, tuple(events), state.outcome, state.candidates, verdict)


def recognise(
    recording: TactileFrames | ArrayLike,
    *,
    threshold: float | None = None,
    pitch_mm: float | None = None,
    network: ContactNetwork = HAND_SET,
    confidence: float = DEFAULT_CONFIDENCE,
    config: TactemeConfig | None = None,
    cleaning: CleaningConfig | None = DEFAULT_CLEANING,
    limits: ContactLimits | None = DEFAULT_LIMITS,
) -> Recognition:
    """Recognise the object(s) touching the sensor in a recording (batch).

    Parameters
    ----------
    recording : TactileFrames or (T, rows, cols) array
        Bool contact images or float deflections.
    threshold : float, optional
        Contact threshold for float frames (in the recording's units); default
        0.03 mm, the Bonneville preset's. Ignored for bool frames.
    pitch_mm : float, optional
        Overrides the recording's pitch (required for a bare array).
    network : ContactNetwork
        Level 2 network (hand-set by default).
    confidence : float
        Level 2 confidence.
    config : TactemeConfig, optional
        Level 3 thresholds.
    cleaning : CleaningConfig or None
        Image cleaning before Level 1 (:mod:`taxelkit.smart.cleaning`);
        None feeds the thresholded images to Level 1 as paper 001 does.
    limits : ContactLimits or None
        Level 2 limits in mm and taxels, with hysteresis
        (:mod:`taxelkit.smart.contact_limits`); None keeps the network's classes.

    Returns
    -------
    Recognition
    """
    cfg = TactemeConfig() if config is None else config
    if isinstance(recording, TactileFrames):
        frames = recording.frames
        t_s = np.asarray(recording.t_s, dtype=np.float64)
        pitch = recording.pitch_mm if pitch_mm is None else check_positive("pitch_mm", pitch_mm)
    else:
        frames = np.asarray(recording)
        t_s = np.arange(frames.shape[0], dtype=np.float64) * DEFAULT_FRAME_INTERVAL_S
        if pitch_mm is None:
            raise InputError("pitch_mm is required when recording is a bare array")
        pitch = check_positive("pitch_mm", pitch_mm)
    thr = _DEFAULT_THRESHOLD_MM if threshold is None else check_threshold("threshold", threshold)
    images = binary_images(frames, None if frames.dtype == bool else thr)
    if cleaning is not None and images.ndim == 3:
        images = clean_images(images, t_s, config=cleaning)
    stats = image_stats(images, pitch_mm=pitch)
    classes = classify_contacts(stats, network, confidence=confidence)
    half = _half_length(stats)
    if limits is not None:
        classes = apply_limits(
            classes, stats.n_taxels, 2.0 * half, stats.elongation, limits, area_mm2=stats.area_mm2
        ).astype(np.int8)

    extent = np.full((classes.size, 2), np.nan)
    lines = np.flatnonzero(classes == ContactClass.LINE)
    if lines.size:
        stack = images.reshape(-1, *images.shape[-2:])
        extent[lines] = line_extents(
            stack[lines], stats.centre_mm[lines], stats.orientation_deg[lines], pitch
        )

    def track_of(idx: NDArray[np.intp]) -> SegmentTrack:
        return SegmentTrack(
            idx,
            stats.centre_mm[idx],
            stats.orientation_deg[idx],
            stats.area_mm2[idx],
            stats.elongation[idx],
            half[idx],
            t_s[idx],
            extent[idx],
        )

    k, k_none = debounce_counts(cfg, float(t_s[1] - t_s[0]) if t_s.size > 1 else None)
    runs = accepted_runs(classes, k, k_none=k_none)
    return _finish(classes, _events_for_runs(runs, track_of, cfg))


class SmartSensor:
    """The smart sensor, one frame at a time (streaming Levels 1-4).

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
        Image cleaning before Level 1, as in :func:`recognise`.
    limits : ContactLimits or None
        Level 2 limits, as in :func:`recognise`.
    evaluate_every : int
        The open segment's motion tactemes are looked for every this many of
        its frames, or every 1/32 of its length so far if that is more (the
        look is O(length): this keeps the cost per frame constant), and
        whenever it ends. Detection is causal, so the events and their frame
        numbers are those of :func:`recognise`; only their emission waits (up
        to 67 ms at 240 Hz for the default 16, at most 3 % of the segment's age
        for long segments). 1 emits every event on its own frame.

    Examples
    --------
    >>> import numpy as np
    >>> sensor = SmartSensor((16, 16), pitch_mm=1.7625)
    >>> frame = np.zeros((16, 16), bool); frame[7:9, 7:9] = True
    >>> [e.kind for _ in range(3) for e in sensor.push(frame)]
    ['contact', 'tacteme']
    """

    def __init__(
        self,
        shape: tuple[int, int],
        *,
        pitch_mm: float,
        threshold: float = _DEFAULT_THRESHOLD_MM,
        network: ContactNetwork = HAND_SET,
        confidence: float = DEFAULT_CONFIDENCE,
        config: TactemeConfig | None = None,
        cleaning: CleaningConfig | None = DEFAULT_CLEANING,
        limits: ContactLimits | None = DEFAULT_LIMITS,
        evaluate_every: int = 16,
    ) -> None:
        rows, cols = check_shape("shape", shape)
        if (
            isinstance(evaluate_every, bool)
            or not isinstance(evaluate_every, int | np.integer)
            or evaluate_every < 1
        ):
            raise InputError(f"evaluate_every must be an integer >= 1, got {evaluate_every!r}")
        self.evaluate_every = int(evaluate_every)
        self.shape = (rows, cols)
        self.pitch_mm = check_positive("pitch_mm", pitch_mm)
        self.threshold = check_threshold("threshold", threshold)
        self.network = network
        self.confidence = float(confidence)
        self.config = TactemeConfig() if config is None else config
        self.cleaning = cleaning
        self.limits = limits
        u = np.arange(cols) - (cols - 1) / 2.0
        v = np.arange(rows) - (rows - 1) / 2.0
        uu, vv = np.meshgrid(u, v)
        self._basis = np.stack(
            [
                np.ones(rows * cols),
                uu.ravel(),
                vv.ravel(),
                uu.ravel() ** 2,
                vv.ravel() ** 2,
                (uu * vv).ravel(),
            ],
            axis=1,
        )
        # the network as plain floats: per hidden unit (w_area, w_elong, bias),
        # per output its weight column and bias (one frame is too small for NumPy)
        self._hidden = list(
            zip(
                network.w_hidden[0].tolist(),
                network.w_hidden[1].tolist(),
                network.b_hidden.tolist(),
                strict=True,
            )
        )
        self._outputs = list(
            zip(network.w_output.T.tolist(), network.b_output.tolist(), strict=True)
        )
        self._basis_t = np.ascontiguousarray(self._basis.T)
        self._u_mm = self._basis[:, 1] * self.pitch_mm  # taxel centres, mm
        self._v_mm = self._basis[:, 2] * self.pitch_mm
        self.reset()

    def reset(self) -> None:
        """Start afresh (no frames seen)."""
        self.frame_index = 0
        self.classes: list[int] = []
        self._accepted = int(ContactClass.NONE)
        self._candidate: int | None = None
        self._cand_frames: list[int] = []
        self._cand_rows: list[tuple[float, ...]] = []  # statistics of the candidate frames
        # the open segment's frames and statistics, in growing buffers (amortised O(1))
        self._seg_idx = np.empty(64, dtype=np.intp)
        self._seg_rows = np.empty((64, 9))
        self._seg_n = 0
        self._state = _Levels34(self.config)
        self._limit_state = LimitState()
        self._t_first: float | None = None
        self._dt: float | None = None
        self._cleaner = (
            None if self.cleaning is None else ImageCleaner(self.shape, config=self.cleaning)
        )

    # -- Level 1 and 2 for one frame --------------------------------------------------
    def _classify(self, frame: NDArray[Any], t_s: float) -> tuple[int, tuple[float, ...]]:
        b = frame if frame.dtype == bool else frame > self.threshold
        if self._cleaner is not None:
            b = self._cleaner.push(b, t_s)
        n, su, sv, suu, svv, suv = (self._basis_t @ b.ravel()).tolist()
        if n == 0:
            self._limit_state.long = False  # as the batch path: no contact, no length
            self._limit_state.big = False
            return int(ContactClass.NONE), ()
        p = self.pitch_mm
        cuu = (n * suu - su * su) / (n * n) + CELL_SECOND_MOMENT
        cvv = (n * svv - sv * sv) / (n * n) + CELL_SECOND_MOMENT
        cuv = (n * suv - su * sv) / (n * n)
        radius = math.hypot(0.5 * (cuu - cvv), cuv)
        lam_max = 0.5 * (cuu + cvv) + radius
        lam_min = (cuu * cvv - cuv * cuv) / lam_max
        elong = math.sqrt(max(lam_max / lam_min, 1.0))  # >= 1 despite rounding
        theta = 0.5 * math.degrees(math.atan2(2.0 * cuv, cuu - cvv))
        if theta <= -90.0:
            theta += 180.0
        area = n * p * p
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
        half = math.sqrt(3.0 * lam_max * p * p)
        if self.limits is not None:
            cls = limit_one(cls, int(n), 2.0 * half, elong, area, self.limits, self._limit_state)
        cx, cy = su / n * p, sv / n * p
        lo = hi = math.nan
        if cls == ContactClass.LINE:  # the drawn ends along the axis (the pivot's yardstick)
            t = math.radians(theta)
            on = b.ravel()
            proj = (self._u_mm[on] - cx) * math.cos(t) + (self._v_mm[on] - cy) * math.sin(t)
            lo, hi = float(proj.min()) - 0.5 * p, float(proj.max()) + 0.5 * p
        return cls, (cx, cy, theta, area, elong, half, lo, hi)

    # -- Level 3 and 4 -------------------------------------------------------------------
    def push(self, frame: ArrayLike, t_s: float | None = None) -> list[Event]:
        """Process one frame; return the events it caused (often none).

        Parameters
        ----------
        frame : (rows, cols) bool or float
        t_s : float, optional
            Timestamp, s (default: the frame index times
            :data:`~taxelkit.frames.DEFAULT_FRAME_INTERVAL_S`, as for a
            recording without ``t_s``). Events carry frame indices.
        """
        f = np.asarray(frame)
        if f.shape != self.shape:
            raise InputError(f"frame must have shape {self.shape}, got {f.shape}")
        j = self.frame_index
        self.frame_index += 1
        t = float(j) * DEFAULT_FRAME_INTERVAL_S if t_s is None else float(t_s)
        cls, stats = self._classify(f, t)
        self.classes.append(cls)
        row = (*stats, t) if stats else ()
        if self._t_first is None:
            self._t_first = t
        elif self._dt is None:
            self._dt = t - self._t_first
        k_contact, k_none = debounce_counts(self.config, self._dt)
        if cls == ContactClass.INDETERMINATE:
            return []
        before = len(self._state.events)
        if cls == self._accepted:
            self._candidate, self._cand_frames, self._cand_rows = None, [], []
            if cls != ContactClass.NONE:
                self._append(j, row)
                if self._seg_n % max(self.evaluate_every, self._seg_n // 32) == 0:
                    self._flush()
        else:
            if cls != self._candidate:
                self._candidate, self._cand_frames, self._cand_rows = cls, [], []
            self._cand_frames.append(j)
            self._cand_rows.append(row)
            if len(self._cand_frames) < (k_none if cls == ContactClass.NONE else k_contact):
                return []
            self._flush()  # the open segment ends: its last motion tactemes first
            self._accepted = cls
            self._seg_n = 0
            if cls != ContactClass.NONE:
                for jj, rr in zip(self._cand_frames, self._cand_rows, strict=True):
                    self._append(jj, rr)
            self._candidate, self._cand_frames, self._cand_rows = None, [], []
            track = self._track() if cls != ContactClass.NONE else None
            self._state.open_run(cls, j, track)
        return self._state.events[before:]

    def _append(self, j: int, row: tuple[float, ...]) -> None:
        if self._seg_n == self._seg_idx.size:  # grow by doubling
            self._seg_idx = np.concatenate([self._seg_idx, np.empty_like(self._seg_idx)])
            self._seg_rows = np.concatenate([self._seg_rows, np.empty_like(self._seg_rows)])
        self._seg_idx[self._seg_n] = j
        self._seg_rows[self._seg_n] = row
        self._seg_n += 1

    def _flush(self) -> None:
        if self._accepted != ContactClass.NONE and self._seg_n:
            self._state.update(self._track())

    def _track(self) -> SegmentTrack:
        n = self._seg_n
        r = self._seg_rows[:n]
        return SegmentTrack(
            self._seg_idx[:n].copy(), r[:, 0:2], r[:, 2], r[:, 3], r[:, 4], r[:, 5], r[:, 8],
            r[:, 6:8],
        )  # fmt: skip

    def result(self) -> Recognition:
        """Everything so far as a :class:`Recognition` (pending detections included)."""
        self._flush()
        return _finish(np.asarray(self.classes, dtype=np.int8), list(self._state.events))
