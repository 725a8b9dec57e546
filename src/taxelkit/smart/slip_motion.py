"""The slip detector's window means and motion measure, for many frames at once.

:class:`~taxelkit.smart.slip_scan.SlipScanner` decides every frame from
window means of its features and the motion between two windows
(:meth:`~taxelkit.smart.slip_scan.SlipScanner.motion_mm`, the rule of
:mod:`taxelkit.smart.slip`). The per-frame rule sums each window row by row
(``w`` additions a frame) and measures one frame at a time in Python; here
the sums come from sums over windows of powers of two rows (a few additions
a window, vectorised) and the measure is vectorised over frames.

The floats differ from the per-frame rule's by rounding only, so a decision
can differ only where a value lies within that rounding of a limit, or where
the measure is ill-conditioned. Each window's mean is within
:meth:`WindowSums.error_bound` of the row-by-row mean (a bound on the rounding
of the sums, from the largest feature value); every decision closer to its limit
than ``MARGIN`` times that bound (and every window holding an infinite value,
or a NaN other than a line's ends not measured) is marked *unsure*, and the
scanner recomputes those frames by the per-frame rule. The decisions, and
so the slips, are therefore those of the per-frame rule (tested on
randomised segments, ties included).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.slip import SlipConfig
from taxelkit.smart.slip_features import motion_mm

__all__ = [
    "AXIS_MIN_NORM",
    "ENDS",
    "MARGIN",
    "WindowSums",
    "exact_means",
    "motions_mm",
    "row_window_means",
    "window_decisions",
    "window_means",
]

#: Distance to a limit, in units of the means' rounding bound, below which a
#: decision is recomputed by the per-frame rule (it covers the measure's
#: amplification of a rounding: products with centres, half-lengths and
#: turns of tactile arrays, and square roots kept away from zero).
MARGIN = 1.0e6

#: Axis sums (``cos 2 theta``, ``sin 2 theta``) shorter than this leave the
#: axis ill-conditioned: the frame is recomputed.
AXIS_MIN_NORM = 1.0e-2

_EPS = float(np.finfo(np.float64).eps)


class WindowSums:
    """Means of windows of consecutive rows, from sums over windows of powers of two rows.

    Level ``k`` holds the sum of every ``2^k`` consecutive rows (two of
    level ``k - 1`` added, one vectorised addition a level); a window of
    ``w`` rows adds one term of each level in the binary digits of ``w``.
    Every row of a window enters its sum, so a NaN makes it NaN exactly as
    in the row-by-row sum.

    Parameters
    ----------
    x : (n, F) float
    nan_columns : slice
        Columns whose NaN (a value not measured) the caller handles (NaN
        means where the window holds one, as the row-by-row mean); any other
        NaN, and any infinity, marks the windows holding it bad.
    """

    def __init__(self, x: NDArray[np.float64], nan_columns: slice = slice(0)) -> None:
        self._odd: NDArray[np.intp] | None = None
        size = np.abs(x)
        if np.isfinite(size.max(initial=0.0)):
            self._big = float(size.max(initial=0.0))
        else:
            x = self._set_aside(x, nan_columns)
            self._big = float(np.max(size, where=np.isfinite(size), initial=0.0))
        self._levels = [x]

    def _set_aside(self, x: NDArray[np.float64], nan_columns: slice) -> NDArray[np.float64]:
        """``x``, rows with an infinity or a NaN outside ``nan_columns`` at 0 (counted)."""
        nan = np.isnan(x)
        allowed = np.zeros(x.shape[1], bool)
        allowed[nan_columns] = True
        odd = np.asarray(np.isinf(x).any(axis=1) | (nan & ~allowed).any(axis=1))
        if odd.any():
            x = np.where(odd[:, None], 0.0, x)
            self._odd = np.concatenate([[0], np.cumsum(odd)])
        return x

    def _level(self, k: int) -> NDArray[np.float64]:
        """Sums of every ``2^k`` consecutive rows."""
        while len(self._levels) <= k:
            prev, half = self._levels[-1], 1 << (len(self._levels) - 1)
            self._levels.append(prev[:-half] + prev[half:])
        return self._levels[k]

    def means(
        self, start: int, w: int, count: int
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Means ``(count, F)`` of the windows of ``w`` rows at ``start + k``, and the bad ones.

        Each finite mean is within :meth:`error_bound` of the row-by-row mean.
        """
        total: NDArray[np.float64] | None = None
        off = start
        for k in range(w.bit_length() - 1, -1, -1):
            if w >> k & 1:
                term = self._level(k)[off : off + count]
                total = term if total is None else total + term
                off += 1 << k
        assert total is not None
        out: NDArray[np.float64] = total / w
        bad = np.zeros(count, bool)
        if self._odd is not None:
            p = start + np.arange(count)
            bad = (self._odd[p + w] - self._odd[p]) > 0
        return out, bad

    def error_bound(self, w: int) -> float:
        """Bound on a window mean's distance from the row-by-row mean (finite windows).

        Each row passes through at most ``2 log2 w + 1`` roundings (its
        levels, then the terms added), each at most ``eps`` times a partial
        sum of at most ``w max|x|``; the row-by-row sum through at most ``w``;
        both divide by ``w``: ``(w + 2 bitlength(w) + 4) eps max|x|``.
        """
        return (w + 2.0 * w.bit_length() + 4.0) * _EPS * self._big + 1e-300


