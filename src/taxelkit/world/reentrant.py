"""Relief specimens with sharp re-entrant corners, beyond the five of paper 000.

The five paper shapes have one kind of concave corner (the star's 252 deg
notches). These outlines test a tracer where an edge turns back into the
figure:

* ``"l-shape"`` - an L in the square the paper's square would occupy (side
  ``R sqrt 2`` for a circumscribed circle of radius ``R``), arms
  :data:`L_ARM_RATIO` of the side wide: one 270 deg re-entrant corner;
* ``"deep-star"`` - a five-pointed star with notches deeper than the
  pentagram's: inner radius :data:`DEEP_STAR_INNER_RATIO` of the outer one
  (the pentagram's is 0.382), tips of 28 deg and notches of 280 deg.

Both are built like :func:`~taxelkit.world.relief.relief_shape`: canonical
vertices counter-clockwise around the origin, scaled, rotated, then moved.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.world._planar import check_transform, transform_points
from taxelkit.world.contour_relief import DEFAULT_STEP_HEIGHT_UM, PolygonRelief

__all__ = [
    "DEEP_STAR_INNER_RATIO",
    "L_ARM_RATIO",
    "REENTRANT_SHAPE_NAMES",
    "reentrant_relief",
]

#: Names accepted by :func:`reentrant_relief`.
REENTRANT_SHAPE_NAMES: tuple[str, ...] = ("l-shape", "deep-star")
#: Width of the L's arms as a fraction of its bounding square's side.
L_ARM_RATIO = 0.4
#: Inner/outer radius ratio of the deep star (pentagram: 0.382).
DEEP_STAR_INNER_RATIO = 0.25


def _unit_vertices(name: str) -> NDArray[np.float64]:
    """Canonical vertices for a circumscribed radius of 1, counter-clockwise."""
    if name == "l-shape":
        h = 1.0 / math.sqrt(2.0)  # half-side of the square with corners on the unit circle
        w = 2.0 * h * L_ARM_RATIO
        return np.array(
            [(-h, -h), (h, -h), (h, -h + w), (-h + w, -h + w), (-h + w, h), (-h, h)],
            dtype=np.float64,
        )
    k = np.arange(10)
    angles = np.deg2rad(90.0 + 36.0 * k)
    radii = np.where(k % 2 == 0, 1.0, DEEP_STAR_INNER_RATIO)
    return np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])


def reentrant_relief(
    name: str,
    *,
    diameter_mm: float = 90.0,
    step_height_um: float = DEFAULT_STEP_HEIGHT_UM,
    rotation_deg: float = 0.0,
    offset_mm: tuple[float, float] = (0.0, 0.0),
    scale: float = 1.0,
) -> PolygonRelief:
    """A specimen with sharp re-entrant corners (module docs).

    Parameters
    ----------
    name : str
        One of :data:`REENTRANT_SHAPE_NAMES`.
    diameter_mm : float, mm
        Diameter of the circle through the outer corners (the L: of its
        bounding square), before scaling.
    step_height_um : float, um
        Height of the raised shape (> 0).
    rotation_deg : float, deg
        Counter-clockwise rotation about the shape's centre.
    offset_mm : (x, y) float, mm
        Position of the centre on the plate.
    scale : float
        Size factor (> 0).

    Returns
    -------
    PolygonRelief

    Raises
    ------
    InputError
        For an unknown name or an invalid size, angle or offset.

    Examples
    --------
    >>> ell = reentrant_relief("l-shape", diameter_mm=90.0)
    >>> ell.vertices_mm.shape, float(ell.height_mm(-25.0, 25.0)), float(ell.height_mm(20.0, 20.0))
    ((6, 2), 0.2, 0.0)
    """
    if not isinstance(name, str) or name not in REENTRANT_SHAPE_NAMES:
        raise InputError(
            f"unknown re-entrant shape {name!r}; known: {', '.join(REENTRANT_SHAPE_NAMES)}"
        )
    diameter = check_positive("diameter_mm", diameter_mm)
    rot, off, s = check_transform(rotation_deg, offset_mm, scale)
    verts = transform_points(
        _unit_vertices(name), rotation_deg=rot, offset_mm=off, scale=0.5 * diameter * s
    )
    return PolygonRelief(verts, step_height_um=step_height_um)
