"""Level 3 of the smart sensor: debounced contact segments and the tactemes they produce.

Debounce (paper 001, Section 3, Level 3)
    A new contact class is accepted after it has been seen ``k`` times in a row
    (``k = 3`` in the paper); indeterminate images are skipped: they neither
    count nor break a run, and never start a tacteme. Shorter runs are
    spurious and ignored. Accepted runs of one class separated only by
    spurious images form one *segment*.

Tactemes of a segment (thresholds in :class:`TactemeConfig`, all on smoothed
values: the mean of the last ``k`` frames of the segment, against the mean of
its first ``k`` frames; like a class, a motion must hold for ``k`` frames in
a row, so the one-frame collapse of a contact that tips away is not motion)
    - PC, LC, AC: a point, line or area segment is accepted.
    - PC moves / LCM / AC moves: the centre of contact moves more than
      ``move_mm`` (a line: across itself, as a rolling line does); "AC moves"
      also needs the area to stay within ``area_tolerance`` (a sliding face
      keeps its footprint, a face tipping onto an edge shrinks).
    - LC slides along itself (beyond paper 001): both ends of the line move
      more than ``move_mm`` along it (the centre's shift along the line less
      the change of its half-length) and the centre less than half that across
      it, before any LCM: sliding, which no rolling object does.
    - PC takes an orthogonal turn: after moving, the point's path turns by
      60-120 deg, between legs of ``turn_leg_mm`` or at a corner between two
      straight chords of that length (the earlier of the two).
    - LCMP: the line has moved ``parallel_move_mm`` with its orientation
      within ``parallel_tol_deg`` of the segment's start (a tolerance that
      grows by ``parallel_tol_growth_deg_per_mm`` with the distance rolled
      beyond), for ``parallel_hold_s``.
    - LCMT: the line's orientation changes by more than ``turn_deg`` from the
      segment's start (orientation is not re-anchored: a line's width and
      length changes do not turn it); once it
      has turned ``pivot_turn_deg`` the least-squares common point of the
      lines seen so far (the pivot) is compared with the line: within
      ``pivot_end_ratio`` half-lengths of the line's centre it is "about one
      end" (a cone's apex), farther it is "in an arc" (a truncated cone's
      virtual apex), in half-lengths of the pressed line (the drawn one less
      the footprint's half-width at each end, ``pivot_pressed_half``); nearer
      than ``pivot_min_ratio`` half-lengths it is "LC spins about its middle"
      (beyond paper 001: a line spun in place).
      A pivot far beyond the line may be called "in an arc" from
      ``pivot_arc_turn_deg`` on, with a band that widens as the turn shrinks;
      "in an arc" reads the pivot's distance from the mean middle of the
      lines of the last ``smooth_s`` (``pivot_arc_smooth``). Every verdict
      sustained in the segment is emitted: a pivot read in two places
      (about one end, later in an arc) gives both.

    References re-anchor whenever the smoothed area differs from the area at
    the reference by more than ``area_step`` (see :class:`TactemeConfig`):
    a cumulative test, so it means the same at every frame rate.
    - AC rotates: the orientation of an elongated area turns by more than
      ``area_rotate_deg`` with its area unchanged.
    - LC -> AC, AC -> LC, and LC -> AC -> LC (:mod:`taxelkit.smart.transitions`)
      with the two lines parallel or at 90 deg (a square face) or at 60/120
      deg (a triangular face); the line must be a held edge (at least
      ``2 k`` frames) and the change direct (at most ``2 k`` frames between
      the segments). A round body's end face
      tipping onto its rim shrinks through a lens that reads as a line for a
      few frames, and its side reaches a face through a rim-point phase.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.face_shapes import face_limits, face_masks, triangularity
from taxelkit.smart.pivot_rules import pivot_tacteme
from taxelkit.smart.tacteme_config import (
    PAPER_LEVEL3,
    TactemeConfig,
    debounce_counts,
)
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.track_geometry import (
    anchors,
    axis_angle_deg,
    axis_vectors,
    carried_shift,
    corner_turn,
    first,
    orthogonal_turn,
    rolling_mean,
    sustained,
    turn,
)

__all__ = [
    "PAPER_LEVEL3",
    "SegmentTrack",
    "TactemeConfig",
    "accepted_runs",
    "debounce_counts",
    "frames_for_interval",
    "segment_tactemes",
]

_INDET = int(ContactClass.INDETERMINATE)
_NONE = int(ContactClass.NONE)
#: A motion must be seen on at least this many frames (a one-frame collapse is not motion).
MOTION_MIN_FRAMES = 2


def accepted_runs(
    classes: NDArray[np.integer], k: int, *, k_none: int | None = None
) -> list[tuple[int, int, NDArray[np.intp]]]:
    """Debounced segments of a whole class sequence, vectorised.

    Parameters
    ----------
    classes : (T,) int
        :class:`~taxelkit.smart.contact_classes.ContactClass` codes.
    k : int
        Debounce count.
    k_none : int, optional
        Debounce count of "no contact" (default ``k``).

    Returns
    -------
    list of (class, accept_frame, frames)
        In order: the accepted class, the frame at which it was accepted (its
        ``k``-th repetition) and the frames of that class that belong to the
        segment (spurious and indeterminate frames excluded): every later frame
        of the accepted class, however short its run, belongs to it, exactly
        as in the streaming form. The state before the first frame is "none".
    """
    c_all = np.asarray(classes)
    idx = np.flatnonzero(c_all != _INDET)
    c = c_all[idx]
    if c.size == 0:
        return []
    cut = np.flatnonzero(np.diff(c)) + 1
    starts = np.concatenate([[0], cut]).tolist()
    ends = np.concatenate([cut, [c.size]]).tolist()
    out: list[tuple[int, int, NDArray[np.intp]]] = []
    current = int(ContactClass.NONE)
    pending: list[NDArray[np.intp]] = []
    for s, e in zip(starts, ends, strict=True):  # one step per run of equal classes
        cls = int(c[s])
        if cls == current:  # the accepted class goes on, spurious runs between excluded
            if out:
                pending.append(idx[s:e])
        elif e - s >= (k_cls := k if cls != _NONE or k_none is None else k_none):
            if out and pending:  # a new class seen k times in a row: accepted
                prev_cls, prev_acc, _ = out[-1]
                out[-1] = (prev_cls, prev_acc, np.concatenate(pending))
            pending = [idx[s:e]]
            out.append((cls, int(idx[s + k_cls - 1]), idx[s:e]))
            current = cls
    if out and pending:
        prev_cls, prev_acc, _ = out[-1]
        out[-1] = (prev_cls, prev_acc, np.concatenate(pending))
    return out


def frames_for_interval(dt: float, seconds: float, floor: int) -> int:
    """Frames covering ``seconds`` at the frame interval ``dt`` (s), at least ``floor``.

    ``floor`` when the interval is unknown (``dt <= 0``); the time is rounded up,
    less 1e-9 frames so that a span of whole frames is not counted one over.
    """
    return max(floor, math.ceil(seconds / dt - 1e-9)) if dt > 0 else floor


@dataclass(frozen=True, eq=False)
class SegmentTrack:
    """Level 1 statistics of one segment's frames, in order.

    Attributes
    ----------
    frames : (n,) int
        Frame indices.
    centre_mm : (n, 2) float
    orientation_deg : (n,) float
    area_mm2 : (n,) float
    elongation : (n,) float
    half_length_mm : (n,) float
        ``sqrt(3 lambda_max)``: half the length of a uniform line with the
        contact's largest second moment.
    t_s : (n,) float, s
        Timestamps of the frames.
    extent_mm : (n, 2) float or None
        Where each line begins and ends along its axis, mm from its centre
        (:func:`~taxelkit.smart.line_extents.line_extents`; NaN where not
        measured). None: the line is taken as centred on its centre, with
        half-length ``half_length_mm``.
    pitch_mm : float
        Taxel pitch, mm (0: unknown); an early "in an arc" needs a turn beyond
        what the grid alone gives a line of that length.
    """

    frames: NDArray[np.intp]
    centre_mm: NDArray[np.float64]
    orientation_deg: NDArray[np.float64]
    area_mm2: NDArray[np.float64]
    elongation: NDArray[np.float64]
    half_length_mm: NDArray[np.float64]
    t_s: NDArray[np.float64]
    extent_mm: NDArray[np.float64] | None = None
    pitch_mm: float = 0.0

    def frame_interval_s(self, k: int) -> float:
        """Frame interval from the segment's first ``k`` frames (fixed once accepted), s."""
        head = self.t_s[: max(2, k)].tolist()  # a few numbers: plain Python is faster
        if len(head) < 2:
            return 1.0
        steps = sorted(b - a for a, b in itertools.pairwise(head))
        mid = len(steps) // 2
        return float(steps[mid] if len(steps) % 2 else 0.5 * (steps[mid - 1] + steps[mid]))

    def frames_for(self, seconds: float, k: int, *, minimum: int | None = None) -> int:
        """Frames covering ``seconds`` at this segment's rate, at least ``minimum`` (default k).

        The rate comes from the first ``k`` frames.
        """
        return frames_for_interval(
            self.frame_interval_s(k), seconds, k if minimum is None else minimum
        )


