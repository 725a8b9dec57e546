"""Relief specimens of paper 000: a flat plate with a raised relief of fine step height.

This module is the entry point for relief specimens. It builds the named
shapes of the paper - circle, square, triangle, five-pointed star and hexagon
(:data:`SHAPE_NAMES`) - from the diameter of their circumscribed circle in a
documented canonical orientation (:func:`relief_shape`), and polygons from
vertex lists (:func:`relief_from_vertices`). It also re-exports the specimen
classes and the heightmap functions, which live in their own modules:

* :mod:`taxelkit.world.contour_relief` - :class:`PolygonRelief`,
  :class:`CircleRelief` and the :class:`ShapeRelief` protocol;
* :mod:`taxelkit.world.edge` - :class:`EdgeRelief`, a straight step edge;
* :mod:`taxelkit.world.heightmap` - :class:`HeightmapRelief`,
  :func:`load_heightmap`, :func:`relief_from_heightmap`,
  :func:`heightmap_from_relief`.

Conventions shared by all: x, y in mm in the specimen frame, base plane at
``z = 0``, step heights given in um and heights returned in mm, points exactly
on a contour count as raised.
"""

from __future__ import annotations

import math
from typing import Literal, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.world._planar import check_transform, check_vertices, transform_points
from taxelkit.world.contour_relief import (
    CIRCLE_OUTLINE_VERTICES,
    DEFAULT_STEP_HEIGHT_UM,
    CircleRelief,
    PolygonRelief,
    ShapeRelief,
)
from taxelkit.world.edge import EDGE_OUTLINE_HALF_LENGTH_MM, EdgeRelief
from taxelkit.world.heightmap import (
    HeightmapRelief,
    heightmap_from_relief,
    load_heightmap,
    relief_from_heightmap,
)

__all__ = [
    "CIRCLE_OUTLINE_VERTICES",
    "DEFAULT_DIAMETER_MM",
    "DEFAULT_STEP_HEIGHT_UM",
    "EDGE_OUTLINE_HALF_LENGTH_MM",
    "SHAPE_NAMES",
    "STAR_INNER_RADIUS_RATIO",
    "CircleRelief",
    "EdgeRelief",
    "HeightmapRelief",
    "PolygonRelief",
    "ShapeRelief",
    "heightmap_from_relief",
    "load_heightmap",
    "relief_from_heightmap",
    "relief_from_vertices",
    "relief_shape",
]

#: Circumscribed-circle diameter of the named specimens, mm (issue default for
#: the paper-000 plates).
DEFAULT_DIAMETER_MM = 90.0

#: Inner/outer radius ratio of a regular pentagram outline (dimensionless).
#: The five-pointed star is the 10-vertex outline of a regular pentagram: outer
#: vertices at radius ``R`` every 72 deg, inner vertices at radius ``r`` halfway
#: between them. An inner vertex is where two of the pentagram's chords cross;
#: in the triangle formed by the centre, an outer vertex and the neighbouring
#: inner vertex the angles are 36 deg (at the centre), 18 deg (at the outer
#: vertex, half of the 36 deg tip angle) and 126 deg (at the inner vertex), so
#: by the law of sines ``r / R = sin 18 deg / sin 126 deg = 0.381966...``
#: (= 1 / phi**2, phi the golden ratio).
STAR_INNER_RADIUS_RATIO = math.sin(math.radians(18.0)) / math.sin(math.radians(126.0))

#: Names accepted by :func:`relief_shape`.
SHAPE_NAMES: tuple[str, ...] = ("circle", "square", "triangle", "star", "hexagon")

#: Canonical polygon shapes: (number of outer vertices, angle of the first
#: outer vertex from +x in deg, inner/outer radius ratio or None for a convex
#: regular polygon).
_POLYGON_SHAPES: dict[str, tuple[int, float, float | None]] = {
    "square": (4, 45.0, None),
    "triangle": (3, 90.0, None),
    "star": (5, 90.0, STAR_INNER_RADIUS_RATIO),
    "hexagon": (6, 90.0, None),
}


def relief_from_vertices(
    vertices_mm: ArrayLike, *, step_height_um: float = DEFAULT_STEP_HEIGHT_UM
) -> PolygonRelief:
    """A raised polygon from a list of vertices.

    Parameters
    ----------
    vertices_mm : (V, 2) array_like, mm
        Vertices of a simple polygon in either orientation, ``V >= 3``.
    step_height_um : float, um
        Height of the raised polygon (> 0).

    Returns
    -------
    PolygonRelief

    Raises
    ------
    InputError
        See :class:`PolygonRelief`.

    Examples
    --------
    >>> r = relief_from_vertices([(0, 0), (10, 0), (0, 10)], step_height_um=50)
    >>> float(r.height_mm(2.0, 2.0)), float(r.height_mm(8.0, 8.0))
    (0.05, 0.0)
    """
    return PolygonRelief(check_vertices(vertices_mm), step_height_um=step_height_um)


