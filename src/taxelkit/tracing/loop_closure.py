"""When a trace may be called closed: back at its start around a plausible contour.

Coming back near the start is not enough: on a rough plate a tracer that
follows noise can circle a bump a few millimetres wide and return to where it
began. A loop is *plausible* when

* its enclosed area (shoelace formula on the commanded points, closed back to
  the first) is at least the area of the array's footprint: a contour that
  fits under the array is seen whole at once, it cannot be followed by moving
  the array along it (Section IV), so a smaller loop is not a traced contour;
* its isoperimetric quotient ``4 pi A / L^2`` (1 for a circle) is at least
  :data:`DEFAULT_MIN_COMPACTNESS`: the path is not a long wander around a
  small area. The threshold leaves room for sharp re-entrant outlines: the
  pentagram has 0.27, the deep star of :mod:`taxelkit.world.reentrant` 0.14,
  the L 0.50. Spikier outlines need a lower ``min_loop_compactness`` (a
  twelve-pointed star with notches at a quarter of its radius has 0.03).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError

__all__ = [
    "DEFAULT_MIN_COMPACTNESS",
    "enclosed_area_mm2",
    "footprint_area_mm2",
    "is_plausible_loop",
    "isoperimetric_quotient",
]

#: Smallest isoperimetric quotient ``4 pi A / L^2`` of a closed trace.
DEFAULT_MIN_COMPACTNESS = 0.05


def _points(points_mm: ArrayLike) -> NDArray[np.float64]:
    p = np.asarray(points_mm, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 2:
        raise InputError(f"points_mm must have shape (K, 2), got {p.shape}")
    return p


def enclosed_area_mm2(points_mm: ArrayLike) -> float:
    """Signed area of the polygon through the points, closed back to the first, mm^2.

    Parameters
    ----------
    points_mm : (K, 2) float, mm

    Returns
    -------
    float, mm^2
        Positive counter-clockwise (a raised figure traced with its raised
        side on the left); 0 for fewer than 3 points.

    Examples
    --------
    >>> enclosed_area_mm2([(0, 0), (2, 0), (2, 3), (0, 3)])
    6.0
    """
    p = _points(points_mm)
    if p.shape[0] < 3:
        return 0.0
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def isoperimetric_quotient(points_mm: ArrayLike) -> float:
    """``4 pi |A| / L^2`` of the closed polygon through the points (1 for a circle).

    Parameters
    ----------
    points_mm : (K, 2) float, mm

    Returns
    -------
    float in [0, 1]
        0 for a degenerate polygon.

    Examples
    --------
    >>> round(isoperimetric_quotient([(0, 0), (1, 0), (1, 1), (0, 1)]), 4)  # pi / 4
    0.7854
    """
    p = _points(points_mm)
    if p.shape[0] < 3:
        return 0.0
    closed = np.vstack([p, p[:1]])
    length = float(np.sum(np.hypot(*np.diff(closed, axis=0).T)))
    if length <= 0.0:
        return 0.0
    return 4.0 * math.pi * abs(enclosed_area_mm2(p)) / length**2


def footprint_area_mm2(element_offsets_mm: ArrayLike) -> float:
    """Area of the square block the active elements cover, mm^2.

    Parameters
    ----------
    element_offsets_mm : (rows, cols, 2) float, mm
        Element centres relative to the array centre.

    Returns
    -------
    float, mm^2
        ``(cols pitch_x) (rows pitch_y)``: 18 x 18 = 324 mm^2 for the 6 x 6
        block at 3 mm of paper 000 (one pitch per element, centre to centre
        span plus one pitch).
    """
    e = np.asarray(element_offsets_mm, dtype=np.float64)
    if e.ndim != 3 or e.shape[2] != 2 or min(e.shape[:2]) < 1:
        raise InputError(f"element_offsets_mm must have shape (rows, cols, 2), got {e.shape}")
    rows, cols = e.shape[:2]
    span_x = float(np.ptp(e[..., 0]))
    span_y = float(np.ptp(e[..., 1]))
    width = span_x * cols / (cols - 1) if cols > 1 else span_y / max(rows - 1, 1)
    height = span_y * rows / (rows - 1) if rows > 1 else width
    return float(width * height)


def is_plausible_loop(
    points_mm: ArrayLike,
    *,
    min_area_mm2: float,
    min_compactness: float = DEFAULT_MIN_COMPACTNESS,
) -> bool:
    """Whether a trace that came back to its start encloses a plausible contour.

    Parameters
    ----------
    points_mm : (K, 2) float, mm
        The commanded points of the loop.
    min_area_mm2 : float, mm^2
        Smallest enclosed area (:func:`footprint_area_mm2` of the array).
    min_compactness : float
        Smallest :func:`isoperimetric_quotient`.

    Returns
    -------
    bool

    Examples
    --------
    >>> square = [(0, 0), (30, 0), (30, 30), (0, 30)]
    >>> is_plausible_loop(square, min_area_mm2=324.0), is_plausible_loop(square, min_area_mm2=1e4)
    (True, False)
    """
    p = _points(points_mm)
    return (
        abs(enclosed_area_mm2(p)) >= min_area_mm2 and isoperimetric_quotient(p) >= min_compactness
    )
