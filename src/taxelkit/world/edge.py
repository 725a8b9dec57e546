"""A straight step edge: the simplest relief specimen, one half-plane raised.

A plate whose surface steps up by ``step_height_um`` across a straight line:
the simplest specimen for checking step detection and edge tracing.
Conventions as in :mod:`taxelkit.world.relief`: mm in the specimen frame,
base plane at ``z = 0``, points on the edge itself are raised.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Self

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import check_positive
from taxelkit.world._planar import (
    check_finite,
    check_xy,
    cos_sin_deg,
    transform_points,
)
from taxelkit.world.contour_relief import DEFAULT_STEP_HEIGHT_UM
from taxelkit.world.step_relief import StepRelief

__all__ = ["EDGE_OUTLINE_HALF_LENGTH_MM", "EdgeRelief"]

#: Half-length of the segment :meth:`EdgeRelief.outline_mm` returns by default,
#: mm; covers a 90 mm specimen from the edge's reference point.
EDGE_OUTLINE_HALF_LENGTH_MM = 100.0


@dataclass(frozen=True)
class EdgeRelief(StepRelief):
    """A straight step edge: the half-plane on the left of a directed line is raised.

    The edge is the line through ``point_mm`` with direction
    ``d = (cos angle_deg, sin angle_deg)`` (angle measured counter-clockwise
    from +x). A point ``p`` is raised when it lies on the left of ``d``, i.e.
    when ``d x (p - point_mm) = -sin(a) (x - x0) + cos(a) (y - y0) >= 0``.
    Examples: ``angle_deg=0`` raises ``y >= y0``; ``angle_deg=90`` (edge along
    +y) raises ``x <= x0``.

    Parameters
    ----------
    point_mm : (x, y) float, mm
        A point on the edge.
    angle_deg : float, deg
        Direction of the edge from +x, counter-clockwise.
    step_height_um : float, keyword-only
        Height of the raised side above the base plane, um (> 0).

    Raises
    ------
    InputError
        If the point or angle is not finite or the step height is not positive.

    Examples
    --------
    >>> edge = EdgeRelief((0.0, 0.0), 90.0, step_height_um=50.0)  # along +y
    >>> float(edge.height_mm(-1.0, 0.0)), float(edge.height_mm(1.0, 0.0))
    (0.05, 0.0)
    """

    point_mm: tuple[float, float] = (0.0, 0.0)
    angle_deg: float = 0.0
    step_height_um: float = field(default=DEFAULT_STEP_HEIGHT_UM, kw_only=True)

    def __post_init__(self) -> None:
        object.__setattr__(self, "point_mm", check_xy("point_mm", self.point_mm))
        object.__setattr__(self, "angle_deg", check_finite("angle_deg", self.angle_deg))
        self._check_step_height()

    @property
    def direction(self) -> tuple[float, float]:
        """Unit vector along the edge, ``(cos angle, sin angle)`` (exact at multiples of 90 deg)."""
        return cos_sin_deg(self.angle_deg)

    def _left_distance_mm(self, x: NDArray[np.float64], y: NDArray[np.float64]) -> Any:
        c, s = self.direction
        return -s * (x - self.point_mm[0]) + c * (y - self.point_mm[1])

    def _raised(self, x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.bool_]:
        raised: NDArray[np.bool_] = self._left_distance_mm(x, y) >= 0.0
        return raised

    def outline_mm(
        self, *, half_length_mm: float = EDGE_OUTLINE_HALF_LENGTH_MM
    ) -> NDArray[np.float64]:
        """A finite piece of the edge line, for plotting.

        Parameters
        ----------
        half_length_mm : float, mm
            Distance from ``point_mm`` to each end (> 0).

        Returns
        -------
        (2, 2) float, mm
            ``point - L d`` and ``point + L d``, in the edge's direction.
        """
        half = check_positive("half_length_mm", half_length_mm)
        d = np.asarray(self.direction)
        p = np.asarray(self.point_mm)
        return np.vstack([p - half * d, p + half * d])

    def _distance_mm(self, pts: NDArray[np.float64], *, signed: bool) -> NDArray[np.float64]:
        left: NDArray[np.float64] = np.asarray(
            self._left_distance_mm(pts[..., 0], pts[..., 1]), dtype=np.float64
        )
        return left if signed else np.abs(left)

    def _transformed(
        self, rotation_deg: float, offset_mm: tuple[float, float], scale: float
    ) -> Self:
        p = transform_points(
            np.asarray(self.point_mm), rotation_deg=rotation_deg, offset_mm=offset_mm, scale=scale
        )
        # the direction turns with the plate
        return type(self)(
            (float(p[0]), float(p[1])),
            self.angle_deg + rotation_deg,
            step_height_um=self.step_height_um,
        )
