"""The track geometry of :mod:`taxelkit.smart.track_geometry`, fed a chunk at a time.

Level 3 looks at a whole contact segment: rolling means over the smoothing
window, motions that must hold for some frames, the legs and corners of a
point's path. Streamed, the segment grows a chunk at a time; the classes below
carry just enough state across chunks (the last running sums, run lengths, the
last breakpoint) that each chunk costs the same whatever the segment's age,
and each gives bit for bit what the batch function gives on the whole track:

* sums are continued in the batch's order (``np.cumsum`` adds one term after
  the other, so a running sum carried across chunks is the same float);
* comparisons use the same expressions on the same floats.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.track_geometry import drawn_half_mm, spaced_points
from taxelkit.smart.verdict_holds import Sustained

__all__ = [
    "CarriedShift",
    "CornerScan",
    "LegScan",
    "RollingMean",
    "RunningSum",
    "Sustained",
    "mean_axis_deg",
    "turn_from",
]


class RunningSum:
    """``np.cumsum`` along axis 0 of a sequence that arrives in chunks.

    Parameters
    ----------
    width : int
        Columns of each row (``(m, width)`` chunks), or 0 for ``(m,)`` chunks.
    """

    def __init__(self, width: int = 0) -> None:
        self.total: NDArray[np.float64] = np.zeros(width) if width else np.zeros(())

    def push(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """Cumulative sums of the rows of ``x``, continuing the earlier chunks."""
        if x.shape[0] == 0:
            return x.astype(np.float64)
        # the total added to the first row, then summed on: the floats of
        # np.cumsum over [total, *x] (each step adds one row to the same sum)
        c = np.array(x, dtype=np.float64)
        c[0] += self.total
        np.cumsum(c, axis=0, out=c)
        self.total = c[-1].copy()
        return c


class RollingMean:
    """:func:`~taxelkit.smart.track_geometry.rolling_mean` of a sequence arriving in chunks.

    Keeps the last ``w`` running sums (``w`` rows), nothing else.

    Parameters
    ----------
    w : int
        Window, frames.
    width : int
        As :class:`RunningSum`.
    """

    def __init__(self, w: int, width: int = 0) -> None:
        self.w = int(w)
        self.seen = 0
        self._sum = RunningSum(width)
        self._tail: NDArray[np.float64] = np.zeros((0, width) if width else (0,))

    def push(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """Means of the last ``w`` rows (fewer at the start) at each row of ``x``."""
        m, w = x.shape[0], self.w
        c = self._sum.push(x)
        hist = np.concatenate([self._tail, c])
        lead = self._tail.shape[0]
        if self.seen >= w:  # every row has w rows before it: the same floats, fewer calls
            self.seen += m
            self._tail = hist[-w:]
            steady: NDArray[np.float64] = (c - hist[lead - w : lead + m - w]) / w
            return steady
        j = self.seen + np.arange(m)
        out = c.copy()
        late = max(0, w - self.seen)  # rows from here on have w rows before them
        if late < m:
            out[late:] -= hist[lead + late - w : lead + m - w]
        n = np.minimum(j + 1, w).reshape((-1,) + (1,) * (x.ndim - 1))
        self.seen += m
        self._tail = hist[-w:]
        result: NDArray[np.float64] = out / n
        return result


class LegScan:
    """:func:`~taxelkit.smart.track_geometry.orthogonal_turn` along a path arriving in chunks.

    Holds the last breakpoint and the last three legs.

    Parameters
    ----------
    leg_mm : float
    window_deg : (float, float)
    """

    def __init__(self, leg_mm: float, window_deg: tuple[float, float]) -> None:
        self.leg = float(leg_mm)
        self.lo = np.cos(np.deg2rad(window_deg[1]))
        self.hi = np.cos(np.deg2rad(window_deg[0]))
        self.base: tuple[float, float] | None = None
        self.legs: list[tuple[float, float]] = []
        self.found: int | None = None

    def push(self, points: NDArray[np.float64], index: NDArray[np.intp]) -> int | None:
        """Feed path points ``(m, 2)`` numbered ``index``; the first turn's number, if any."""
        if self.found is not None or points.shape[0] == 0:
            return self.found
        start = 0
        if self.base is None:  # the scan's starting point
            self.base = (float(points[0, 0]), float(points[0, 1]))
            start = 1
        # NumPy finds where a leg may end; the scan's own arithmetic decides there
        i = start
        m = points.shape[0]
        while i < m:
            bx, by = self.base
            d_np = np.hypot(points[i:, 0] - bx, points[i:, 1] - by)
            near = np.flatnonzero(d_np >= self.leg * (1.0 - 1e-9))
            if near.size == 0:
                return None
            i += int(near[0])
            x, y = float(points[i, 0]), float(points[i, 1])
            dx, dy = x - bx, y - by
            d = math.hypot(dx, dy)
            if d < self.leg:
                i += 1
                continue
            self.legs = [*self.legs[-2:], (dx / d, dy / d)]
            self.base = (x, y)
            for back in (2, 3):
                if len(self.legs) >= back:
                    ux, uy = self.legs[-back]
                    c = ux * self.legs[-1][0] + uy * self.legs[-1][1]
                    if self.lo <= c <= self.hi:
                        self.found = int(index[i])
                        return self.found
            i += 1
        return None


