"""Motion tactemes of many whole segments at once: the batch twin of ``segment_tactemes``.

:func:`~taxelkit.smart.tactemes.segment_tactemes` looks at one segment with
a few dozen NumPy calls on its frames; a recording (or a chunk of one) holds
hundreds of segments, most a few hundred frames long, so that the calls'
fixed cost dominates. :func:`batch_tactemes` lays the segments of one class
and one frame rate end to end (:class:`~taxelkit.smart.segment_runs.Runs`)
and applies the same rules to all of them at once: every value is computed
by the same floating-point operations as in the per-segment form (running
sums segment by segment, element-wise operations on the same operands), so
the tactemes and their frames are those of ``segment_tactemes`` (tested).
The rare, longer searches (a moving point's corners, a turning line's pivot,
a face's shape) run per segment on the segment's slice of the batch.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.gather import take_rows
from taxelkit.smart.pivot_rules import pivot_tacteme, pivot_verdicts
from taxelkit.smart.pivots import drawn_pivot_fit
from taxelkit.smart.segment_runs import Runs, run_anchors
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.tactemes import (
    MOTION_MIN_FRAMES,
    SegmentTrack,
    TactemeConfig,
    _face_tactemes,
    _point_turn,
    frames_for_interval,
)
from taxelkit.smart.track_geometry import axis_angle_deg, drawn_half_mm
from taxelkit.smart.verdict_holds import bridge_gaps, gap_rows

__all__ = ["batch_tactemes"]

_POINT, _LINE, _AREA = int(ContactClass.POINT), int(ContactClass.LINE), int(ContactClass.AREA)

Found = list[tuple[Tacteme, int]]
#: Rows (frames of all segments) computed together: the temporaries stay in the cache.
PIECE_ROWS = 16384
#: What a turning line's pivot may read (each that is sustained, at its first frame).
_PIVOT_TACTEMES = (Tacteme.LC_SPINS, Tacteme.LCMT_ABOUT_END, Tacteme.LCMT_ARC)


def batch_tactemes(items: Sequence[tuple[int, SegmentTrack]], config: TactemeConfig) -> list[Found]:
    """:func:`~taxelkit.smart.tactemes.segment_tactemes` of every ``(class, track)``.

    Parameters
    ----------
    items : sequence of (int, SegmentTrack)
        Each segment's contact class and track.
    config : TactemeConfig

    Returns
    -------
    list of list of (Tacteme, frame)
        For each item, what ``segment_tactemes(cls, track, config)`` returns.
    """
    k = int(config.debounce_frames)
    out: list[Found] = [[] for _ in items]
    groups: dict[tuple[int, int, int], list[int]] = {}
    for i, (cls, track) in enumerate(items):
        n = track.frames.size
        if n < k or cls not in (_POINT, _LINE, _AREA):
            continue
        dt = track.frame_interval_s(k)
        hold = frames_for_interval(dt, config.motion_hold_s, MOTION_MIN_FRAMES)
        w = frames_for_interval(dt, config.smooth_s, k)
        groups.setdefault((int(cls), w, hold), []).append(i)
    for (cls, w, hold), members in groups.items():
        for part in _pieces(members, [items[i][1].frames.size for i in members]):
            tracks = [items[i][1] for i in part]
            for i, found in zip(part, _group(cls, tracks, w, hold, config), strict=True):
                out[i] = found
    return out


def _pieces(members: list[int], sizes: list[int]) -> list[list[int]]:
    """``members`` cut into consecutive pieces of about :data:`PIECE_ROWS` rows."""
    out: list[list[int]] = [[]]
    rows = 0
    for i, size in zip(members, sizes, strict=True):
        if rows and rows + size > PIECE_ROWS:
            out.append([])
            rows = 0
        out[-1].append(i)
        rows += size
    return out


def _group(
    cls: int, tracks: list[SegmentTrack], w: int, hold: int, config: TactemeConfig
) -> list[Found]:
    """The tactemes of segments of one class, smoothing window ``w`` and hold ``hold``."""
    runs = Runs(np.array([t.frames.size for t in tracks], dtype=np.intp))
    s_n = len(tracks)
    starts, lengths, seg, local = runs.starts, runs.lengths, runs.seg, runs.local
    frames = np.concatenate([t.frames for t in tracks])
    span = frames if config.hold_spans_gaps else None  # holds in the recording's frames
    theta = np.concatenate([t.orientation_deg for t in tracks])
    # columns: centre x, y, axis vector, area, elongation, half-length; each class
    # smooths those its rules read (a point: its centre; a line: not its elongation).
    # Kept column by column (rows of the transpose): filled and smoothed contiguously.
    raw_t = np.zeros((7, runs.size))
    raw_t[0:2] = np.concatenate([t.centre_mm for t in tracks]).T
    used = [0, 1] if cls == _POINT else [0, 1, 2, 3, 4, 6 if cls == _LINE else 5]
    ext = None
    if cls != _POINT:
        t2 = np.deg2rad(2.0 * theta)  # axis_vectors, column by column
        raw_t[2], raw_t[3] = np.cos(t2), np.sin(t2)
        raw_t[4] = np.concatenate([t.area_mm2 for t in tracks])
    if cls == _AREA:
        raw_t[5] = np.concatenate([t.elongation for t in tracks])
    if cls == _LINE:
        raw_t[6] = np.concatenate([t.half_length_mm for t in tracks])
        if all(t.extent_mm is not None for t in tracks):
            ext = np.concatenate([t.extent_mm for t in tracks if t.extent_mm is not None])
    smooth_t = np.zeros_like(raw_t)
    smooth_t[used] = runs.rolling_mean(raw_t[used].T, w).T
    raw, smooth = raw_t.T, smooth_t.T  # (N, 7)
    centre = np.ascontiguousarray(smooth[:, 0:2])  # contiguous: its rows gathered fast
    angle = axis_angle_deg(smooth[:, 2:4])
    area, elong = smooth[:, 4], smooth[:, 5]
    if cls == _POINT:
        anchor = np.zeros(runs.size, np.intp)
    else:
        shape = elong if cls == _AREA else np.ones_like(elong)
        anchor = run_anchors(runs, area, shape, w, config.area_step)
    n_row = lengths[seg]
    ref = np.minimum(anchor + w - 1, n_row - 1)  # within the segment
    ref_g = starts[seg] + ref
    valid = local >= anchor + w - 1
    shift = centre - take_rows(centre, ref_g)
    moved = np.where(valid, np.hypot(*shift.T), 0.0)
    out: list[Found] = [[] for _ in range(s_n)]
    hits: list[tuple[Tacteme, NDArray[np.intp]]] = []
    if cls == _POINT:
        j_move = runs.first_sustained(moved > config.move_mm, hold, span, hold)
        hits.append((Tacteme.PC_MOVES, j_move))
        corner = np.full(s_n, -1, np.intp)
        for s in np.flatnonzero(j_move >= 0).tolist():
            a, b = int(starts[s]), int(starts[s] + lengths[s])
            j = _point_turn(centre[a:b], int(ref[a + int(j_move[s])]), config)
            if j is not None:
                corner[s] = j
        hits.append((Tacteme.PC_ORTHOGONAL_TURN, corner))
    elif cls == _LINE:
        hits += _line_hits(
            runs,
            tracks,
            config,
            smooth,
            shift,
            angle,
            anchor,
            ref,
            ref_g,
            valid,
            w,
            hold,
            raw,
            theta,
            ext,
            span,
        )
    else:
        turned = np.where(valid, _turn(angle, ref_g), 0.0)
        same = np.abs(area / area[ref_g] - 1.0) <= config.area_tolerance
        moves = runs.first_sustained((moved > config.move_mm) & same, hold, span, hold)
        hits.append((Tacteme.AC_MOVES, moves))
        oriented = (elong >= config.area_min_elongation) & (
            elong[ref_g] >= config.area_min_elongation
        )
        rotated = (turned > config.area_rotate_deg) & same & oriented
        hits.append((Tacteme.AC_ROTATES, runs.first_sustained(rotated, hold, span, hold)))
        if config.face_shapes:
            steady = valid & same
            for s, track in enumerate(tracks):
                a, b = int(starts[s]), int(starts[s] + lengths[s])
                faces = _face_tactemes(track, config, area[a:b], elong[a:b], steady[a:b], w, hold)
                out[s] += [(tac, int(track.frames[j])) for tac, j in faces if j is not None]
    firsts = starts.tolist()
    columns = [(tac, j.tolist()) for tac, j in hits]
    for s in range(s_n):
        found = [(tac, int(frames[firsts[s] + js[s]])) for tac, js in columns if js[s] >= 0]
        found += out[s]
        found.sort(key=lambda item: item[1])
        out[s] = found
    return out


def _turn(angle: NDArray[np.float64], ref: NDArray[np.intp]) -> NDArray[np.float64]:
    """:func:`~taxelkit.smart.track_geometry.turn` (``ref`` global rows)."""
    d: NDArray[np.float64] = np.abs((angle - angle[ref] + 90.0) % 180.0 - 90.0)
    return d


def _line_hits(
    runs: Runs,
    tracks: list[SegmentTrack],
    config: TactemeConfig,
    smooth: NDArray[np.float64],
    shift: NDArray[np.float64],
    angle: NDArray[np.float64],
    anchor: NDArray[np.intp],
    ref: NDArray[np.intp],
    ref_g: NDArray[np.intp],
    valid: NDArray[np.bool_],
    w: int,
    hold: int,
    raw: NDArray[np.float64],
    theta: NDArray[np.float64],
    ext: NDArray[np.float64] | None,
    span: NDArray[np.intp] | None,
) -> list[tuple[Tacteme, NDArray[np.intp]]]:
    """The line rules of ``segment_tactemes``: each tacteme's index per segment (-1: none).

    In the order the per-segment form emits them (ties in frame keep it).
    ``shift``: each row's smoothed centre less its reference's ``(N, 2)``, mm;
    ``span``: the rows' frame numbers where holds count the recording's frames.
    """
    starts, lengths, seg, local = runs.starts, runs.lengths, runs.seg, runs.local
    move = config.move_mm
    t_ref = np.deg2rad(angle.take(ref_g))
    cos_ref, sin_ref = np.cos(t_ref), np.sin(t_ref)
    along = np.abs(shift[:, 0] * cos_ref + shift[:, 1] * sin_ref)
    half = smooth[:, 6]
    ends = along - np.abs(half - half.take(ref_g))
    across = np.where(valid, np.abs(-shift[:, 0] * sin_ref + shift[:, 1] * cos_ref), 0.0)
    j_lcm = runs.first_sustained(across > move, hold, span, hold)
    slid = valid & (ends > move) & (across < 0.5 * move)
    j_slide = runs.first_sustained(slid, hold, span, hold)
    slide = np.where((j_slide >= 0) & ((j_lcm < 0) | (j_slide < j_lcm)), j_slide, -1)
    first_ref = np.minimum(w - 1, lengths - 1)  # a line's turn counts from its first reference
    first_g = starts + first_ref
    turned_all = np.where(local >= first_ref[seg], _turn(angle, first_g[seg]), 0.0)
    t0 = np.deg2rad(angle.take(first_g))  # each segment's (sine and cosine gathered per row)
    rolled = _carried_shift(runs, np.ascontiguousarray(smooth[:, 0:2]), shift, anchor, ref_g)
    across_all = np.abs(-rolled[:, 0] * np.sin(t0).take(seg) + rolled[:, 1] * np.cos(t0).take(seg))
    parallel = (across_all >= config.parallel_move_mm) & (
        turned_all <= config.parallel_limit_deg(across_all)
    )
    j_par = _first_held(
        runs, parallel, _holds(tracks, config.parallel_hold_s, hold, config), span, hold
    )
    j_turn = runs.first_sustained(turned_all > config.turn_deg, hold, span, hold)
    par = np.where((j_par >= 0) & ((j_turn < 0) | (j_par < j_turn)), j_par, -1)
    pivots = {tac: np.full(starts.size, -1, np.intp) for tac in _PIVOT_TACTEMES}
    turning = np.flatnonzero(j_turn >= 0)
    for s, (j, tac) in _pivots(
        runs, tracks, config, angle, anchor, ref, j_turn, turning, w, hold, raw, theta, ext, span
    ):
        pivots[tac][s] = j
    out = [
        (Tacteme.LC_SLIDES, slide),
        (Tacteme.LCM, j_lcm),
        (Tacteme.LCMP, par),
        (Tacteme.LCMT, j_turn),
    ]
    return out + list(pivots.items())  # each verdict sustained in a segment, at its first index


def _holds(
    tracks: Sequence[SegmentTrack], seconds: float, hold: int, config: TactemeConfig
) -> NDArray[np.intp]:
    """Each segment's frames covering ``seconds`` at its own rate, at least ``hold``."""
    k = int(config.debounce_frames)
    return np.array([frames_for_interval(t.frame_interval_s(k), seconds, hold) for t in tracks])


