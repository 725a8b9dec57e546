"""The pivot of a turning line, streamed: the twin of the batch rules' pivot verdicts.

:class:`PivotRun` keeps the least-squares sums of
:func:`~taxelkit.smart.pivots.pivot_fit` from one anchor on and runs the three
pivot verdicts of :func:`~taxelkit.smart.tactemes.segment_tactemes` ("spins",
"about one end", "in an arc") on frames as they arrive, with the same floats
as the batch path; each verdict is looked for until it is found.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.pivot_limits import (
    arc_limit_turn_deg,
    arc_ratio_limit,
    pivot_lower,
    pivot_upper,
)
from taxelkit.smart.pivots import pivot_from_sums, pressed_half_mm, trailing_mean
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.track_stream import RunningSum, drawn_length_mm, turn_from
from taxelkit.smart.verdict_holds import Sustained

__all__ = ["LinePivot", "PivotRun"]

#: Frames of a line that has not turned (yet) kept back from its pivot's sums: they
#: are only read once it turns, and a run that re-anchors first drops them.
KEPT_ROWS = 512


class PivotRun:
    """The pivot of a turning line from one anchor on: least-squares sums, three verdicts.

    Frames before the anchor's reference (its first full window) wait in
    ``pending`` for it.

    Parameters
    ----------
    start : int
        Segment index of the anchor.
    hold : int
        Frames a verdict must hold.
    arc_w : int
        Lines whose mean middle "in an arc" reads (1: the current line's).
    every : bool
        Look for every verdict until it is found (False: stop at the first,
        :attr:`~taxelkit.smart.tactemes.TactemeConfig.pivot_every_verdict`).
    arc_max_turn : bool
        "In an arc" reads its limit at the largest turn so far
        (:attr:`~taxelkit.smart.tactemes.TactemeConfig.pivot_arc_max_turn`).
    pressed : bool
        Ratios in the pressed lines' half-lengths
        (:attr:`~taxelkit.smart.tactemes.TactemeConfig.pivot_pressed_half`).
    spans : bool
        A verdict holds over the frames of the recording it spans
        (:attr:`~taxelkit.smart.tactemes.TactemeConfig.hold_spans_gaps`), on
        at least ``min_rows`` of the segment's frames.
    min_rows : int
    gap : int
        Rows where a verdict does not read, between two where it does, that
        it holds through (:class:`~taxelkit.smart.verdict_holds.Sustained`,
        :attr:`~taxelkit.smart.tactemes.TactemeConfig.pivot_gap_s`).
    """

    def __init__(
        self,
        start: int,
        hold: int,
        arc_w: int = 1,
        every: bool = True,
        arc_max_turn: bool = False,
        pressed: bool = False,
        spans: bool = False,
        min_rows: int = 1,
        gap: int = 0,
    ) -> None:
        self.start = start  # segment index of the anchor
        self.every = every
        self.arc_max_turn = arc_max_turn
        self.pressed = pressed
        self.sums = RunningSum(7)  # sxx, sxy, syy, bx, by, half, dd: column by column
        self.count = 0
        self.arc_w = arc_w
        self.tail = np.empty((0, 2))  # the last arc_w - 1 line middles, mm
        self.ref_angle: float | None = None
        # (ratios, their errors, the arc's ratios, angles, frames, drawn line lengths in mm)
        # awaiting their reference angle
        self.pending: list[
            tuple[
                NDArray[np.float64],
                NDArray[np.float64],
                NDArray[np.float64],
                NDArray[np.float64],
                NDArray[np.intp],
                NDArray[np.float64],
            ]
        ] = []
        # spins, about one end, in an arc: "about one end", the verdict that names a
        # cone, holds on the segment's own rows
        self.verdicts = [Sustained(hold, flag, min_rows, gap) for flag in (spans, False, spans)]
        self.gap = gap
        self.max_turn = 0.0  # the largest turn from the reference so far, deg
        # (frame, tacteme) of each verdict sustained so far, in the order found
        self.found: list[tuple[int, Tacteme]] = []

    @property
    def complete(self) -> bool:
        """Every verdict looked for has been found: later frames change nothing."""
        if not self.every:
            return bool(self.found)
        return all(s.found is not None for s in self.verdicts)

    def ratios(
        self, rows: NDArray[np.float64]
    ) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """:func:`~taxelkit.smart.pivot_rules._pivot_ratios` continued over ``rows``.

        Returns the ratio, its error and the arc's ratio (from the mean middle
        of the last ``arc_w`` lines).
        """
        # the arithmetic of _pivot_ratios, column by column (the same floats, fewer temporaries)
        m = rows.shape[0]
        lo, hi = rows[:, 6], rows[:, 7]
        measured = np.isfinite(lo) & np.isfinite(hi)
        t = np.deg2rad(rows[:, 2])
        cos, sin = np.cos(t), np.sin(t)
        offset = 0.5 * (lo + hi)
        cx = np.where(measured, rows[:, 0] + offset * cos, rows[:, 0])
        cy = np.where(measured, rows[:, 1] + offset * sin, rows[:, 1])
        nx = -sin
        d = nx * cx + cos * cy
        terms = np.empty((m, 7))
        np.multiply(nx, nx, out=terms[:, 0])
        np.multiply(nx, cos, out=terms[:, 1])
        np.multiply(cos, cos, out=terms[:, 2])
        np.multiply(nx, d, out=terms[:, 3])
        np.multiply(cos, d, out=terms[:, 4])
        drawn = np.where(measured, 0.5 * (hi - lo), rows[:, 5])  # drawn_half_mm
        terms[:, 5] = pressed_half_mm(drawn, rows[:, 3]) if self.pressed else drawn
        np.multiply(d, d, out=terms[:, 6])
        sums = self.sums.push(terms)
        ratio, error = pivot_from_sums(sums, self.count, cx, cy)
        self.count += m
        if self.arc_w <= 1:
            return ratio, error, ratio
        middle = np.stack([cx, cy], axis=-1)
        mean = trailing_mean(middle, self.arc_w, self.tail)
        self.tail = np.concatenate([self.tail, middle])[-(self.arc_w - 1) :]
        return ratio, error, pivot_from_sums(sums, self.count - m, mean[:, 0], mean[:, 1])[0]

    def decide(
        self,
        min_ratio: float,
        end_lo: float,
        end_ratio: float,
        band: float,
        turn_deg: float,
        arc_turn_deg: float,
        pitch_mm: float = 0.0,
        min_line_mm: float = 0.0,
        end_sigmas: float = 0.0,
        arc_sigmas: float = 0.0,
    ) -> None:
        """Run the three verdicts over the pending frames (their reference angle is known).

        Spins below ``min_ratio`` half-lengths and about one end up to
        ``end_lo`` (the ratio plus ``end_sigmas`` times its error,
        :func:`~taxelkit.smart.pivot_limits.pivot_upper`), on frames turned
        more than ``turn_deg`` from the reference; in an arc from
        :func:`~taxelkit.smart.pivot_limits.arc_ratio_limit` of the turn
        (the arc's ratio less ``arc_sigmas`` times the error,
        :func:`~taxelkit.smart.pivot_limits.pivot_lower`);
        no verdict on lines drawn shorter than ``min_line_mm``; with
        ``arc_max_turn`` (the run's) the arc's limit reads the largest turn so far where
        the grid allows (:func:`~taxelkit.smart.pivot_limits.arc_limit_turn_deg`,
        :attr:`~taxelkit.smart.tactemes.TactemeConfig.pivot_arc_max_turn`). Each verdict
        is looked for until it is found (all three may be), as
        :func:`~taxelkit.smart.pivot_rules.pivot_tacteme` does.
        """
        for ratio, error, arc_ratio, angle, frames, line_mm in self.pending:
            if self.complete:
                break
            if frames.size == 0:
                continue
            assert self.ref_angle is not None
            turned = turn_from(angle, self.ref_angle)
            arc_turned = turned
            if self.arc_max_turn:
                largest = np.maximum.accumulate(np.maximum(turned, self.max_turn))
                self.max_turn = float(largest[-1])
                arc_turned = arc_limit_turn_deg(turned, largest, line_mm, pitch_mm, turn_deg)
            short = line_mm < min_line_mm
            ratio = np.where(short, np.nan, ratio)
            ready = turned > turn_deg
            arc_low = pivot_lower(arc_ratio, error, arc_sigmas)
            arc = np.where(short, np.nan, arc_low) >= arc_ratio_limit(
                arc_turned, end_ratio, band, turn_deg, arc_turn_deg, line_mm, pitch_mm
            )
            if not (ready.any() or arc.any()) and self.gap == 0:  # no verdict holds here
                for s in self.verdicts:
                    s.reset()
                continue
            verdicts = (
                (Tacteme.LC_SPINS, ready & (ratio < min_ratio)),
                (
                    Tacteme.LCMT_ABOUT_END,
                    ready
                    & (ratio >= min_ratio)
                    & (pivot_upper(ratio, error, end_sigmas) <= end_lo),
                ),
                (Tacteme.LCMT_ARC, arc),
            )
            hits = []
            for s, (tac, verdict) in zip(self.verdicts, verdicts, strict=True):
                if s.found is not None:  # found before: its frame is emitted already
                    continue
                f = s.push(verdict, frames)
                if f is not None:
                    hits.append((f, tac))
            self.found += sorted(hits, key=lambda hit: hit[0])
            if not self.every:
                self.found = self.found[:1]
        self.pending = []


class LinePivot:
    """The pivot runs of one streamed line segment: a :class:`PivotRun` from each anchor.

    Until the line turns (LCMT), a re-anchor starts a new run and the frames
    wait (at most :data:`KEPT_ROWS` of them) outside the run's sums, which
    only the turn reads; the sums continue in the same order whatever the
    pieces, so the verdicts are those of feeding every frame at once.

    Parameters
    ----------
    w : int
        Smoothing window, frames (an anchor's reference is its frame ``w - 1``).
    hold : int
        Frames a pivot verdict must hold.
    limits : tuple
        The arguments of :meth:`PivotRun.decide`.
    arc_w : int
        Lines whose mean middle "in an arc" reads (:class:`PivotRun`).
    every : bool
        Every verdict, or only the first (:class:`PivotRun`).
    arc_max_turn : bool
        The arc's limit at the largest turn so far (:class:`PivotRun`).
    pressed : bool
        Ratios in the pressed lines' half-lengths (:class:`PivotRun`).
    spans : bool
        Verdicts hold over the recording's frames (:class:`PivotRun`).
    min_rows : int
        Rows a verdict must hold on, with ``spans`` (:class:`PivotRun`).
    gap : int
        Rows a verdict holds through (:class:`PivotRun`).
    """

    def __init__(
        self,
        w: int,
        hold: int,
        limits: tuple[float, ...],
        arc_w: int = 1,
        every: bool = True,
        arc_max_turn: bool = False,
        pressed: bool = False,
        spans: bool = False,
        min_rows: int = 1,
        gap: int = 0,
    ) -> None:
        self.w, self.hold, self.limits, self.arc_w = w, hold, limits, arc_w
        self.gap = gap
        self.every, self.arc_max_turn, self.pressed = every, arc_max_turn, pressed
        self.spans, self.min_rows = spans, min_rows
        self.run: PivotRun | None = None
        self._kept: list[tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]] = []
        self._kept_n = 0

    @property
    def waiting(self) -> bool:
        """A verdict waits for the run's reference angle (see :meth:`close`)."""
        run = self.run
        return run is not None and not run.complete and run.ref_angle is None and bool(run.pending)

    def close(self, last_angle: float) -> None:
        """The segment ended: the waiting frames are judged against ``last_angle``."""
        if self.run is not None:
            self.run.ref_angle = last_angle
            self.run.decide(*self.limits)

    def push(
        self,
        stretches: list[tuple[int, int, int]],
        j: NDArray[np.intp],
        frames: NDArray[np.intp],
        rows: NDArray[np.float64],
        angle: NDArray[np.float64],
        turned: bool,
        turn_seg: int | None,
    ) -> None:
        """A chunk's rows ``lo..hi - 1`` of each stretch ``(lo, hi, anchor)``.

        ``j``: their segment indices; ``angle``: their smoothed axes, deg;
        ``turned``: the line has turned, at segment index ``turn_seg``.
        """
        for lo, hi, a in stretches:
            run = self.run
            if run is None or (run.start != a and (turn_seg is None or a <= turn_seg)):
                run = self.run = PivotRun(
                    a,
                    self.hold,
                    self.arc_w,
                    self.every,
                    self.arc_max_turn,
                    self.pressed,
                    self.spans,
                    self.min_rows,
                    self.gap,
                )
                self._kept, self._kept_n = [], 0
            if run.complete:
                continue
            r = run.start + self.w - 1
            if run.ref_angle is None and int(j[lo]) <= r < int(j[hi - 1]) + 1:
                run.ref_angle = float(angle[lo + r - int(j[lo])])
            self._kept.append((rows[lo:hi].copy(), angle[lo:hi].copy(), frames[lo:hi].copy()))
            self._kept_n += hi - lo
            if turned or self._kept_n > KEPT_ROWS:
                self._feed(run)

    def _feed(self, run: PivotRun) -> None:
        """The kept frames through the run's sums, then its verdicts (reference known).

        The kept pieces go through as one (the sums, the trailing means and
        the verdicts' runs continue across pieces: the same floats).
        """
        kept = self._kept
        if len(kept) > 1:
            rows_k, angle_k, frames_k = (np.concatenate(p) for p in zip(*kept, strict=True))
            kept = [(rows_k, angle_k, frames_k)]
        for rows, angle, frames in kept:
            ratio, error, arc = run.ratios(rows)
            run.pending.append((ratio, error, arc, angle, frames, drawn_length_mm(rows)))
        self._kept, self._kept_n = [], 0
        if run.ref_angle is not None:
            run.decide(*self.limits)
