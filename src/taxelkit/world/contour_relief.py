"""Relief specimens bounded by a closed contour: polygons and discs (paper 000).

Every specimen lives in its own frame: x and y in mm on the plate, the base
plane at ``z = 0`` and the top of the raised relief at ``z = step_height``.
Step heights are given in micrometres (``step_height_um``) because the paper's
steps are fine (tens to hundreds of um); all heights come back in mm.

The specimen classes (this module holds the first two):

* :class:`PolygonRelief` - any simple polygon (the square, triangle, star and
  hexagon of :func:`~taxelkit.world.relief.relief_shape`, or a vertex list);
* :class:`CircleRelief` - a disc, queried analytically;
* :class:`~taxelkit.world.edge.EdgeRelief` - a straight edge, one half-plane
  raised (in :mod:`taxelkit.world.edge`).

Height queries are vectorised (one :func:`shapely.intersects_xy` call or one
NumPy expression for all points) and accept coordinate arrays of any shape,
e.g. the ``(P, H, W)`` sample grids of the sensor simulator.

Boundary convention: the relief is a closed set. A point exactly on the
contour is raised, for polygons, circles and edges alike.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Protocol, Self, runtime_checkable

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.world._planar import (
    check_vertices,
    check_xy,
    distance_to_closed_polyline_mm,
    signed_area_mm2,
    transform_points,
)
from taxelkit.world.step_relief import StepRelief

__all__ = [
    "CIRCLE_OUTLINE_VERTICES",
    "DEFAULT_STEP_HEIGHT_UM",
    "CircleRelief",
    "PolygonRelief",
    "ShapeRelief",
]

#: Step height of the raised relief, um (issue default; the optical sensor of
#: paper 000 resolves steps down to 50 um).
DEFAULT_STEP_HEIGHT_UM = 200.0

#: Vertices of the polygon :meth:`CircleRelief.outline_mm` returns by default
#: (chord error ``r (1 - cos(pi / 360))``, 0.0017 mm for r = 45 mm).
CIRCLE_OUTLINE_VERTICES = 360


@runtime_checkable
class ShapeRelief(Protocol):
    """A relief with a closed or straight contour that edge tracing can follow.

    Everything a :class:`~taxelkit.world.base.Relief` has, plus the contour
    for plotting and for measuring tracing error.
    """

    @property
    def step_height_mm(self) -> float:
        """Height of the raised side above the base plane, mm."""
        ...

    def height_mm(self, x_mm: ArrayLike, y_mm: ArrayLike) -> NDArray[np.float64]:
        """Surface height at points, mm (see :class:`~taxelkit.world.base.Relief`)."""
        ...

    def outline_mm(self) -> NDArray[np.float64]:
        """Contour for plotting, ``(V, 2)`` float, mm.

        A closed contour repeats its first vertex at the end; an edge returns
        the two end points of a finite piece of its line.
        """
        ...

    def distance_to_edge_mm(
        self, points_mm: ArrayLike, *, signed: bool = False
    ) -> NDArray[np.float64]:
        """Distance from points to the contour, mm."""
        ...


@dataclass(frozen=True, eq=False)
class PolygonRelief(StepRelief):
    """A plate with a raised simple polygon.

    Parameters
    ----------
    vertices_mm : (V, 2) float, mm
        Polygon vertices in order, ``V >= 3``; a closing copy of the first
        vertex is dropped. Stored counter-clockwise (a clockwise list is
        reversed, keeping the first vertex first) as a read-only array.
    step_height_um : float, keyword-only
        Height of the raised polygon above the base plane, um (> 0).

    Raises
    ------
    InputError
        If the vertices are not finite, fewer than 3, repeat consecutively,
        or do not form a valid simple polygon (self-intersection, zero area),
        or the step height is not positive.

    Notes
    -----
    Equality is identity (``eq=False``): the vertex array is not hashable.
    """

    vertices_mm: NDArray[np.float64]
    step_height_um: float = field(default=DEFAULT_STEP_HEIGHT_UM, kw_only=True)
    _polygon: Any = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self._check_step_height()
        verts = check_vertices(self.vertices_mm)
        polygon = shapely.Polygon(verts)
        if not shapely.is_valid(polygon):
            reason = shapely.is_valid_reason(polygon)
            raise InputError(
                f"vertices_mm must describe a simple polygon with non-zero area, got: {reason}"
            )
        if signed_area_mm2(verts) < 0.0:
            verts = np.roll(verts[::-1], 1, axis=0)
            polygon = shapely.Polygon(verts)
        verts = np.ascontiguousarray(verts)
        verts.setflags(write=False)
        shapely.prepare(polygon)
        object.__setattr__(self, "vertices_mm", verts)
        object.__setattr__(self, "_polygon", polygon)

    def __reduce__(self) -> tuple[Any, ...]:
        # Rebuild through __init__ so that a copy is validated, prepared and read-only.
        return (_polygon_relief, (np.array(self.vertices_mm), self.step_height_um))

    @property
    def area_mm2(self) -> float:
        """Area of the raised polygon, mm^2."""
        return signed_area_mm2(self.vertices_mm)

    def _raised(self, x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.bool_]:
        raised: NDArray[np.bool_] = shapely.intersects_xy(self._polygon, x, y)
        return raised

    def outline_mm(self) -> NDArray[np.float64]:
        """Closed contour for plotting and distance computations.

        Returns
        -------
        (V + 1, 2) float, mm
            The counter-clockwise vertices followed by a copy of the first.
        """
        return np.vstack([self.vertices_mm, self.vertices_mm[:1]])

    def _distance_mm(self, pts: NDArray[np.float64], *, signed: bool) -> NDArray[np.float64]:
        flat = pts.reshape(-1, 2)
        dist = distance_to_closed_polyline_mm(flat, self.vertices_mm)
        if signed:
            inside = shapely.intersects_xy(self._polygon, flat[:, 0], flat[:, 1])
            dist = np.where(inside, dist, -dist)
        return dist.reshape(pts.shape[:-1])

    def _transformed(
        self, rotation_deg: float, offset_mm: tuple[float, float], scale: float
    ) -> Self:
        verts = transform_points(
            self.vertices_mm, rotation_deg=rotation_deg, offset_mm=offset_mm, scale=scale
        )
        return type(self)(verts, step_height_um=self.step_height_um)


def _polygon_relief(vertices_mm: NDArray[np.float64], step_height_um: float) -> PolygonRelief:
    """Unpickling helper of :class:`PolygonRelief` (its step height is keyword-only)."""
    return PolygonRelief(vertices_mm, step_height_um=step_height_um)


@dataclass(frozen=True)
class CircleRelief(StepRelief):
    """A plate with a raised disc; heights are computed exactly, not from a polygon.

    Parameters
    ----------
    centre_mm : (x, y) float, mm
        Centre of the disc.
    radius_mm : float
        Radius, mm (> 0).
    step_height_um : float, keyword-only
        Height of the disc above the base plane, um (> 0).

    Raises
    ------
    InputError
        If the centre is not a finite pair or a size is not positive.
    """

    centre_mm: tuple[float, float]
    radius_mm: float
    step_height_um: float = field(default=DEFAULT_STEP_HEIGHT_UM, kw_only=True)

    def __post_init__(self) -> None:
        object.__setattr__(self, "centre_mm", check_xy("centre_mm", self.centre_mm))
        object.__setattr__(self, "radius_mm", check_positive("radius_mm", self.radius_mm))
        self._check_step_height()

    @property
    def area_mm2(self) -> float:
        """Area of the disc, ``pi r^2``, mm^2."""
        return math.pi * self.radius_mm**2

    def _raised(self, x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.bool_]:
        dx = x - self.centre_mm[0]
        dy = y - self.centre_mm[1]
        raised: NDArray[np.bool_] = dx * dx + dy * dy <= self.radius_mm**2
        return raised

    def outline_mm(self, *, n_vertices: int = CIRCLE_OUTLINE_VERTICES) -> NDArray[np.float64]:
        """Inscribed regular polygon approximating the circle, for plotting.

        Parameters
        ----------
        n_vertices : int
            Number of distinct vertices (>= 3); the first lies at angle 0 (+x).

        Returns
        -------
        (n_vertices + 1, 2) float, mm
            Counter-clockwise vertices on the circle, closed by a copy of the first.
        """
        if int(n_vertices) != n_vertices or int(n_vertices) < 3:
            raise InputError(f"n_vertices must be an integer >= 3, got {n_vertices!r}")
        t = np.linspace(0.0, 2.0 * math.pi, int(n_vertices) + 1)
        t[-1] = 0.0  # close exactly
        return np.column_stack(
            [
                self.centre_mm[0] + self.radius_mm * np.cos(t),
                self.centre_mm[1] + self.radius_mm * np.sin(t),
            ]
        )

    def _distance_mm(self, pts: NDArray[np.float64], *, signed: bool) -> NDArray[np.float64]:
        inward: NDArray[np.float64] = self.radius_mm - np.hypot(
            pts[..., 0] - self.centre_mm[0], pts[..., 1] - self.centre_mm[1]
        )
        return inward if signed else np.abs(inward)

    def _transformed(
        self, rotation_deg: float, offset_mm: tuple[float, float], scale: float
    ) -> Self:
        centre = transform_points(
            np.asarray(self.centre_mm), rotation_deg=rotation_deg, offset_mm=offset_mm, scale=scale
        )
        return type(self)(
            (float(centre[0]), float(centre[1])),
            self.radius_mm * scale,
            step_height_um=self.step_height_um,
        )
