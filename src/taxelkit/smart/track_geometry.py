"""Geometry of a contact's track for Level 3: smoothing, anchors, turns, pivots, corners.

Pure functions on the arrays of :class:`~taxelkit.smart.tactemes.SegmentTrack`;
the tacteme rules in :mod:`taxelkit.smart.tactemes` say what their results mean.
Orientations are axial (a line at 10 deg is the line at 190 deg): they are
averaged as doubled-angle vectors.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "anchors",
    "axis_angle_deg",
    "axis_difference_deg",
    "axis_vectors",
    "carried_shift",
    "corner_turn",
    "drawn_half_mm",
    "first",
    "first_jump",
    "grid_wobble_deg",
    "orthogonal_turn",
    "rolling_mean",
    "spaced_points",
    "sustained",
    "turn",
]


#: Relative distance within which ``np.hypot`` and ``math.hypot`` may disagree (both are
#: within an ulp or two of the exact value): :func:`orthogonal_turn` decides those by the latter.
_HYPOT_MARGIN = 1e-12


def rolling_mean(x: NDArray[np.float64], w: int) -> NDArray[np.float64]:
    """Mean of the last ``w`` rows (fewer at the start), along axis 0."""
    c = np.cumsum(x, axis=0)
    out = c.copy()
    out[w:] -= c[:-w]
    n = np.minimum(np.arange(1, x.shape[0] + 1), w).reshape((-1,) + (1,) * (x.ndim - 1))
    result: NDArray[np.float64] = out / n
    return result


def axis_vectors(theta_deg: NDArray[np.float64]) -> NDArray[np.float64]:
    t = np.deg2rad(2.0 * theta_deg)
    return np.stack([np.cos(t), np.sin(t)], axis=-1)


def axis_angle_deg(v: NDArray[np.float64]) -> NDArray[np.float64]:
    out: NDArray[np.float64] = 0.5 * np.rad2deg(np.arctan2(v[..., 1], v[..., 0]))
    return out


def axis_difference_deg(a: NDArray[np.float64], b: float) -> NDArray[np.float64]:
    """Smallest difference between line orientations, in [0, 90] deg."""
    d = np.abs((a - b + 90.0) % 180.0 - 90.0)
    out: NDArray[np.float64] = d
    return out


def anchors(
    area: NDArray[np.float64], elongation: NDArray[np.float64], k: int, tolerance: float
) -> NDArray[np.intp]:
    """Index of the motion anchor of every frame (re-anchored on cumulative change of shape).

    The reference of anchor ``a`` is its first full smoothing window, frame
    ``a + k - 1``; a frame whose area or elongation differs from the
    reference's by more than ``tolerance`` (relative) becomes the next
    anchor: a face landing keeps its area for a moment while its outline
    still changes. One vectorised search per anchor: a segment has few.
    """
    n = area.size
    out = np.zeros(n, dtype=np.intp)
    a = 0
    while a < n:
        r = min(a + k - 1, n - 1)
        dev = (np.abs(area[r + 1 :] / area[r] - 1.0) > tolerance) | (
            np.abs(elongation[r + 1 :] / elongation[r] - 1.0) > tolerance
        )
        hits = np.flatnonzero(dev)
        nxt = n if hits.size == 0 else r + 1 + int(hits[0])
        out[a:nxt] = a
        a = nxt
    return out


def carried_shift(
    centre: NDArray[np.float64], anchor: NDArray[np.intp], ref: NDArray[np.intp]
) -> NDArray[np.float64]:
    """Displacement of the centre since the segment began, summed across re-anchors.

    Each anchor's stretch contributes the shift from its reference to its
    last frame (or to the current frame, for the stretch under way); the
    frames between an anchor and its reference (a change of width or area,
    not motion) contribute nothing. A line rolling on while its area
    re-anchors the references thus keeps the distance it has already rolled.

    Parameters
    ----------
    centre : (n, 2) float, mm
        Smoothed centres.
    anchor, ref : (n,) int
        Each frame's anchor (:func:`anchors`) and reference frame.

    Returns
    -------
    (n, 2) float, mm
    """
    n = anchor.size
    starts = np.flatnonzero(np.diff(anchor, prepend=-1))  # first frame of each stretch
    ends = np.append(starts[1:] - 1, n - 1)
    refs = ref[starts]
    done = np.where((ends >= refs)[:, None], centre[ends] - centre[refs], 0.0)
    before = np.zeros_like(done)  # what the earlier stretches rolled, summed in order
    before[1:] = np.cumsum(done[:-1], axis=0)
    stretch = np.cumsum(np.diff(anchor, prepend=-1) != 0) - 1
    current = np.where((np.arange(n) >= ref)[:, None], centre - centre[ref], 0.0)
    out: NDArray[np.float64] = before[stretch] + current
    return out


def first(mask: NDArray[np.bool_], start: int) -> int | None:
    hits = np.flatnonzero(mask[start:])
    return None if hits.size == 0 else int(hits[0]) + start


def sustained(
    mask: NDArray[np.bool_], k: int, frames: NDArray[np.intp] | None = None, min_rows: int = 1
) -> NDArray[np.bool_]:
    """True where ``mask`` has held for the last ``k`` frames (motion is debounced too).

    ``frames``: the rows' frame numbers in the recording ``(n,)``; given, a
    run of True rows holds once it spans ``k`` frames of the recording
    (``frames[i] - frames[first] + 1 >= k``), the frames left out of the
    segment between its rows counted, and counts at least ``min_rows`` rows.
    None: ``k`` rows.
    """
    if frames is not None:
        idx = np.arange(mask.size)
        first_row = np.maximum.accumulate(np.where(mask, 0, idx + 1))  # each run's first row
        first_row = np.minimum(first_row, max(mask.size - 1, 0))
        spans: NDArray[np.bool_] = (
            mask & (frames - frames[first_row] + 1 >= k) & (idx - first_row + 1 >= min_rows)
        )
        return spans
    c = np.cumsum(mask.astype(np.int64))
    run = c.copy()
    run[k:] -= c[:-k]
    out: NDArray[np.bool_] = run >= k
    return out


def turn(angle: NDArray[np.float64], ref: NDArray[np.intp]) -> NDArray[np.float64]:
    """Orientation change from each frame's reference, in [0, 90] deg."""
    d = np.abs((angle - angle[ref] + 90.0) % 180.0 - 90.0)
    out: NDArray[np.float64] = d
    return out