def window_means(
    x: NDArray[np.float64], w: int, nan_columns: slice = slice(0)
) -> tuple[NDArray[np.float64], NDArray[np.bool_], float]:
    """Means of every ``w`` consecutive rows (:class:`WindowSums`), the bad ones, the bound.

    Returns
    -------
    means : (n - w + 1, F) float
    bad : (n - w + 1,) bool
    bound : float
        :meth:`WindowSums.error_bound`.
    """
    m = x.shape[0] - w + 1
    if m <= 0:
        return np.zeros((0, x.shape[1])), np.zeros(0, bool), 0.0
    sums = WindowSums(x, nan_columns)
    return (*sums.means(0, w, m), sums.error_bound(w))


def row_window_means(x: NDArray[np.float64], w: int) -> NDArray[np.float64]:
    """Mean of each ``w`` consecutive rows ``(n - w + 1, F)``, row by row (the per-frame rule).

    Empty when ``n < w``.
    """
    n = x.shape[0] - w + 1
    if n <= 0:
        return np.zeros((0, x.shape[1]))
    out = x[:n].copy()
    for j in range(1, w):  # in a fixed order: the same floats whatever the chunking
        out += x[j : j + n]
    out /= w
    return out


def exact_means(x: NDArray[np.float64], starts: NDArray[np.intp], w: int) -> NDArray[np.float64]:
    """Means of the windows of ``w`` rows starting at ``starts``, summed row by row.

    The same floats as the per-frame rule's window means (the same additions
    in the same order).
    """
    out = x[starts].copy()
    for j in range(1, w):
        out += x[starts + j]
    out /= w
    return out


# Feature columns (those of :class:`~taxelkit.smart.slip_scan.SlipScanner.features`).
_CX, _CY, _AREA, _C2, _S2, _HALF, _ELONG = range(7)
_END1, _END2, _COV = slice(7, 9), slice(9, 11), slice(11, 14)
_AREA2 = 14

#: Columns of a line's two ends (NaN where not measured).
ENDS = slice(7, 11)


def _axis_rad(c2: NDArray[np.float64], s2: NDArray[np.float64]) -> NDArray[np.float64]:
    out: NDArray[np.float64] = 0.5 * np.arctan2(s2, c2)
    return out


