"""Relief specimens outside paper 000's five shapes, for open-set recognition.

Each shape is a simple polygon centred on its area centroid and scaled so
that the circle about the centroid through its farthest vertex has the given
diameter, like :func:`~taxelkit.world.relief.relief_shape`, then
rotated and moved. Curved outlines (ellipse, semicircle) are fine polygons of
:data:`CURVE_VERTICES` vertices. Several of them are *histogram twins* of a
stored shape - the same direction histogram, so chain-symbolizing (Eq. 13)
cannot tell them apart: the pentagon (the star's five directions 72 deg
apart, equal shares), the cross and the L-shape (the square's four directions,
equal shares).

==============  ===================================================
name            outline (unit circumscribed radius before scaling)
==============  ===================================================
ellipse         axes ratio 1 : :data:`ELLIPSE_AXIS_RATIO`
l-shape         2 x 2 square minus its upper-right 1 x 1 quarter
pentagon        regular, 5 vertices
rectangle       sides 2 : 1
octagon         regular, 8 vertices
cross           plus sign of arms 1/3 of its width
rhombus         interior angles 60 and 120 deg
trapezoid       isosceles, parallel sides 2 : 1, height 1
right-triangle  legs 2 : 1
semicircle      half disc
t-shape         bar 3 x 1 on a stem 1 x 2
heptagon        regular, 7 vertices
==============  ===================================================
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError
from taxelkit.world.contour_relief import PolygonRelief
from taxelkit.world.relief import relief_from_vertices

__all__ = [
    "CURVE_VERTICES",
    "ELLIPSE_AXIS_RATIO",
    "OUT_OF_SET_SHAPES",
    "open_set_outline_mm",
    "open_set_relief",
]

#: Vertices of the polygons standing in for curved outlines.
CURVE_VERTICES = 180
#: Minor / major axis of the ellipse specimen (dimensionless).
ELLIPSE_AXIS_RATIO = 0.6


#: The plus sign: arms a third of its width, counter-clockwise from the bottom arm.
_CROSS = [(1, 0), (2, 0), (2, 1), (3, 1), (3, 2), (2, 2)]
_CROSS += [(2, 3), (1, 3), (1, 2), (0, 2), (0, 1), (1, 1)]


def _regular(n: int) -> NDArray[np.float64]:
    a = math.pi / 2 + 2 * math.pi * np.arange(n) / n
    return np.column_stack([np.cos(a), np.sin(a)])


def _centroid(pts: NDArray[np.float64]) -> NDArray[np.float64]:
    """Area centroid of a simple polygon (shoelace formula)."""
    x, y = pts[:, 0], pts[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = float(cross.sum()) / 2
    out: NDArray[np.float64] = np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()])
    out /= 6 * area
    return out


def _curve(t: NDArray[np.float64], rx: float, ry: float) -> NDArray[np.float64]:
    return np.column_stack([rx * np.cos(t), ry * np.sin(t)])


def _unit_outlines() -> dict[str, NDArray[np.float64]]:
    full = 2 * math.pi * np.arange(CURVE_VERTICES) / CURVE_VERTICES
    half = math.pi * np.arange(CURVE_VERTICES + 1) / CURVE_VERTICES
    raw = {
        "ellipse": _curve(full, 1.0, ELLIPSE_AXIS_RATIO),
        "l-shape": [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)],
        "pentagon": _regular(5),
        "rectangle": [(0, 0), (2, 0), (2, 1), (0, 1)],
        "octagon": _regular(8),
        "cross": _CROSS,
        "rhombus": [(0, 0), (1, 0), (1.5, math.sqrt(3) / 2), (0.5, math.sqrt(3) / 2)],
        "trapezoid": [(0, 0), (2, 0), (1.5, 1), (0.5, 1)],
        "right-triangle": [(0, 0), (2, 0), (0, 1)],
        "semicircle": _curve(half, 1.0, 1.0),
        "t-shape": [(1, 0), (2, 0), (2, 2), (3, 2), (3, 3), (0, 3), (0, 2), (1, 2)],
        "heptagon": _regular(7),
    }
    out = {}
    for name, v in raw.items():
        pts = np.asarray(v, dtype=np.float64)
        pts = pts - _centroid(pts)  # the area centroid (inside every shape here) at the origin
        out[name] = pts / np.max(np.hypot(pts[:, 0], pts[:, 1]))
    return out


_UNIT = _unit_outlines()

#: Names of the out-of-set specimens, in a fixed order.
OUT_OF_SET_SHAPES: tuple[str, ...] = tuple(_UNIT)


def open_set_outline_mm(
    name: str,
    *,
    diameter_mm: float = 90.0,
    rotation_deg: float = 0.0,
    offset_mm: ArrayLike = (0.0, 0.0),
) -> NDArray[np.float64]:
    """Vertices ``(V, 2)`` in mm of an out-of-set outline.

    Parameters
    ----------
    name : str
        One of :data:`OUT_OF_SET_SHAPES`.
    diameter_mm : float, mm
        Diameter of the circle about the origin through the farthest vertex (> 0).
    rotation_deg : float, deg
        Counter-clockwise rotation about the centre.
    offset_mm : (2,) float, mm
        Centre on the plate.

    Returns
    -------
    (V, 2) float64, mm

    Raises
    ------
    InputError
        For an unknown name (listing the known ones) or a non-positive diameter.
    """
    if name not in _UNIT:
        raise InputError(f"unknown shape {name!r}; known: {', '.join(OUT_OF_SET_SHAPES)}")
    if not (math.isfinite(diameter_mm) and diameter_mm > 0):
        raise InputError(f"diameter_mm must be a finite number > 0, got {diameter_mm!r}")
    a = math.radians(rotation_deg)
    rot = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
    off = np.asarray(offset_mm, dtype=np.float64).reshape(2)
    out: NDArray[np.float64] = (diameter_mm / 2) * _UNIT[name] @ rot.T + off
    return out


def open_set_relief(
    name: str,
    *,
    diameter_mm: float = 90.0,
    rotation_deg: float = 0.0,
    offset_mm: ArrayLike = (0.0, 0.0),
    step_height_um: float = 200.0,
) -> PolygonRelief:
    """A raised out-of-set specimen (see :func:`open_set_outline_mm`).

    Parameters
    ----------
    name, diameter_mm, rotation_deg, offset_mm
        As :func:`open_set_outline_mm`.
    step_height_um : float, um
        Height of the step (> 0).

    Returns
    -------
    PolygonRelief

    Examples
    --------
    >>> r = open_set_relief("rectangle", diameter_mm=50.0)
    >>> float(r.height_mm(0.0, 0.0)), float(r.height_mm(0.0, 20.0))
    (0.2, 0.0)
    """
    outline = open_set_outline_mm(
        name, diameter_mm=diameter_mm, rotation_deg=rotation_deg, offset_mm=offset_mm
    )
    return relief_from_vertices(outline, step_height_um=step_height_um)