def _first_held(
    runs: Runs,
    mask: NDArray[np.bool_],
    holds: NDArray[np.intp],
    span: NDArray[np.intp] | None = None,
    min_rows: int = 1,
    keep: NDArray[np.bool_] | None = None,
) -> NDArray[np.intp]:
    """``runs.first_sustained(mask, h, span, min_rows)``, each segment's own ``h`` (``holds``).

    ``keep``: only its True rows may be the first (a mask whose gaps were
    bridged, :func:`~taxelkit.smart.verdict_holds.bridge_gaps`, and the mask before).
    """

    def held(h: int) -> NDArray[np.intp]:
        on = runs.sustained(mask, h, span, min_rows)
        return runs.first(on if keep is None else on & keep)

    values = np.unique(holds).tolist()
    if len(values) == 1:
        return held(values[0])
    out = np.full(holds.size, -1, np.intp)
    for h in values:
        sel = holds == h
        out[sel] = held(h)[sel]
    return out


def _pivots(
    runs: Runs,
    tracks: list[SegmentTrack],
    config: TactemeConfig,
    angle: NDArray[np.float64],
    anchor: NDArray[np.intp],
    ref: NDArray[np.intp],
    j_turn: NDArray[np.intp],
    turning: NDArray[np.intp],
    w: int,
    hold: int,
    raw: NDArray[np.float64],
    raw_theta: NDArray[np.float64],
    raw_ext: NDArray[np.float64] | None,
    span: NDArray[np.intp] | None = None,
) -> list[tuple[int, tuple[int, Tacteme]]]:
    """:func:`~taxelkit.smart.pivot_rules.pivot_tacteme` of the segments ``turning``, together.

    ``raw``, ``raw_theta``, ``raw_ext``: the group's unsmoothed centres (columns
    0-1) and half-lengths (column 6), axes and line extents (None: not all
    measured, each segment alone); ``w``: the group's smoothing window, frames;
    ``span``: the group's frame numbers where holds count the recording's frames.
    Returns ``(segment, (index, tacteme))`` for each pivot verdict sustained
    in a segment (one segment may have several).
    """
    starts, lengths = runs.starts, runs.lengths
    pitch = tracks[0].pitch_mm
    if raw_ext is None or any(t.pitch_mm != pitch for t in tracks):
        alone, together = turning.tolist(), turning[:0]
    else:
        alone, together = [], turning
    out: list[tuple[int, tuple[int, Tacteme]]] = []
    for s in alone:
        a, b = int(starts[s]), int(starts[s] + lengths[s])
        found = pivot_tacteme(
            tracks[s], config, angle[a:b], anchor[a:b], ref[a:b], int(j_turn[s]), hold
        )
        out += [(s, jt) for jt in found]
    if together.size == 0 or raw_ext is None:
        return out
    # the lines from each turn's anchor to the segment's end, laid end to end
    first = anchor[starts[together] + j_turn[together]]  # within the segment
    part = Runs(lengths[together] - first)
    rows = (starts[together] + first)[part.seg] + part.local  # rows of the group
    theta, centre, half, ext = raw_theta[rows], raw[rows, 0:2], raw[rows, 6], raw_ext[rows]
    area = raw[rows, 4] if config.pivot_pressed_half else None
    ratio, error, arc_ratio = drawn_pivot_fit(
        theta, centre, half, ext, w if config.pivot_arc_smooth else 1, runs=part, area_mm2=area
    )
    line_mm = 2.0 * drawn_half_mm(half, ext)
    pitch = tracks[int(together[0])].pitch_mm
    ref_start = starts[together] + ref[starts[together] + first]  # each turn's reference row
    turned_now = np.abs((angle[rows] - angle[ref_start][part.seg] + 90.0) % 180.0 - 90.0)
    largest = part.cummax(turned_now) if config.pivot_arc_max_turn else None  # run by run
    verdicts = pivot_verdicts(config, ratio, error, arc_ratio, turned_now, line_mm, pitch, largest)
    group = [tracks[s] for s in together.tolist()]
    holds = _holds(group, config.pivot_hold_s, hold, config)
    k = int(config.debounce_frames)
    gaps = np.array([gap_rows(t.frame_interval_s(k), config.pivot_gap_s) for t in group])
    verdicts_of: list[list[tuple[int, Tacteme]]] = [[] for _ in range(together.size)]
    part_span = None if span is None else span[rows]
    for tac, verdict in verdicts:
        # "about one end", the verdict that names a cone, holds on the segment's own rows
        own = tac is Tacteme.LCMT_ABOUT_END
        bridged = bridge_gaps(verdict, gaps[part.seg], part.seg)
        span_v = None if own else part_span
        js = _first_held(part, bridged, holds, span_v, hold, keep=verdict)
        for i, j in enumerate(js.tolist()):
            if j >= 0:
                verdicts_of[i].append((int(first[i]) + j, tac))
    for s, v in zip(together.tolist(), verdicts_of, strict=True):
        found = sorted(v, key=lambda hit: hit[0])
        out += [(s, jt) for jt in (found if config.pivot_every_verdict else found[:1])]
    return out