def _orthogonal_turn(centre: NDArray[np.float64], start: int, config: TactemeConfig) -> int | None:
    window = (config.orthogonal_min_deg, config.orthogonal_max_deg)
    return orthogonal_turn(centre, start, config.turn_leg_mm, window)


def _corner_turn(centre: NDArray[np.float64], start: int, config: TactemeConfig) -> int | None:
    window = (config.orthogonal_min_deg, config.orthogonal_max_deg)
    return corner_turn(centre, start, config.turn_leg_mm, window, config.corner_step_mm)


def _point_turn(centre: NDArray[np.float64], start: int, config: TactemeConfig) -> int | None:
    """First index at which a moving point's path turns (legs or a corner), from ``start``."""
    found = [
        j
        for j in (_orthogonal_turn(centre, start, config), _corner_turn(centre, start, config))
        if j is not None
    ]
    return min(found) if found else None


def _face_tactemes(
    track: SegmentTrack,
    config: TactemeConfig,
    area: NDArray[np.float64],
    elong: NDArray[np.float64],
    steady: NDArray[np.bool_],
    w: int,
    hold: int,
) -> list[tuple[Tacteme, int | None]]:
    """The face-shape tactemes of an area segment and the index each is seen at (or None)."""
    k = int(config.debounce_frames)
    raw = triangularity(track.area_mm2, track.elongation, track.half_length_mm)
    face_hold = track.frames_for(config.face_hold_s, k, minimum=hold)
    span = track.frames if config.hold_spans_gaps else None
    return [
        (tac, first(sustained(mask, face_hold, span, hold), 0))
        for tac, mask in face_masks(
            area, elong, rolling_mean(raw, w), steady, **face_limits(config)
        )
    ]


