"""Placing a relief on the plate: scaled, rotated and moved, its heights scaled.

:func:`~taxelkit.world.relief.relief_shape` builds the named specimens in any
pose; :class:`PlacedRelief` does the same for any relief, a user's heightmap
included, without resampling it: a height query maps the point back into the
relief's own frame,

    p_own = centre + R(-rotation) (p - centre - offset) / scale,

and multiplies the height found there by ``height_scale``. The shape is
scaled about ``centre``, rotated counter-clockwise about it, then moved by
``offset_mm`` (the order of ``relief_shape``).

:func:`raised_extent_mm` measures where a heightmap's relief stands (the
centroid of its raised samples and the diameter of the circle about it that
holds them all), so that a heightmap can be given a size like a named shape.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.world._planar import broadcast_xy, check_finite, check_xy
from taxelkit.world.base import Relief
from taxelkit.world.heightmap import HeightmapRelief

__all__ = ["RAISED_FRACTION", "PlacedRelief", "raised_extent_mm"]

#: A heightmap sample is part of the raised relief when it stands above this
#: fraction of the map's highest sample (half: the middle of a step).
RAISED_FRACTION = 0.5


@dataclass(frozen=True, eq=False)
class PlacedRelief:
    """A relief scaled, rotated and moved on the plate, its heights scaled.

    Parameters
    ----------
    base : Relief
    centre_mm : (x, y) float, mm
        Point of ``base`` about which it is scaled and rotated.
    rotation_deg : float, deg
        Counter-clockwise rotation.
    offset_mm : (x, y) float, mm
        Translation applied last (the centre ends at ``centre + offset``).
    scale : float
        Size factor (> 0).
    height_scale : float
        Factor on every height (> 0).

    Examples
    --------
    >>> from taxelkit.world.relief import relief_from_vertices
    >>> bar = relief_from_vertices([(0, -1), (10, -1), (10, 1), (0, 1)], step_height_um=100)
    >>> up = PlacedRelief(bar, rotation_deg=90.0, height_scale=2.0)
    >>> float(up.height_mm(0.0, 5.0)), float(up.height_mm(5.0, 0.0))
    (0.2, 0.0)
    """

    base: Relief
    centre_mm: tuple[float, float] = (0.0, 0.0)
    rotation_deg: float = 0.0
    offset_mm: tuple[float, float] = (0.0, 0.0)
    scale: float = 1.0
    height_scale: float = 1.0

    def __post_init__(self) -> None:
        if not isinstance(self.base, Relief):
            raise InputError(f"base must be a Relief (height_mm), got {type(self.base).__name__}")
        object.__setattr__(self, "centre_mm", check_xy("centre_mm", self.centre_mm))
        object.__setattr__(self, "offset_mm", check_xy("offset_mm", self.offset_mm))
        check_finite("rotation_deg", self.rotation_deg)
        check_positive("scale", self.scale)
        check_positive("height_scale", self.height_scale)

    @property
    def placed_centre_mm(self) -> tuple[float, float]:
        """Where ``centre_mm`` of the base lies on the plate, mm."""
        return (
            self.centre_mm[0] + self.offset_mm[0],
            self.centre_mm[1] + self.offset_mm[1],
        )

    def height_mm(self, x_mm: ArrayLike, y_mm: ArrayLike) -> NDArray[np.float64]:
        """Height at points of the plate, ``(...)`` mm."""
        x, y = broadcast_xy(x_mm, y_mm)
        cx, cy = self.placed_centre_mm
        a = math.radians(self.rotation_deg)
        c, s = math.cos(a), math.sin(a)
        dx, dy = (x - cx) / self.scale, (y - cy) / self.scale
        own_x = self.centre_mm[0] + c * dx + s * dy
        own_y = self.centre_mm[1] - s * dx + c * dy
        out: NDArray[np.float64] = self.height_scale * np.asarray(
            self.base.height_mm(own_x, own_y), dtype=np.float64
        )
        return out


def raised_extent_mm(heightmap: HeightmapRelief) -> tuple[tuple[float, float], float, float]:
    """Centre, diameter and height of a heightmap's raised relief.

    Parameters
    ----------
    heightmap : HeightmapRelief

    Returns
    -------
    centre_mm : (x, y) float, mm
        Centroid of the samples above :data:`RAISED_FRACTION` of the highest.
    diameter_mm : float, mm
        Twice the largest distance from that centroid to a raised sample (for
        the named shapes, about the circumscribed circle's diameter).
    peak_mm : float, mm
        The highest sample.

    Raises
    ------
    InputError
        If no sample stands above the base plane.

    Examples
    --------
    >>> from taxelkit.world.relief import relief_shape, heightmap_from_relief
    >>> hm = heightmap_from_relief(relief_shape("circle", diameter_mm=40.0),
    ...                            pixel_mm=0.5, extent_mm=(-30, 30, -30, 30))
    >>> centre, diameter, peak = raised_extent_mm(hm)
    >>> (round(centre[0], 6) + 0.0, round(diameter, 1), peak)
    (0.0, 40.0, 0.2)
    """
    z = heightmap.heights_mm
    peak = float(z.max())
    if peak <= 0.0:
        raise InputError("the heightmap has no raised relief (every height <= 0)")
    rows, cols = np.nonzero(z > RAISED_FRACTION * peak)
    xs, ys = heightmap.x_mm[cols], heightmap.y_mm[rows]
    cx, cy = float(xs.mean()), float(ys.mean())
    diameter = 2.0 * float(np.max(np.hypot(xs - cx, ys - cy)))
    return (cx, cy), diameter, peak
