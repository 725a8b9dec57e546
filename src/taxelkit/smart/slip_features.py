"""The slip detector's per-frame features and motion measure (the rule as written).

:class:`~taxelkit.smart.slip_scan.SlipScanner` averages the features over
windows of frames and measures the motion between two windows' means, frame
by frame (the reference rule) or vectorised (:mod:`taxelkit.smart.slip_motion`,
which falls back on :func:`motion_mm` where it cannot vouch for a decision).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.slip import SlipConfig

__all__ = ["N_FEATURES", "line_returned", "motion_mm", "slip_features"]

# Feature columns averaged over the windows (from the rows of segment_scan.ROW_COLUMNS).
_CX, _CY, _AREA_COL, _C2, _S2, _HALF, _ELONG = range(7)
_END1, _END2 = slice(7, 9), slice(9, 11)  # a line's two ends, x y (mm), in a consistent order
_ENDS = slice(_END1.start, _END2.stop)
_COV = slice(11, 14)  # second central moments xx, yy, xy, mm^2
_AREA2 = 14  # the area squared, mm^4 (a window's mean gives the spread of its areas)
#: Features per frame.
N_FEATURES = 15


def slip_features(
    rows: NDArray[np.float64],
    *,
    line: bool,
    every: bool = False,
    u_last: NDArray[np.float64] | None = None,
    starts: NDArray[np.intp] | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
    """Per-frame features ``(m, 15)`` from rows ``(m, 9)`` (segment_scan's ``ROW_COLUMNS``).

    Centre, area, doubled-angle axis, half-length, elongation, a line's two
    ends (its drawn extent along its axis, the axis oriented like the
    previous frame's so that the ends keep their order), a face's second
    central moments and the area squared. The columns a class does not read
    are left at 0 (a face's ends, a line's moments) unless ``every``.

    Parameters
    ----------
    rows : (m, 9) float
    line : bool
        A line's features (else a face's).
    every : bool
        Fill every column (the per-frame reference scan).
    u_last : (2,) float, optional
        The oriented axis of the frame before the first (None: the first
        frame orients itself).
    starts : (S,) int, optional
        The rows hold ``S`` segments laid end to end, beginning at these rows
        (increasing, the first 0): each orients its axes from its own first
        frame, as a new scanner would, and ``u_last`` is not used.

    Returns
    -------
    features : (m, 15) float
    axes : (m, 2) float or None
        The oriented line axes (None unless a line's, or ``every``).
    """
    m = rows.shape[0]
    out = np.empty((m, N_FEATURES))
    theta = np.deg2rad(rows[:, 2])
    t2 = 2.0 * theta
    out[:, _CX], out[:, _CY], out[:, _AREA_COL] = rows[:, 0], rows[:, 1], rows[:, 3]
    out[:, _C2], out[:, _S2] = np.cos(t2), np.sin(t2)
    out[:, _HALF], out[:, _ELONG] = rows[:, 5], rows[:, 4]
    out[:, _AREA2] = rows[:, 3] * rows[:, 3]
    u: NDArray[np.float64] | None = None
    if line or every:
        u = np.stack([np.cos(theta), np.sin(theta)], axis=-1)
        first = u[:1] if u_last is None or starts is not None else u_last[None]
        prev = np.concatenate([first, u[:-1]])
        if starts is not None:
            prev[starts] = u[starts]
        flip = np.cumprod(np.where(np.einsum("ij,ij->i", u, prev) < 0.0, -1.0, 1.0))
        if starts is not None and starts.size > 1:  # each segment's own product (of +-1)
            carried = np.ones(starts.size)
            carried[1:] = flip[starts[1:] - 1]
            flip *= np.repeat(carried, np.diff(np.append(starts, m)))
        u = u * flip[:, None]
        lo = np.where(flip > 0, rows[:, 6], -rows[:, 7])
        hi = np.where(flip > 0, rows[:, 7], -rows[:, 6])
        centre = rows[:, :2]
        out[:, _END1] = centre + lo[:, None] * u
        out[:, _END2] = centre + hi[:, None] * u
    else:
        out[:, _END1.start : _END2.stop] = 0.0
    if not line or every:
        lam_max = rows[:, 5] ** 2 / 3.0  # half = sqrt(3 lambda_max)
        lam_min = lam_max / np.maximum(rows[:, 4], 1.0) ** 2  # elongation = sqrt(max / min)
        c, s_ = np.cos(theta), np.sin(theta)
        out[:, _COV.start] = lam_max * c * c + lam_min * s_ * s_
        out[:, _COV.start + 1] = lam_max * s_ * s_ + lam_min * c * c
        out[:, _COV.start + 2] = (lam_max - lam_min) * c * s_
    else:
        out[:, _COV] = 0.0
    return out, u


def motion_mm(
    ref: NDArray[np.float64],
    cur: NDArray[np.float64],
    *,
    line: bool,
    config: SlipConfig,
    length_mm: float = math.inf,
) -> float:
    """How far the footprint moved from mean features ``ref`` to ``cur`` ``(15,)``, mm.

    NaN when the mean area changed by more than ``area_step`` of the
    reference's, or (a face) when the areas of the current window spread
    by more than that (standard deviation): no decision. A line whose two
    ends' moves differ by more than ``length_mm`` (``line_length_pitches``
    times the pitch) grew or shrank at one end: 0.
    """
    cfg = config
    a_ref, a_cur = float(ref[_AREA_COL]), float(cur[_AREA_COL])
    if not a_ref > 0 or abs(a_cur / a_ref - 1.0) > cfg.area_step:
        return math.nan
    dx, dy = float(cur[_CX] - ref[_CX]), float(cur[_CY] - ref[_CY])
    if line:  # along the bisector of the two axes: a turn about a pivot cancels
        c2, s2 = float(ref[_C2] + cur[_C2]), float(ref[_S2] + cur[_S2])
        th = 0.5 * math.atan2(s2, c2)
        ax, ay = math.cos(th), math.sin(th)
        th_ref = 0.5 * math.atan2(float(ref[_S2]), float(ref[_C2]))
        th_cur = 0.5 * math.atan2(float(cur[_S2]), float(cur[_C2]))
        turn = abs((th_cur - th_ref + 0.5 * math.pi) % math.pi - 0.5 * math.pi)
        across = abs(dy * ax - dx * ay) + turn * float(ref[_HALF])
        if across > cfg.line_across_mm:  # the line turned or moved across: it rolls
            return 0.0
        e1, e2 = cur[_END1] - ref[_END1], cur[_END2] - ref[_END2]
        d1, d2 = float(e1[0] * ax + e1[1] * ay), float(e2[0] * ax + e2[1] * ay)
        if math.isnan(d1 + d2):  # ends not measured: the centre less the change of length
            return abs(dx * ax + dy * ay) - abs(float(cur[_HALF] - ref[_HALF]))
        if abs(d1 - d2) > length_mm:  # a rigid slide keeps the line's length
            return 0.0
        return min(abs(d1), abs(d2)) if d1 * d2 > 0.0 else 0.0  # both ends, the same way
    spread = float(cur[_AREA2]) - a_cur * a_cur  # the current window's areas: a face tipping
    if spread > (cfg.area_step * a_ref) ** 2:
        return math.nan
    # both sides of the footprint must move: one that grows or shrinks on one side
    # moves its centre by half the change of its length along the motion
    moved = math.hypot(dx, dy)
    if moved > 0.0:
        nx, ny = dx / moved, dy / moved
        size = [
            math.sqrt(12.0 * max(0.0, float(v[0] * nx * nx + v[1] * ny * ny + 2 * v[2] * nx * ny)))
            for v in (ref[_COV], cur[_COV])
        ]
        moved -= 0.5 * abs(size[1] - size[0])
    th_ref = 0.5 * math.atan2(float(ref[_S2]), float(ref[_C2]))
    if min(float(ref[_ELONG]), float(cur[_ELONG])) >= cfg.min_elongation:
        th_cur = 0.5 * math.atan2(float(cur[_S2]), float(cur[_C2]))
        turn = abs((th_cur - th_ref + 0.5 * math.pi) % math.pi - 0.5 * math.pi)
        moved = max(moved, turn * float(ref[_HALF]))
    return moved


def line_returned(
    cur: NDArray[np.float64],
    past: NDArray[np.float64],
    first: NDArray[np.intp],
    stop: NDArray[np.intp],
    *,
    tol_mm: float,
    area_step: float,
) -> NDArray[np.bool_]:
    """Whether each line's mean features ``cur`` are back where one of its frames ``past`` had them.

    Back: the area within ``area_step`` of that frame's (relative), and both
    drawn ends within ``tol_mm`` of that frame's along the bisector of the
    two axes (:attr:`~taxelkit.smart.slip.SlipConfig.line_return_s`).
    Frames with ends not measured, or an axis square to the line's, are not
    matched. Only IEEE-exact operations (the bisector from square roots of
    the doubled-angle sums, no trigonometry): the decisions are the same
    whatever the rows are tested with, and on every CPU.

    Parameters
    ----------
    cur : (k, 15) float
        Mean features of ``k`` windows (:func:`slip_features` columns).
    past : (m, 15) float
        Features of single frames.
    first, stop : (k,) int
        Each window is tested against the rows ``first[i] <= j < stop[i]`` of ``past``.
    tol_mm, area_step : float

    Returns
    -------
    (k,) bool
    """
    k, m = cur.shape[0], past.shape[0]
    if k == 0 or m == 0:
        return np.zeros(k, bool)
    a = past[None, :, _AREA_COL]
    j = np.arange(m)[None, :]
    inside = (j >= np.asarray(first)[:, None]) & (j < np.asarray(stop)[:, None])
    with np.errstate(divide="ignore", invalid="ignore"):
        same = (a > 0.0) & (np.abs(cur[:, None, _AREA_COL] / a - 1.0) <= area_step)
        c2 = cur[:, None, _C2] + past[None, :, _C2]
        s2 = cur[:, None, _S2] + past[None, :, _S2]
        norm = np.sqrt(c2 * c2 + s2 * s2)
        cos2 = c2 / norm
        ax = np.sqrt(np.maximum(0.0, 0.5 * (1.0 + cos2)))
        ay = np.copysign(np.sqrt(np.maximum(0.0, 0.5 * (1.0 - cos2))), s2)
        ends = cur[:, None, _ENDS] - past[None, :, _ENDS]  # (k, m, 4): x1 y1 x2 y2
        along = ends[..., 0::2] * ax[..., None] + ends[..., 1::2] * ay[..., None]
        back = same & (norm > 0.0) & (np.abs(along).max(axis=-1) <= tol_mm)
    out: NDArray[np.bool_] = np.any(back & inside, axis=1)
    return out