def drawn_half_mm(
    half_length_mm: NDArray[np.float64], extent_mm: NDArray[np.float64] | None
) -> NDArray[np.float64]:
    """Half of each line's drawn length, mm: from its extents where measured.

    Parameters
    ----------
    half_length_mm : (n,) float
        Moment half-lengths, used where no extent was measured.
    extent_mm : (n, 2) float or None
        :func:`~taxelkit.smart.line_extents.line_extents` (NaN where not measured);
        None: none measured.
    """
    if extent_mm is None:
        return half_length_mm
    measured = np.isfinite(extent_mm[:, 0]) & np.isfinite(extent_mm[:, 1])
    out: NDArray[np.float64] = np.where(
        measured, 0.5 * (extent_mm[:, 1] - extent_mm[:, 0]), half_length_mm
    )
    return out


def grid_wobble_deg(line_mm: NDArray[np.float64], pitch_mm: float) -> float:
    """How far the grid alone can tilt a drawn line of the mean length, deg.

    ``atan(pitch / length)``: each end of a line is drawn to the nearest
    taxel, so a line of ``length`` can read tilted by about one pitch over
    its length. 0 when the pitch is unknown (0) or no length was measured.

    Parameters
    ----------
    line_mm : (n,) float
        Drawn lengths of the line's frames, mm.
    pitch_mm : float
        Taxel pitch, mm.
    """
    if pitch_mm <= 0 or line_mm.size == 0:
        return 0.0
    mean = float(np.mean(line_mm))
    return float(np.rad2deg(np.arctan2(pitch_mm, mean))) if mean > 0 else 90.0


def orthogonal_turn(
    centre: NDArray[np.float64], start: int, leg_mm: float, window_deg: tuple[float, float]
) -> int | None:
    """First frame at which a point's path has turned by 60-120 deg.

    The smoothed path from ``start`` is cut into legs of ``leg_mm``
    (a breakpoint each time the point is that far from the last one); a turn
    is the angle between the legs before and after the leg that holds the
    corner (or between consecutive legs), so a corner falling inside a leg
    still shows its full angle. The legs are much longer than the taxel-sized
    jumps of a point contact's centre.
    """
    leg = leg_mm
    lo, hi = np.cos(np.deg2rad(window_deg[1])), np.cos(np.deg2rad(window_deg[0]))
    xs, ys = centre[:, 0], centre[:, 1]
    bx, by = float(xs[start]), float(ys[start])
    legs: list[tuple[float, float]] = []
    j, ahead = start + 1, 16
    while j < xs.size:  # from breakpoint to breakpoint; legs are few
        # the next point a leg away, looked for in windows that double: the frames np.hypot
        # puts nearer than the leg by more than its rounding are skipped, the others are
        # tested as the rule writes it
        q = None
        while q is None and j < xs.size:
            stop = min(xs.size, j + ahead)
            near = np.hypot(xs[j:stop] - bx, ys[j:stop] - by) < leg * (1.0 - _HYPOT_MARGIN)
            for i in (j + np.flatnonzero(~near)).tolist():
                x, y = float(xs[i]), float(ys[i])
                dx, dy = x - bx, y - by
                d = math.hypot(dx, dy)
                if not d < leg:  # (a NaN breaks the path too)
                    q = i
                    break
            else:
                j, ahead = stop, 2 * ahead
        if q is None:
            return None
        j, ahead = q, max(16, (q - j) * 2)
        legs.append((dx / d, dy / d))
        bx, by = x, y
        for back in (2, 3):  # compare with the leg before last and the one before that
            if len(legs) >= back:
                ux, uy = legs[-back]
                c = ux * legs[-1][0] + uy * legs[-1][1]
                if lo <= c <= hi:
                    return j
        j += 1
    return None


