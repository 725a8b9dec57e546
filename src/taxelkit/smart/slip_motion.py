"""The slip detector's window means and motion measure, for many frames at once.

:class:`~taxelkit.smart.slip_scan.SlipScanner` decides every frame from
window means of its features and the motion between two windows
(:meth:`~taxelkit.smart.slip_scan.SlipScanner.motion_mm`, the rule of
:mod:`taxelkit.smart.slip`). The per-frame rule sums each window row by row
(``w`` additions a frame) and measures one frame at a time in Python; here
the sums come from cumulative sums restarted every few rows (two or three
terms a window) and the measure is vectorised over frames.

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

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "AXIS_MIN_NORM",
    "ENDS",
    "MARGIN",
    "WindowSums",
    "exact_means",
    "motions_mm",
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
    """Means of windows of consecutive rows, from cumulative sums restarted every ``block`` rows.

    Parameters
    ----------
    x : (n, F) float
    block : int
        Rows between restarts (>= the longest window asked for): a window's
        sum is then the difference of two cumulative sums of one block, or
        one block's tail plus the next block's head.
    nan_columns : slice
        Columns whose NaN (a value not measured) the caller handles: a
        window's mean there is NaN exactly where it holds a NaN (as the
        row-by-row sum); any other NaN or infinity marks the window bad.
    """

    def __init__(self, x: NDArray[np.float64], block: int, nan_columns: slice = slice(0)) -> None:
        n, f = x.shape
        self.block = max(1, int(block))
        self._odd: NDArray[np.intp] | None = None
        self._nan: NDArray[np.intp] | None = None
        if not np.isfinite(x).all():
            x = self._set_aside(x, nan_columns)
        self._big = float(np.max(np.abs(x))) if x.size else 0.0
        b = self.block
        nb = -(-n // b)
        pad = np.zeros((nb * b, f))
        pad[:n] = x
        self._local = np.cumsum(pad.reshape(nb, b, f), axis=1).reshape(nb * b, f)

    def _set_aside(self, x: NDArray[np.float64], nan_columns: slice) -> NDArray[np.float64]:
        """``x`` with its non-finite values at 0, counted (NaN in ``nan_columns``, others)."""
        f = x.shape[1]
        nan = np.isnan(x)
        allowed = np.zeros(f, bool)
        allowed[nan_columns] = True
        odd = np.asarray(np.isinf(x).any(axis=1) | (nan & ~allowed).any(axis=1))
        if odd.any():
            x = np.where(odd[:, None] | np.isinf(x), 0.0, x)
            self._odd = np.concatenate([[0], np.cumsum(odd)])
        if nan.any():
            x = np.where(nan, 0.0, x)
            self._nan = np.concatenate([np.zeros((1, f), np.intp), np.cumsum(nan, axis=0)])
        return x

    def means(
        self, start: int, w: int, count: int
    ) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
        """Means ``(count, F)`` of the windows of ``w`` rows at ``start + k``, and the bad ones.

        Each mean is within :meth:`error_bound` of the row-by-row mean.
        """
        if w > self.block:
            raise ValueError(f"w must be at most the block, {self.block}, got {w}")
        b, local = self.block, self._local
        p = start + np.arange(count)
        end = p + w - 1
        off = p % b
        block_end = p - off + b - 1
        before = np.where(off[:, None] > 0, local[p - 1], 0.0)
        two = (end > block_end)[:, None]  # the window runs into the next block
        total = np.where(two, (local[block_end] - before) + local[end], local[end] - before)
        out: NDArray[np.float64] = total / w
        bad = np.zeros(count, bool)
        if self._odd is not None:
            bad = (self._odd[p + w] - self._odd[p]) > 0
        if self._nan is not None:
            out[(self._nan[p + w] - self._nan[p]) > 0] = np.nan
        return out, bad

    def error_bound(self, w: int) -> float:
        """Bound on a window mean's distance from the row-by-row mean (finite windows).

        Three cumulative sums of at most ``b`` rows (each rounded by at most
        ``b eps`` times its ``b max|x|``) and two additions, divided by ``w``;
        the row-by-row sum rounds by at most ``w eps max|x|`` on the mean:
        ``((3 b^2 + 4 b) / w + w + 2) eps max|x|``.
        """
        b = self.block
        return ((3.0 * b * b + 4.0 * b) / w + w + 2.0) * _EPS * self._big + 1e-300


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
    sums = WindowSums(x, w, nan_columns)
    return (*sums.means(0, w, m), sums.error_bound(w))


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

#: Columns of a line's two ends (NaN where not measured).
ENDS = slice(7, 11)


def _axis_rad(c2: NDArray[np.float64], s2: NDArray[np.float64]) -> NDArray[np.float64]:
    out: NDArray[np.float64] = 0.5 * np.arctan2(s2, c2)
    return out


def _line_motion(
    ref: NDArray[np.float64], cur: NDArray[np.float64], unsure: NDArray[np.bool_]
) -> NDArray[np.float64]:
    """A line's two ends along the bisector of the axes, mm (both must move the same way)."""
    c2, s2 = ref[:, _C2] + cur[:, _C2], ref[:, _S2] + cur[:, _S2]
    unsure |= np.hypot(c2, s2) < AXIS_MIN_NORM
    th = _axis_rad(c2, s2)
    ax, ay = np.cos(th), np.sin(th)
    e1, e2 = cur[:, _END1] - ref[:, _END1], cur[:, _END2] - ref[:, _END2]
    d1, d2 = e1[:, 0] * ax + e1[:, 1] * ay, e2[:, 0] * ax + e2[:, 1] * ay
    both = np.where(d1 * d2 > 0.0, np.minimum(np.abs(d1), np.abs(d2)), 0.0)
    # ends not measured (NaN as in the row-by-row means): the centre less the change of length
    dx, dy = cur[:, _CX] - ref[:, _CX], cur[:, _CY] - ref[:, _CY]
    centre = np.abs(dx * ax + dy * ay) - np.abs(cur[:, _HALF] - ref[:, _HALF])
    out: NDArray[np.float64] = np.where(np.isnan(d1 + d2), centre, both)
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
    limit_mm : float
        The limit the motion is compared with, mm.
    bound : float
        Bound on the means' rounding (:meth:`WindowSums.error_bound`).

    Returns
    -------
    motion : (n,) float, mm
        NaN where the mean area changed by more than ``area_step``.
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
            motion = _line_motion(ref, cur, unsure)
        else:
            motion = _face_motion(ref, cur, unsure, min_elongation, tol)
    unsure |= ~changed & (np.abs(motion - limit_mm) <= tol)
    out: NDArray[np.float64] = np.where(changed, np.nan, motion)
    return out, unsure