def _unit_shape_vertices(name: str) -> NDArray[np.float64]:
    """Canonical vertices on the unit circumscribed circle, counter-clockwise."""
    n_points, first_deg, inner_ratio = _POLYGON_SHAPES[name]
    if inner_ratio is None:
        angles = np.deg2rad(first_deg + 360.0 / n_points * np.arange(n_points))
        radii = np.ones(n_points)
    else:
        k = np.arange(2 * n_points)
        angles = np.deg2rad(first_deg + 180.0 / n_points * k)
        radii = np.where(k % 2 == 0, 1.0, inner_ratio)
    return np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])


@overload
def relief_shape(
    name: Literal["circle"],
    *,
    diameter_mm: float = DEFAULT_DIAMETER_MM,
    step_height_um: float = DEFAULT_STEP_HEIGHT_UM,
    rotation_deg: float = 0.0,
    offset_mm: tuple[float, float] = (0.0, 0.0),
    scale: float = 1.0,
) -> CircleRelief: ...


@overload
def relief_shape(
    name: Literal["square", "triangle", "star", "hexagon"],
    *,
    diameter_mm: float = DEFAULT_DIAMETER_MM,
    step_height_um: float = DEFAULT_STEP_HEIGHT_UM,
    rotation_deg: float = 0.0,
    offset_mm: tuple[float, float] = (0.0, 0.0),
    scale: float = 1.0,
) -> PolygonRelief: ...


@overload
def relief_shape(
    name: str,
    *,
    diameter_mm: float = DEFAULT_DIAMETER_MM,
    step_height_um: float = DEFAULT_STEP_HEIGHT_UM,
    rotation_deg: float = 0.0,
    offset_mm: tuple[float, float] = (0.0, 0.0),
    scale: float = 1.0,
) -> PolygonRelief | CircleRelief: ...


def relief_shape(
    name: str,
    *,
    diameter_mm: float = DEFAULT_DIAMETER_MM,
    step_height_um: float = DEFAULT_STEP_HEIGHT_UM,
    rotation_deg: float = 0.0,
    offset_mm: tuple[float, float] = (0.0, 0.0),
    scale: float = 1.0,
) -> PolygonRelief | CircleRelief:
    """One of the named specimens of paper 000, sized by its circumscribed circle.

    Canonical orientation (``rotation_deg=0``), centred on the origin with all
    outer vertices on the circle of radius ``R = scale * diameter_mm / 2``:

    * ``"circle"`` - disc of radius ``R`` (:class:`CircleRelief`);
    * ``"square"`` - axis-aligned, vertices at 45, 135, 225, 315 deg (side ``R sqrt 2``);
    * ``"triangle"`` - equilateral, a vertex at +y (90 deg), base parallel to x;
    * ``"star"`` - regular pentagram outline, 10 vertices: outer ones at
      ``R`` from 90 deg (a point at +y) every 72 deg, inner ones at
      ``STAR_INNER_RADIUS_RATIO * R`` halfway between;
    * ``"hexagon"`` - regular, a vertex at +y, two sides parallel to y.

    Polygon vertices run counter-clockwise starting at the first listed angle.
    The shape is scaled, then rotated counter-clockwise by ``rotation_deg``
    about its centre, then its centre is moved to ``offset_mm``.

    Parameters
    ----------
    name : str
        One of :data:`SHAPE_NAMES`.
    diameter_mm : float, mm
        Diameter of the circumscribed circle before scaling (> 0).
    step_height_um : float, um
        Height of the raised shape (> 0).
    rotation_deg : float, deg
        Counter-clockwise rotation about the shape's centre.
    offset_mm : (x, y) float, mm
        Position of the shape's centre on the plate.
    scale : float
        Size factor (> 0) applied to ``diameter_mm``.

    Returns
    -------
    PolygonRelief or CircleRelief

    Raises
    ------
    InputError
        For an unknown name (listing :data:`SHAPE_NAMES`) or an invalid size,
        angle or offset.

    Examples
    --------
    >>> star = relief_shape("star", diameter_mm=90.0)
    >>> star.vertices_mm.shape
    (10, 2)
    >>> float(star.height_mm(0.0, 0.0)), float(star.height_mm(0.0, 46.0))
    (0.2, 0.0)
    """
    if not isinstance(name, str) or name not in SHAPE_NAMES:
        raise InputError(f"unknown shape {name!r}; known shapes: {', '.join(SHAPE_NAMES)}")
    diameter = check_positive("diameter_mm", diameter_mm)
    rot, off, s = check_transform(rotation_deg, offset_mm, scale)
    radius = 0.5 * diameter * s
    if name == "circle":
        return CircleRelief(off, radius, step_height_um=step_height_um)
    verts = transform_points(
        _unit_shape_vertices(name), rotation_deg=rot, offset_mm=off, scale=radius
    )
    return PolygonRelief(verts, step_height_um=step_height_um)
