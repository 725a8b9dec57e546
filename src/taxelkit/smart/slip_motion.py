"""The slip detector's motion measure over many frames at once.

:class:`~taxelkit.smart.slip_scan.SlipScanner` decides frame by frame with
:meth:`~taxelkit.smart.slip_scan.SlipScanner.motion_mm` (scalar Python
arithmetic); here the same arithmetic runs on the window means of a whole
chunk: the features' window means (summed in a fixed order, so a frame's
means do not depend on the chunking), and the motions of a line and of a
face, operation for operation as the scalar rule. Library functions
(``atan2``, ``hypot``, ``cos``) may differ from Python's ``math`` in the last
bit, so a motion within :data:`GUARD_MM` of a limit is decided by the scalar
rule instead.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "AREA",
    "C2",
    "COV",
    "CX",
    "CY",
    "ELONG",
    "END1",
    "END2",
    "GUARD_MM",
    "HALF",
    "N_FEATURES",
    "S2",
    "Windows",
    "motions_area",
    "motions_line",
    "window_means",
]

#: Feature columns averaged over the windows (from the rows of segment_scan.ROW_COLUMNS):
#: centre x, y (mm), area (mm^2), doubled-angle axis cos, sin, half-length (mm), elongation.
CX, CY, AREA, C2, S2, HALF, ELONG = range(7)
#: A line's two ends, x y (mm), in a consistent order.
END1, END2 = slice(7, 9), slice(9, 11)
#: A face's second central moments xx, yy, xy, mm^2.
COV = slice(11, 14)
#: Feature columns in all.
N_FEATURES = 14


def window_means(x: NDArray[np.float64], w: int) -> NDArray[np.float64]:
    """Mean of each ``w`` consecutive rows ``(n - w + 1, F)``; empty when ``n < w``."""
    n = x.shape[0] - w + 1
    if n <= 0:
        return np.zeros((0, x.shape[1]))
    out = x[:n].copy()
    for j in range(1, w):  # in a fixed order: the same floats whatever the chunking
        out += x[j : j + n]
    out /= w
    return out


#: Motions this close to a decision's limit are recomputed by the scalar rule, mm.
GUARD_MM = 1e-9


def motions_line(ref: NDArray[np.float64], cur: NDArray[np.float64]) -> NDArray[np.float64]:
    """A line's motion (:meth:`SlipScanner.motion_mm`), rows ``(K, F)``; NaN not yet applied."""
    dx, dy = cur[:, CX] - ref[:, CX], cur[:, CY] - ref[:, CY]
    th = 0.5 * np.arctan2(ref[:, S2] + cur[:, S2], ref[:, C2] + cur[:, C2])
    ax, ay = np.cos(th), np.sin(th)
    e1, e2 = cur[:, END1] - ref[:, END1], cur[:, END2] - ref[:, END2]
    d1, d2 = e1[:, 0] * ax + e1[:, 1] * ay, e2[:, 0] * ax + e2[:, 1] * ay
    a1, a2 = np.abs(d1), np.abs(d2)
    both = np.where(d1 * d2 > 0.0, np.where(a2 < a1, a2, a1), 0.0)  # min(|d1|, |d2|)
    centre = np.abs(dx * ax + dy * ay) - np.abs(cur[:, HALF] - ref[:, HALF])
    out: NDArray[np.float64] = np.where(np.isnan(d1 + d2), centre, both)
    return out


class Windows:
    """Means of ``w`` consecutive rows of ``x`` from row ``start`` on (computed once)."""

    def __init__(self, x: NDArray[np.float64], w: int, start: int) -> None:
        self.start = start
        self.means = window_means(x[start:], w)

    def rows(self, a: int, b: int) -> NDArray[np.float64]:
        """The windows starting at rows ``a .. b - 1`` of ``x``."""
        return self.means[a - self.start : b - self.start]


def motions_area(
    ref: NDArray[np.float64], cur: NDArray[np.float64], min_elongation: float
) -> NDArray[np.float64]:
    """A face's motion (:meth:`SlipScanner.motion_mm`), rows ``(K, F)``; NaN not yet applied."""
    dx, dy = cur[:, CX] - ref[:, CX], cur[:, CY] - ref[:, CY]
    moved = np.hypot(dx, dy)
    pos = moved > 0.0
    with np.errstate(invalid="ignore", divide="ignore"):
        nx, ny = dx / moved, dy / moved
    size = []
    for v in (ref[:, COV], cur[:, COV]):
        q = v[:, 0] * nx * nx + v[:, 1] * ny * ny + 2 * v[:, 2] * nx * ny
        size.append(np.sqrt(12.0 * np.where(q > 0.0, q, 0.0)))  # max(0.0, q)
    moved = np.where(pos, moved - 0.5 * np.abs(size[1] - size[0]), moved)
    th_ref = 0.5 * np.arctan2(ref[:, S2], ref[:, C2])
    th_cur = 0.5 * np.arctan2(cur[:, S2], cur[:, C2])
    turn = np.abs(np.mod(th_cur - th_ref + 0.5 * math.pi, math.pi) - 0.5 * math.pi)
    far = turn * ref[:, HALF]
    e_ref, e_cur = ref[:, ELONG], cur[:, ELONG]
    elongated = np.where(e_cur < e_ref, e_cur, e_ref) >= min_elongation  # min(), as Python's
    out: NDArray[np.float64] = np.where(elongated & (far > moved), far, moved)  # max(moved, far)
    return out