def spaced_points(
    points: NDArray[np.float64], step_mm: float, last: tuple[float, float] | None = None
) -> NDArray[np.intp]:
    """Rows of ``points`` ``(n, 2)`` each at least ``step_mm`` from the row kept before it.

    A distance filter: the first row is kept (unless ``last``, the point
    kept before these rows, is given), then each row at least ``step_mm``
    from the last one kept. A point jittering in place keeps no rows, so the
    path length between the kept rows does not grow with the frame rate.
    ``step_mm`` <= 0 keeps every row.
    """
    n = points.shape[0]
    if step_mm <= 0.0 or n == 0:
        return np.arange(n, dtype=np.intp)
    kept: list[int] = []
    i = 0
    if last is None:
        kept, i = [0], 1
        last = (float(points[0, 0]), float(points[0, 1]))
    window = 16
    while i < n:
        stop = min(n, i + window)
        gap = np.hypot(points[i:stop, 0] - last[0], points[i:stop, 1] - last[1])
        far = np.flatnonzero(gap >= step_mm)
        if far.size == 0:
            i, window = stop, 2 * window
            continue
        i += int(far[0])
        kept.append(i)
        last = (float(points[i, 0]), float(points[i, 1]))
        i, window = i + 1, 16
    return np.asarray(kept, dtype=np.intp)


def corner_turn(
    centre: NDArray[np.float64],
    start: int,
    leg_mm: float,
    window_deg: tuple[float, float],
    step_mm: float = 0.0,
) -> int | None:
    """First frame at which a corner of 60-120 deg is seen on a point's path (vectorised).

    For every frame ``i`` of the smoothed path from ``start``, the chord from
    the point ``leg_mm`` of path length before ``i`` to ``i`` and the
    chord from ``i`` to the point ``turn_leg_mm`` after it; a corner is where
    both chords are nearly straight (each at least 70 % of the path length
    they span: a resting, jittering point has short chords) and the angle
    between them lies in the window. It is seen when the outgoing chord is
    complete. This finds corners that fall between the legs of
    :func:`orthogonal_turn` when the runs are only a little longer than a leg.
    With ``step_mm`` > 0 the path is first thinned by :func:`spaced_points`.
    """
    rows = spaced_points(centre[start:], step_mm)
    p = centre[start:][rows]
    if p.shape[0] < 3:
        return None
    d = leg_mm
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(p, axis=0).T))])
    a = np.searchsorted(arc, arc - d, side="right") - 1
    b = np.searchsorted(arc, arc + d, side="left")
    ok = (arc >= d) & (b < p.shape[0])
    a, b = np.clip(a, 0, None), np.clip(b, 0, p.shape[0] - 1)
    u = p - p[a]
    v = p[b] - p
    nu, nv = np.hypot(*u.T), np.hypot(*v.T)
    ok &= (nu >= 0.7 * d) & (nv >= 0.7 * d)
    cos = np.sum(u * v, axis=1) / np.where(ok, nu * nv, 1.0)
    lo, hi = np.cos(np.deg2rad(window_deg[1])), np.cos(np.deg2rad(window_deg[0]))
    hits = b[ok & (cos >= lo) & (cos <= hi)]
    return None if hits.size == 0 else start + int(rows[hits.min()])


def first_jump(
    centre_mm: NDArray[np.float64],
    frames: NDArray[np.intp],
    limit_mm: float,
    before: NDArray[np.float64] | None = None,
) -> int | None:
    """First frame whose centre moved more than ``limit_mm`` from the frame before.

    Parameters
    ----------
    centre_mm : (m, 2) float
        Centres of consecutive frames of a segment, mm.
    frames : (m,) int
        Their frame numbers.
    limit_mm : float
        Largest step that is not a jump, mm.
    before : (2,) float, optional
        Centre of the frame before the first (None: the first frame has none).

    Returns
    -------
    int or None
        The frame number jumped to, None if no step exceeds ``limit_mm``.
    """
    if before is None:
        prev, after, at = centre_mm[:-1], centre_mm[1:], frames[1:]
    else:
        prev, after, at = np.vstack([before, centre_mm[:-1]]), centre_mm, frames
    hits = np.flatnonzero(np.hypot(*(after - prev).T) > limit_mm)
    return int(at[hits[0]]) if hits.size else None