def _line_motion(
    ref: NDArray[np.float64],
    cur: NDArray[np.float64],
    unsure: NDArray[np.bool_],
    across_mm: float,
    tol: float,
    length_mm: float = math.inf,
) -> NDArray[np.float64]:
    """A line's two ends along the bisector of the axes, mm (both must move the same way).

    0 where its ends moved across it by more than ``across_mm`` (its shift
    across plus its turn times its half-length: a line that rolls), or
    where the two ends' moves differ by more than ``length_mm`` (a line
    that grew or shrank at one end).
    """
    c2, s2 = ref[:, _C2] + cur[:, _C2], ref[:, _S2] + cur[:, _S2]
    unsure |= np.hypot(c2, s2) < AXIS_MIN_NORM
    for v in (ref, cur):
        unsure |= np.hypot(v[:, _C2], v[:, _S2]) < AXIS_MIN_NORM
    th = _axis_rad(c2, s2)
    ax, ay = np.cos(th), np.sin(th)
    th_ref, th_cur = _axis_rad(ref[:, _C2], ref[:, _S2]), _axis_rad(cur[:, _C2], cur[:, _S2])
    turn = np.abs(np.mod(th_cur - th_ref + 0.5 * np.pi, np.pi) - 0.5 * np.pi)
    shift_x, shift_y = cur[:, _CX] - ref[:, _CX], cur[:, _CY] - ref[:, _CY]
    across = np.abs(shift_y * ax - shift_x * ay) + turn * ref[:, _HALF]
    unsure |= np.abs(across - across_mm) <= tol
    rolls = across > across_mm
    e1, e2 = cur[:, _END1] - ref[:, _END1], cur[:, _END2] - ref[:, _END2]
    d1, d2 = e1[:, 0] * ax + e1[:, 1] * ay, e2[:, 0] * ax + e2[:, 1] * ay
    both = np.where(d1 * d2 > 0.0, np.minimum(np.abs(d1), np.abs(d2)), 0.0)
    if math.isfinite(length_mm):  # a rigid slide keeps the line's length
        grew = np.abs(d1 - d2)
        unsure |= np.abs(grew - length_mm) <= tol
        both = np.where(grew > length_mm, 0.0, both)
    # ends not measured (NaN as in the row-by-row means): the centre less the change of length
    centre = np.abs(shift_x * ax + shift_y * ay) - np.abs(cur[:, _HALF] - ref[:, _HALF])
    out: NDArray[np.float64] = np.where(rolls, 0.0, np.where(np.isnan(d1 + d2), centre, both))
    return out


def _face_motion(
    ref: NDArray[np.float64],
    cur: NDArray[np.float64],
    unsure: NDArray[np.bool_],
    min_elongation: float,
    tol: float,
) -> NDArray[np.float64]:
    """A face's shift where both sides moved, or the turn of its ends, mm."""
    dx, dy = cur[:, _CX] - ref[:, _CX], cur[:, _CY] - ref[:, _CY]
    moved = np.hypot(dx, dy)
    some = moved > 0.0
    safe = np.where(some, moved, 1.0)
    nx, ny = dx / safe, dy / safe
    sizes = []
    for v in (ref[:, _COV], cur[:, _COV]):
        q = v[:, 0] * nx * nx + v[:, 1] * ny * ny + 2 * v[:, 2] * nx * ny
        unsure |= some & (q < tol)  # the square root is steep near zero
        sizes.append(np.sqrt(12.0 * np.maximum(0.0, q)))
    moved = np.where(some, moved - 0.5 * np.abs(sizes[1] - sizes[0]), moved)
    elong = np.minimum(ref[:, _ELONG], cur[:, _ELONG])
    turnable = elong >= min_elongation
    unsure |= np.abs(elong - min_elongation) <= tol
    for v in (ref, cur):
        unsure |= turnable & (np.hypot(v[:, _C2], v[:, _S2]) < AXIS_MIN_NORM)
    th_ref, th_cur = _axis_rad(ref[:, _C2], ref[:, _S2]), _axis_rad(cur[:, _C2], cur[:, _S2])
    turn = np.abs(np.mod(th_cur - th_ref + 0.5 * np.pi, np.pi) - 0.5 * np.pi)
    out: NDArray[np.float64] = np.where(turnable, np.maximum(moved, turn * ref[:, _HALF]), moved)
    return out