class CornerScan:
    """:func:`~taxelkit.smart.track_geometry.corner_turn` along a path arriving in chunks.

    A corner at point ``i`` needs the chord from the point one leg of path
    before ``i`` (``a``) and the chord to the point one leg after (``b``,
    the frame at which it is seen). ``a`` is known when ``i`` arrives, so a
    point whose incoming chord is too short (a resting or jittering point)
    never becomes a candidate; candidates wait for their ``b``. Kept: the
    candidates and the path since one leg before the newest point.

    The path of a point held still for more than :data:`MAX_ROWS` frames
    within one leg is cut to its last rows (the positions dropped differ from
    those kept by the rounding of the rolling mean, ~1e-10 mm), so memory
    stays bounded.

    Parameters
    ----------
    leg_mm : float
    window_deg : (float, float)
    step_mm : float
        The path is thinned by :func:`~taxelkit.smart.track_geometry.spaced_points`
        first (0: every point).
    """

    #: Most path points kept for the incoming chords.
    MAX_ROWS = 4096

    def __init__(
        self, leg_mm: float, window_deg: tuple[float, float], step_mm: float = 0.0
    ) -> None:
        self.d = float(leg_mm)
        self.step = float(step_mm)
        self._last: tuple[float, float] | None = None  # the last point the thinning kept
        self.lo = np.cos(np.deg2rad(window_deg[1]))
        self.hi = np.cos(np.deg2rad(window_deg[0]))
        self._p = np.zeros((0, 2))
        self._arc = np.zeros(0)
        self._idx = np.zeros(0, dtype=np.intp)
        self._cand = np.zeros(0, dtype=np.intp)  # candidate rows, oldest first
        self._cand_u = np.zeros((0, 2))
        self._cand_nu = np.zeros(0)
        self.found: int | None = None

    def push(self, points: NDArray[np.float64], index: NDArray[np.intp]) -> int | None:
        """Feed path points ``(m, 2)`` numbered ``index``; the first corner's number, if any."""
        if self.found is not None or points.shape[0] == 0:
            return self.found
        idx = np.asarray(index, dtype=np.intp)
        if self.step > 0.0:
            rows = spaced_points(points, self.step, self._last)
            if rows.size == 0:
                return None
            points, idx = points[rows], idx[rows]
            self._last = (float(points[-1, 0]), float(points[-1, 1]))
        if self._arc.size:
            steps = np.hypot(*np.diff(np.concatenate([self._p[-1:], points]), axis=0).T)
            arc = np.cumsum(np.concatenate([self._arc[-1:], steps]))[1:]
        else:
            steps = np.hypot(*np.diff(points, axis=0).T)
            arc = np.concatenate([[0.0], np.cumsum(steps)])
            steps = np.concatenate([[1.0], steps])  # the first point is always kept
        keep = steps != 0.0  # a repeated point: same chords, same corner, same frame
        first_row = self._arc.size
        self._p = np.concatenate([self._p, points[keep]])
        self._arc = np.concatenate([self._arc, arc[keep]])
        self._idx = np.concatenate([self._idx, idx[keep]])
        p, arc_all, d = self._p, self._arc, self.d
        new = np.arange(first_row, arc_all.size)
        a = np.clip(np.searchsorted(arc_all, arc_all[new] - d, side="right") - 1, 0, None)
        u = p[new] - p[a]
        nu = np.hypot(*u.T)
        pre = (arc_all[new] >= d) & (nu >= 0.7 * d)
        self._cand = np.concatenate([self._cand, new[pre]])
        self._cand_u = np.concatenate([self._cand_u, u[pre]])
        self._cand_nu = np.concatenate([self._cand_nu, nu[pre]])
        i = self._cand
        b = np.searchsorted(arc_all, arc_all[i] + d, side="left")
        done = b < arc_all.size
        if np.any(done):
            v = p[b[done]] - p[i[done]]
            nv = np.hypot(*v.T)
            ok = nv >= 0.7 * d
            uu, nuu = self._cand_u[done], self._cand_nu[done]
            cos = np.sum(uu * v, axis=1) / np.where(ok, nuu * nv, 1.0)
            hits = b[done][ok & (cos >= self.lo) & (cos <= self.hi)]
            if hits.size:
                self.found = int(self._idx[hits.min()])
                return self.found
            wait = ~done
            self._cand = i[wait]
            self._cand_u = self._cand_u[wait]
            self._cand_nu = self._cand_nu[wait]
        self._trim()
        return None

    def _trim(self) -> None:
        arc = self._arc
        cut = int(np.searchsorted(arc, arc[-1] - self.d, side="right")) - 1  # oldest a to come
        if self._cand.size:
            cut = min(cut, int(self._cand[0]))
        cut = max(cut, arc.size - self.MAX_ROWS if not self._cand.size else 0, 0)
        if cut:
            self._p, self._arc, self._idx = self._p[cut:], arc[cut:], self._idx[cut:]
            self._cand = self._cand - cut