def segment_tactemes(
    cls: int, track: SegmentTrack, config: TactemeConfig
) -> list[tuple[Tacteme, int]]:
    """Motion tactemes of one segment and the frame at which each is seen.

    Parameters
    ----------
    cls : int
        The segment's contact class.
    track : SegmentTrack
        Its frames' statistics (the frames seen so far, for streaming).
    config : TactemeConfig

    Returns
    -------
    list of (Tacteme, frame)
        Each tacteme at most once, in order of frame.
    """
    k = int(config.debounce_frames)
    n = track.frames.size
    hold = track.frames_for(config.motion_hold_s, k, minimum=MOTION_MIN_FRAMES)
    if n < k or cls not in (ContactClass.POINT, ContactClass.LINE, ContactClass.AREA):
        return []
    w = track.frames_for(config.smooth_s, k)  # the smoothing window, in time
    centre = rolling_mean(track.centre_mm, w)
    axis = rolling_mean(axis_vectors(track.orientation_deg), w)
    angle = axis_angle_deg(axis)
    area = rolling_mean(track.area_mm2, w)
    elong = rolling_mean(track.elongation, w)
    if cls == ContactClass.POINT:
        anchor = np.zeros(n, dtype=np.intp)
    else:  # on the smoothed area: taxel flicker averages out
        # a line's elongation jumps with the grid (its width is a taxel or two): area only
        shape = elong if cls == ContactClass.AREA else np.ones_like(elong)
        anchor = anchors(area, shape, w, config.area_step)
    ref = np.minimum(anchor + w - 1, n - 1)  # first full window after the anchor
    valid = np.arange(n) >= anchor + w - 1
    shift = centre - centre[ref]
    moved = np.where(valid, np.hypot(*shift.T), 0.0)
    turned = np.where(valid, turn(angle, ref), 0.0)
    out: list[tuple[Tacteme, int]] = []
    span = track.frames if config.hold_spans_gaps else None  # holds in the recording's frames

    def held(mask: NDArray[np.bool_], k: int) -> int | None:
        """The first index where ``mask`` has held ``k`` frames (on ``hold`` rows at least)."""
        return first(sustained(mask, k, span, hold), 0)

    def emit(t: Tacteme, j: int | None) -> None:
        if j is not None:
            out.append((t, int(track.frames[j])))

    if cls == ContactClass.POINT:
        j_move = held(moved > config.move_mm, hold)
        emit(Tacteme.PC_MOVES, j_move)
        if j_move is not None:
            emit(Tacteme.PC_ORTHOGONAL_TURN, _point_turn(centre, int(ref[j_move]), config))
    elif cls == ContactClass.LINE:
        t_ref = np.deg2rad(angle[ref])
        along = np.abs(shift[:, 0] * np.cos(t_ref) + shift[:, 1] * np.sin(t_ref))
        # both ends must move along: a line that grows or shrinks moves its centre too
        half = rolling_mean(track.half_length_mm, w)
        ends = along - np.abs(half - half[ref])
        across = np.where(
            valid, np.abs(-shift[:, 0] * np.sin(t_ref) + shift[:, 1] * np.cos(t_ref)), 0.0
        )
        j_lcm = held(across > config.move_mm, hold)
        slid = valid & (ends > config.move_mm) & (across < 0.5 * config.move_mm)
        j_slide = held(slid, hold)
        if j_slide is not None and (j_lcm is None or j_slide < j_lcm):
            emit(Tacteme.LC_SLIDES, j_slide)
        emit(Tacteme.LCM, j_lcm)
        # a line's orientation does not suffer from the width and length changes that
        # re-anchor its centre: its turn counts from the segment's first reference
        start_ref = min(w - 1, n - 1)
        turned_all = np.where(np.arange(n) >= start_ref, turn(angle, np.full(n, start_ref)), 0.0)
        # rolled across, summed over re-anchors (a rolling line's area swings as it
        # crosses the rows), on the normal of the segment's first reference
        t0 = np.deg2rad(angle[start_ref])
        rolled = carried_shift(centre, anchor, ref)
        across_all = np.abs(-rolled[:, 0] * np.sin(t0) + rolled[:, 1] * np.cos(t0))
        parallel = (across_all >= config.parallel_move_mm) & (
            turned_all <= config.parallel_limit_deg(across_all)
        )
        par_hold = track.frames_for(config.parallel_hold_s, k, minimum=hold)
        j_par = held(parallel, par_hold)
        j_turn = held(turned_all > config.turn_deg, hold)
        if j_par is not None and (j_turn is None or j_par < j_turn):
            emit(Tacteme.LCMP, j_par)
        if j_turn is not None:
            emit(Tacteme.LCMT, j_turn)
            for j_pivot, tac in pivot_tacteme(track, config, angle, anchor, ref, j_turn, hold):
                emit(tac, j_pivot)
    else:
        same = np.abs(area / area[ref] - 1.0) <= config.area_tolerance
        emit(Tacteme.AC_MOVES, held((moved > config.move_mm) & same, hold))
        oriented = (elong >= config.area_min_elongation) & (
            elong[ref] >= config.area_min_elongation
        )
        rotated = (turned > config.area_rotate_deg) & same & oriented
        emit(Tacteme.AC_ROTATES, held(rotated, hold))
        if config.face_shapes:
            for tac, j in _face_tactemes(track, config, area, elong, valid & same, w, hold):
                emit(tac, j)
    out.sort(key=lambda item: item[1])
    return out