def motions_mm(
    ref: NDArray[np.float64],
    cur: NDArray[np.float64],
    *,
    line: bool,
    area_step: float,
    min_elongation: float,
    limit_mm: float,
    bound: float,
    line_across_mm: float = math.inf,
    line_length_mm: float = math.inf,
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """The per-frame rule's motion for rows of mean features, and where it may differ.

    Parameters
    ----------
    ref, cur : (n, 14) float
        Mean features of the two windows (:func:`window_means`).
    line : bool
        The measure of a line (else of a face).
    area_step, min_elongation : float
        As :class:`~taxelkit.smart.slip.SlipConfig`.
    line_across_mm : float
        As :class:`~taxelkit.smart.slip.SlipConfig` (a line only; default:
        no limit).
    line_length_mm : float
        Largest difference of a line's two ends' moves, mm
        (:attr:`~taxelkit.smart.slip.SlipConfig.line_length_pitches` times the
        pitch; default: no limit).
    limit_mm : float
        The limit the motion is compared with, mm.
    bound : float
        Bound on the means' rounding (:meth:`WindowSums.error_bound`).

    Returns
    -------
    motion : (n,) float, mm
        NaN where the mean area changed by more than ``area_step`` or (a
        face) the current window's areas spread by more than that.
    unsure : (n,) bool
        Frames whose decision (NaN, above ``limit_mm``) may differ from the
        per-frame rule's: recompute them with it.
    """
    tol = MARGIN * bound
    a_ref, a_cur = ref[:, _AREA], cur[:, _AREA]
    unsure = np.abs(a_ref) <= tol
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        ratio = a_cur / a_ref
        dev = np.abs(ratio - 1.0)
        unsure |= np.abs(dev - area_step) <= tol * (1.0 + np.abs(ratio)) / np.abs(a_ref)
        changed = ~(a_ref > 0) | (dev > area_step)
        if line:
            motion = _line_motion(ref, cur, unsure, line_across_mm, tol, line_length_mm)
        else:
            motion = _face_motion(ref, cur, unsure, min_elongation, tol)
            # the areas of the current window spread (their variance) beyond area_step
            spread = cur[:, _AREA2] - a_cur * a_cur
            limit2 = (area_step * a_ref) ** 2
            scale = 1.0 + 2.0 * np.abs(a_cur) + 2.0 * area_step * area_step * np.abs(a_ref)
            unsure |= ~changed & (np.abs(spread - limit2) <= tol * scale)
            changed |= spread > limit2
    unsure |= ~changed & (np.abs(motion - limit_mm) <= tol)
    out: NDArray[np.float64] = np.where(changed, np.nan, motion)
    return out, unsure


def window_decisions(
    x: NDArray[np.float64],
    a0: int,
    wa: int,
    b0: int,
    wb: int,
    count: int,
    limit: float,
    *,
    line: bool,
    config: SlipConfig,
    piece: int = 512,
    length_mm: float = math.inf,
) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """Motions from the windows of ``wa`` rows at ``a0 + k`` to those of ``wb`` at ``b0 + k``.

    Parameters
    ----------
    x : (n, 15) float
        Slip features of the frames (:func:`~taxelkit.smart.slip_features.slip_features`).
    a0, wa, b0, wb : int
        First row and length of the first reference and current windows.
    count : int
        Window pairs, ``k < count``.
    limit : float
        Motion limit, mm.
    line : bool
        The features are a line's.
    config : SlipConfig
    piece : int
        Frames computed together (the window sums of a piece stay small).
    length_mm : float
        A line's largest difference of its ends' moves, mm (as
        :func:`~taxelkit.smart.slip_features.motion_mm`; default: no limit).

    Returns
    -------
    changed, above : (count,) bool
        Whether the area changed (the rule's NaN) and whether the motion
        exceeds ``limit``: those of :func:`~taxelkit.smart.slip_features.motion_mm`
        (frames the vectorised measure cannot vouch for are recomputed by it).
    """
    changed, above = np.empty(count, bool), np.empty(count, bool)
    for k0 in range(0, count, piece):
        m = min(piece, count - k0)
        lo = min(a0, b0) + k0
        sums = WindowSums(x[lo : max(a0 + wa, b0 + wb) + k0 + m - 1], ENDS)
        ma, bad_a = sums.means(a0 + k0 - lo, wa, m)
        mb, bad_b = sums.means(b0 + k0 - lo, wb, m)
        motion, unsure = motions_mm(
            ma,
            mb,
            line=line,
            area_step=config.area_step,
            min_elongation=config.min_elongation,
            limit_mm=limit,
            bound=sums.error_bound(min(wa, wb)),
            line_across_mm=config.line_across_mm,
            line_length_mm=length_mm,
        )
        changed[k0 : k0 + m], above[k0 : k0 + m] = np.isnan(motion), motion > limit
        redo = np.flatnonzero(unsure | bad_a | bad_b) + k0
        if redo.size:
            ra, rb = exact_means(x, a0 + redo, wa), exact_means(x, b0 + redo, wb)
            for k, u, v in zip(redo.tolist(), ra, rb, strict=True):
                mm = motion_mm(u, v, line=line, config=config, length_mm=length_mm)
                changed[k], above[k] = math.isnan(mm), mm > limit
    return changed, above
