"""Level 3 of one open segment, fed a chunk at a time (the streaming twin of ``segment_tactemes``).

:func:`~taxelkit.smart.tactemes.segment_tactemes` looks at a whole segment;
streamed, a segment held for an hour would be looked at over and over, each
look costing its length. :class:`SegmentScanner` carries the state of every
rule across chunks instead (rolling sums, the current anchor and its
reference, run lengths of the sustained motions, the pivot's least-squares
sums, the point's path scans), so a chunk costs the same at any age of the
segment and the memory does not grow with it. Every tacteme is reported with
the frame :func:`~taxelkit.smart.tactemes.segment_tactemes` gives it on the
whole segment, as soon as it is decided:

* a motion is decided on the frame it is seen (the rules are causal);
* "LC slides" and "LCMP" are decided when seen (a later LCM or LCMT cannot
  come first);
* the pivot of a turning line compares each line with the one at its
  anchor's first full window, up to ``w - 1`` frames after the anchor: frames
  before it wait for it (or, if the segment ends first, for its last frame,
  as the batch does).

Only the first frames (``max(k, edge_hold)``, for the transitions of Level 3)
and the last ``w`` running sums are kept.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.face_shapes import face_limits, face_masks, triangularity
from taxelkit.smart.pivot_stream import LinePivot
from taxelkit.smart.segment_head import ROW_COLUMNS, SegmentHead, SlipInputs, rows_from_track
from taxelkit.smart.tacteme_config import TactemeConfig
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.tactemes import MOTION_MIN_FRAMES
from taxelkit.smart.track_geometry import axis_angle_deg, axis_vectors
from taxelkit.smart.track_stream import (
    CarriedShift,
    CornerScan,
    LegScan,
    RollingMean,
    Sustained,
    mean_axis_deg,
    turn_from,
)
from taxelkit.smart.verdict_holds import gap_rows

__all__ = ["ROW_COLUMNS", "SegmentScanner", "mean_axis_deg", "rows_from_track"]

#: An anchor's reference: smoothed centre, axis, area, elongation and half-length there.
_Ref = tuple[NDArray[np.float64], float, Any, Any, Any]

_POINT, _LINE, _AREA = int(ContactClass.POINT), int(ContactClass.LINE), int(ContactClass.AREA)


class SegmentScanner(SegmentHead):
    """Motion tactemes of one open segment, computed incrementally.

    Parameters
    ----------
    cls : int
        The segment's :class:`~taxelkit.smart.contact_classes.ContactClass`.
    config : TactemeConfig
    pitch_mm : float
        Taxel pitch, mm (0: unknown), as :attr:`SegmentTrack.pitch_mm`.

    Examples
    --------
    >>> import numpy as np
    >>> from taxelkit.smart.tactemes import TactemeConfig
    >>> from taxelkit.smart.contact_classes import ContactClass
    >>> scan = SegmentScanner(ContactClass.POINT, TactemeConfig())
    >>> rows = np.zeros((100, 9)); rows[:, 3] = rows[:, 4] = 1.0  # 100 frames at 20 Hz
    >>> rows[:, 0] = np.linspace(0, 5, 100); rows[:, 8] = np.arange(100) / 20
    >>> [(t.value, f) for t, f in scan.extend(np.arange(100), rows)]
    [('PC moves', 44)]
    """

    def __init__(self, cls: int, config: TactemeConfig, pitch_mm: float = 0.0) -> None:
        super().__init__(cls, config, pitch_mm)
        self._early: list[tuple[NDArray[np.intp], NDArray[np.float64], NDArray[np.float64]]] = []
        self._ready = False

    # -- feeding --------------------------------------------------------------------------------
    def extend(
        self,
        frames: NDArray[np.intp],
        rows: NDArray[np.float64],
        *,
        slip: SlipInputs | None = None,
    ) -> list[tuple[Tacteme, int]]:
        """Add frames ``(m,)`` with their rows ``(m, 9)`` (:data:`ROW_COLUMNS`).

        ``slip``: the slip scanner's features and first decisions of these
        frames, computed already (for many segments at once,
        :func:`~taxelkit.smart.bank_slips.slip_inputs`).

        Returns
        -------
        list of (Tacteme, frame)
            Tactemes decided by these frames, in order of frame.
        """
        m = int(frames.size)
        if m == 0:
            return []
        if self.first_frame < 0:
            self.first_frame = int(frames[0])
        self.last_frame = int(frames[-1])
        if self._slip is not None:
            if slip is None:
                self._slip.extend(frames, rows)
            else:
                self._slip.extend(frames, rows, features=slip[0], decided=slip[1])
        axes = axis_vectors(rows[:, 2])  # (m, 2): for the mean axis and the smoothing
        self._axis_sum.push(axes)
        cap = self._head_cap
        # before the rate is fixed, only the frames that fix it (then the cap is known)
        self._keep_head(frames, rows, max(2, self.k) if cap is None else cap, 0)
        self._watch(frames, rows)
        self.size += m
        if not self._ready:
            self._early.append((frames, rows, axes))
            if self.size < max(2, self.k):
                return []
            self._start()
            frames = np.concatenate([f for f, _, _ in self._early])
            rows = np.concatenate([r for _, r, _ in self._early])
            axes = np.concatenate([a for _, _, a in self._early])
            self._early = []
            assert self._head_cap is not None
            self._keep_head(frames, rows, self._head_cap, self._head_n)
        return self._scan(frames, rows, axes, self.size - frames.size)

    @property
    def waiting(self) -> bool:
        """Whether :meth:`close` would decide something (a pivot waits for its reference)."""
        if not self._ready or self.cls != _LINE or self._j_turn is None:
            return False
        return self._piv.waiting

    def close(self) -> list[tuple[Tacteme, int]]:
        """The segment ended: decide what waited for frames that will not come."""
        if not self.waiting:
            return []
        self._piv.close(self._last_angle)  # the batch's reference: the last frame
        new = self._emit_pivot([])
        self.found += new
        return new

    def _start(self) -> None:
        cfg, k = self.config, self.k
        self._ready = True
        self.w = self.frames_for(cfg.smooth_s, k)
        self.hold = self.frames_for(cfg.motion_hold_s, k, minimum=MOTION_MIN_FRAMES)
        self.pivot_hold = self.frames_for(cfg.pivot_hold_s, k, minimum=self.hold)
        self._arc_w = self.w if cfg.pivot_arc_smooth else 1
        self._head_cap = max(k, self.frames_for(cfg.edge_hold_s, k))
        self._cut_head(self._head_cap)
        w = self.w
        self._smooth = RollingMean(w, 7)  # centre x, y, axis vector, area, elongation, half
        self._anchor = 0
        self._ref: _Ref | None = None
        self._start_angle: float | None = None  # a line's turn counts from frame w - 1
        self._rolled = CarriedShift()  # a line's roll across itself, over re-anchors
        limits = (
            cfg.pivot_min_ratio,
            cfg.pivot_end_ratio / cfg.pivot_band,
            cfg.pivot_end_ratio,
            cfg.pivot_band,
            cfg.pivot_turn_deg,
            cfg.pivot_arc_turn_deg,
            self.pitch_mm,
            cfg.pivot_min_line_taxels * self.pitch_mm,
            cfg.pivot_end_sigmas,
            cfg.pivot_arc_sigmas,
        )
        self._last_angle = float("nan")
        self._done: set[Tacteme] = set()
        spans = cfg.hold_spans_gaps
        hold = self.hold
        new = [Sustained(hold, spans, hold) for _ in range(4)]
        new[2] = Sustained(self.frames_for(cfg.parallel_hold_s, k, minimum=hold), spans, hold)
        self._s1, self._s2, self._s3, self._s4 = new
        face_hold = self.frames_for(cfg.face_hold_s, k, minimum=hold)
        self._faces = [Sustained(face_hold, spans, hold) for _ in range(4)]  # face-shape classes
        self._tau = RollingMean(w, 1)
        window = (cfg.orthogonal_min_deg, cfg.orthogonal_max_deg)
        self._legs, self._corners = (
            LegScan(cfg.turn_leg_mm, window),
            CornerScan(cfg.turn_leg_mm, window, cfg.corner_step_mm),
        )
        self._turn_pt: int | None = None
        self._slide_decided = self._par_decided = False
        self._j_turn: int | None = None  # frame of LCMT
        self._j_turn_seg: int | None = None
        self._piv = LinePivot(
            w,
            self.pivot_hold,
            limits,
            self._arc_w,
            cfg.pivot_every_verdict,
            cfg.pivot_arc_max_turn,
            cfg.pivot_pressed_half,
            spans,
            self.hold,
            gap_rows(self.frame_interval_s(k), cfg.pivot_gap_s),
        )

    def _anchors(
        self,
        j: NDArray[np.intp],
        area: NDArray[np.float64],
        elong: NDArray[np.float64],
        centre: NDArray[np.float64],
        angle: NDArray[np.float64],
        half: NDArray[np.float64],
    ) -> list[tuple[int, int, int, _Ref | None]]:
        """Pieces ``(lo, hi, anchor, reference)`` of the chunk (reference None until reached)."""
        m, n0, w, step = j.size, int(j[0]), self.w, self.config.area_step
        out: list[tuple[int, int, int, _Ref | None]] = []
        pos = 0
        while pos < m:
            r = self._anchor + w - 1
            if n0 + pos <= r:  # up to the reference: no test
                hi = min(m, r - n0 + 1)
                if r - n0 < m:
                    q = r - n0
                    self._ref = (centre[q], float(angle[q]), area[q], elong[q], half[q])
                out.append((pos, hi, self._anchor, self._ref if r - n0 < m else None))
                pos = hi
                continue
            hit = None
            if self.cls != _POINT:
                assert self._ref is not None
                dev = np.abs(area[pos:] / self._ref[2] - 1.0) > step
                if self.cls == _AREA:
                    dev |= np.abs(elong[pos:] / self._ref[3] - 1.0) > step
                hits = np.flatnonzero(dev)
                hit = None if hits.size == 0 else pos + int(hits[0])
            if hit is None:
                out.append((pos, m, self._anchor, self._ref))
                pos = m
            else:
                if hit > pos:  # no empty piece when the chunk's first frame re-anchors
                    out.append((pos, hit, self._anchor, self._ref))
                self._anchor, pos = n0 + hit, hit
        return out

    def _scan(
        self,
        frames: NDArray[np.intp],
        rows: NDArray[np.float64],
        axes: NDArray[np.float64],
        n0: int,
    ) -> list[tuple[Tacteme, int]]:
        cfg, w, cls = self.config, self.w, self.cls
        j = n0 + np.arange(frames.size)
        raw = np.empty((rows.shape[0], 7))
        raw[:, 0:2] = rows[:, 0:2]
        raw[:, 2:4] = axes
        raw[:, 4:7] = rows[:, 3:6]
        smooth = self._smooth.push(raw)  # column by column: the batch's rolling means
        centre = smooth[:, 0:2]
        angle = axis_angle_deg(smooth[:, 2:4])
        area = smooth[:, 4]
        elong = smooth[:, 5] if cls == _AREA else rows[:, 4]
        half = smooth[:, 6] if cls == _LINE else rows[:, 5]
        self._last_angle = float(angle[-1])
        pieces = self._anchors(j, area, elong, centre, angle, half)
        valid, (rc, ra, rarea, relong, rhalf) = self._references(
            pieces, j, centre, angle, area, elong, half
        )
        shift = centre - rc
        new: list[tuple[Tacteme, int]] = []
        if cls == _POINT:
            moved = np.where(valid, np.hypot(*shift.T), 0.0)
            j_move = self._s1.push(moved > cfg.move_mm, frames)
            if self._turn_pt is None:  # the path's scans run from frame w - 1 on
                path = j >= w - 1
                found = [
                    self._legs.push(centre[path], frames[path]),
                    self._corners.push(centre[path], frames[path]),
                ]
                hits = [f for f in found if f is not None]
                self._turn_pt = min(hits) if hits else None
            self._add(new, Tacteme.PC_MOVES, j_move)
            if j_move is not None:
                self._add(new, Tacteme.PC_ORTHOGONAL_TURN, self._turn_pt)
        elif cls == _LINE:
            t_ref = np.deg2rad(ra)
            along = np.abs(shift[:, 0] * np.cos(t_ref) + shift[:, 1] * np.sin(t_ref))
            ends = along - np.abs(half - rhalf)
            across = np.where(
                valid, np.abs(-shift[:, 0] * np.sin(t_ref) + shift[:, 1] * np.cos(t_ref)), 0.0
            )
            j_lcm = self._s1.push(across > cfg.move_mm, frames)
            slid = valid & (ends > cfg.move_mm) & (across < 0.5 * cfg.move_mm)
            j_slide = self._s2.push(slid, frames)
            if not self._slide_decided and (j_slide is not None or j_lcm is not None):
                self._slide_decided = True
                if j_slide is not None and (j_lcm is None or j_slide < j_lcm):
                    self._add(new, Tacteme.LC_SLIDES, j_slide)
            self._add(new, Tacteme.LCM, j_lcm)
            at = j >= w - 1
            if self._start_angle is None and np.any(at):
                self._start_angle = float(angle[int(np.argmax(at))])
            turned_all = np.where(
                at,
                turn_from(angle, self._start_angle if self._start_angle is not None else 0.0),
                0.0,
            )
            # rolled across, summed over re-anchors, on the normal of the first reference
            stretches = [(lo, hi, a, None if r is None else r[0]) for lo, hi, a, r in pieces]
            rolled = self._rolled.before(stretches, centre) + shift
            t0 = np.deg2rad(self._start_angle if self._start_angle is not None else 0.0)
            across_all = np.abs(-rolled[:, 0] * np.sin(t0) + rolled[:, 1] * np.cos(t0))
            parallel = (across_all >= cfg.parallel_move_mm) & (
                turned_all <= cfg.parallel_limit_deg(across_all)
            )
            j_par = self._s3.push(parallel, frames)
            j_turn = self._s4.push(turned_all > cfg.turn_deg, frames)
            if not self._par_decided and (j_par is not None or j_turn is not None):
                self._par_decided = True
                if j_par is not None and (j_turn is None or j_par < j_turn):
                    self._add(new, Tacteme.LCMP, j_par)
            if j_turn is not None and self._j_turn is None:
                self._j_turn = j_turn
                self._j_turn_seg = int(j[int(np.searchsorted(frames, j_turn))])
            self._add(new, Tacteme.LCMT, self._j_turn)
            self._pivots(pieces, j, frames, rows, angle)
            self._emit_pivot(new)
        else:
            same = np.abs(area / rarea - 1.0) <= cfg.area_tolerance
            moved = np.where(valid, np.hypot(*shift.T), 0.0)
            self._add(new, Tacteme.AC_MOVES, self._s1.push((moved > cfg.move_mm) & same, frames))
            oriented = (elong >= cfg.area_min_elongation) & (relong >= cfg.area_min_elongation)
            turned = np.where(valid, turn_from(angle, ra), 0.0)
            rotated = (turned > cfg.area_rotate_deg) & same & oriented
            self._add(new, Tacteme.AC_ROTATES, self._s2.push(rotated, frames))
            if cfg.face_shapes:
                tau = self._tau.push(triangularity(rows[:, 3], rows[:, 4], rows[:, 5])[:, None])
                masks = face_masks(area, elong, tau[:, 0], valid & same, **face_limits(cfg))
                for run, (tac, mask) in zip(self._faces, masks, strict=True):
                    self._add(new, tac, run.push(mask, frames))
        new.sort(key=lambda item: item[1])
        self.found += new
        return new

    def _references(
        self,
        pieces: list[tuple[int, int, int, _Ref | None]],
        j: NDArray[np.intp],
        centre: NDArray[np.float64],
        angle: NDArray[np.float64],
        area: NDArray[np.float64],
        elong: NDArray[np.float64],
        half: NDArray[np.float64],
    ) -> tuple[NDArray[np.bool_], tuple[Any, Any, Any, Any, Any]]:
        """Rows past their anchor's reference, and each row's reference (its own values if not).

        One piece past its reference (a chunk that does not re-anchor): the
        reference's values, broadcast (the same floats in every expression).
        """
        w = self.w
        if len(pieces) == 1:
            _, _, a, ref = pieces[0]
            if ref is not None and int(j[0]) >= a + w - 1:
                return np.ones(j.size, bool), ref
        valid = np.zeros(j.size, bool)
        rc, ra, rarea, relong, rhalf = (
            centre.copy(),
            angle.copy(),
            area.copy(),
            elong.copy(),
            half.copy(),
        )
        n0 = int(j[0])  # j counts on from n0
        for lo, hi, a, ref in pieces:
            first = max(lo, a + w - 1 - n0)  # the piece's rows from its reference on
            if first < hi:
                assert ref is not None
                valid[first:hi] = True
                rc[first:hi], ra[first:hi], rarea[first:hi] = ref[0], ref[1], ref[2]
                relong[first:hi], rhalf[first:hi] = ref[3], ref[4]
        return valid, (rc, ra, rarea, relong, rhalf)

    def _add(self, new: list[tuple[Tacteme, int]], tac: Tacteme, frame: int | None) -> None:
        if frame is not None and tac not in self._done:
            self._done.add(tac)
            new.append((tac, frame))

    # -- the pivot of a turning line ------------------------------------------------------
    def _pivots(
        self,
        pieces: list[tuple[int, int, int, _Ref | None]],
        j: NDArray[np.intp],
        frames: NDArray[np.intp],
        rows: NDArray[np.float64],
        angle: NDArray[np.float64],
    ) -> None:
        stretches = [(lo, hi, a) for lo, hi, a, _ in pieces]
        self._piv.push(
            stretches, j, frames, rows, angle, self._j_turn is not None, self._j_turn_seg
        )

    def _emit_pivot(self, new: list[tuple[Tacteme, int]]) -> list[tuple[Tacteme, int]]:
        piv = self._piv.run
        if self._j_turn is not None and piv is not None:
            for frame, tac in piv.found:  # each verdict once (_add), the run's in its order
                self._add(new, tac, frame)
        return new