class CarriedShift:
    """:func:`~taxelkit.smart.track_geometry.carried_shift` of a track arriving in chunks.

    Carries the sum of the shifts of the stretches done (an exclusive running
    sum, in the batch's order), the current stretch's anchor and the centre
    at its reference, and the last centre seen.
    """

    def __init__(self) -> None:
        self.carried = np.zeros(2)
        self.stretch = 0  # anchor of the current stretch
        self.stretch_ref: NDArray[np.float64] | None = None  # centre at its reference
        self.last_centre = np.zeros(2)

    def before(
        self,
        pieces: list[tuple[int, int, int, NDArray[np.float64] | None]],
        centre: NDArray[np.float64],
    ) -> NDArray[np.float64]:
        """The stretches done before each row ``(m, 2)``, mm.

        ``pieces`` are the chunk's runs ``(lo, hi, anchor, centre at the
        anchor's reference or None before it)``; ``centre`` its smoothed
        centres ``(m, 2)``.
        """
        out = np.empty((centre.shape[0], 2))
        for lo, hi, a, ref_centre in pieces:
            if a != self.stretch:  # the previous stretch ended on the frame before
                end = centre[lo - 1] if lo > 0 else self.last_centre
                if self.stretch_ref is not None:
                    self.carried = self.carried + (end - self.stretch_ref)
                self.stretch, self.stretch_ref = a, None
            if ref_centre is not None:
                self.stretch_ref = ref_centre
            out[lo:hi] = self.carried
        self.last_centre = centre[-1].copy()
        return out


def drawn_length_mm(rows: NDArray[np.float64]) -> NDArray[np.float64]:
    """Drawn length of each row's line, mm (twice its :func:`drawn_half_mm`)."""
    out: NDArray[np.float64] = 2.0 * drawn_half_mm(rows[:, 5], rows[:, 6:8])
    return out


def turn_from(angle: NDArray[np.float64], ref: Any) -> NDArray[np.float64]:
    """Axial turn of each angle from ``ref`` (deg, one or one per angle), in [0, 90] deg.

    The arithmetic of :func:`~taxelkit.smart.track_geometry.turn`.
    """
    out: NDArray[np.float64] = np.abs((angle - ref + 90.0) % 180.0 - 90.0)
    return out


def mean_axis_deg(theta_deg: NDArray[np.float64]) -> float:
    """Mean of axial orientations (doubled-angle vectors summed in order), deg."""
    if theta_deg.size == 0:
        return float("nan")
    t = np.deg2rad(2.0 * theta_deg)
    # each column summed in order, as np.cumsum of the stacked vectors along axis 0
    sx, sy = np.cumsum(np.cos(t))[-1], np.cumsum(np.sin(t))[-1]
    return float(0.5 * np.rad2deg(np.arctan2(sy, sx)))