def _carried_shift(
    runs: Runs,
    centre: NDArray[np.float64],
    shift: NDArray[np.float64],
    anchor: NDArray[np.intp],
    ref_g: NDArray[np.intp],
) -> NDArray[np.float64]:
    """:func:`~taxelkit.smart.track_geometry.carried_shift` of every segment (global rows).

    ``shift``: ``centre - centre[ref_g]`` ``(N, 2)``, mm.
    """
    n = runs.size
    anchor_g = runs.starts[runs.seg] + anchor
    new = np.ones(n, bool)
    new[1:] = anchor_g[1:] != anchor_g[:-1]  # a segment's first row always differs
    first = np.flatnonzero(new)  # first row of each stretch
    last = np.append(first[1:] - 1, n - 1)
    refs = ref_g[first]
    done = np.where((last >= refs)[:, None], take_rows(centre, last) - take_rows(centre, refs), 0.0)
    per_seg = np.bincount(runs.seg[first], minlength=runs.lengths.size)
    summed = Runs(per_seg).cumsum(done)  # what each segment's stretches rolled, in order
    before = np.zeros_like(done)
    lead = np.zeros(first.size, bool)  # each segment's first stretch: nothing before
    lead[np.cumsum(per_seg) - per_seg] = True
    later = np.flatnonzero(~lead)
    before[later] = take_rows(summed, later - 1)
    stretch = np.cumsum(new) - 1
    current = np.where((np.arange(n) >= ref_g)[:, None], shift, 0.0)
    out: NDArray[np.float64] = take_rows(before, stretch) + current
    return out
