"""What the step reliefs share: a raised set, its step height, the distance to its contour.

:class:`StepRelief` is the base of
:class:`~taxelkit.world.contour_relief.PolygonRelief`,
:class:`~taxelkit.world.contour_relief.CircleRelief` and
:class:`~taxelkit.world.edge.EdgeRelief`. It validates the step height,
checks and broadcasts the query points and the similarity transform, and
documents the public methods once; a subclass says only which points are
raised, how far a point is from its contour and how its own parameters move.

Conventions: mm in the specimen frame, the base plane at ``z = 0``, the
raised set closed (a point on the contour is raised).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Self

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import check_positive
from taxelkit.world._planar import UM_PER_MM, as_points, broadcast_xy, check_transform

__all__ = ["StepRelief"]


class StepRelief(ABC):
    """A plate with a raised set of uniform height ``step_height_um``.

    Subclasses are frozen dataclasses with a ``step_height_um`` field (um,
    > 0) that call :meth:`_check_step_height` in ``__post_init__``.
    """

    step_height_um: float

    def _check_step_height(self) -> None:
        """Validate ``step_height_um`` (> 0, finite) and store it as a float."""
        step = check_positive("step_height_um", self.step_height_um)
        object.__setattr__(self, "step_height_um", step)

    @property
    def step_height_mm(self) -> float:
        """Step height in mm."""
        return self.step_height_um / UM_PER_MM

    def height_mm(self, x_mm: ArrayLike, y_mm: ArrayLike) -> NDArray[np.float64]:
        """Surface height at points, mm.

        Parameters
        ----------
        x_mm, y_mm : (...) float, mm
            Point coordinates in the specimen frame; broadcast together.

        Returns
        -------
        (...) float, mm
            ``step_height_mm`` on the raised set (its contour included), 0
            elsewhere.

        Raises
        ------
        InputError
            If the coordinates do not broadcast together.
        """
        x, y = broadcast_xy(x_mm, y_mm)
        height: NDArray[np.float64] = np.where(self._raised(x, y), self.step_height_mm, 0.0)
        return height

    def distance_to_edge_mm(
        self, points_mm: ArrayLike, *, signed: bool = False
    ) -> NDArray[np.float64]:
        """Euclidean distance from points to the contour (for an edge, its line).

        Parameters
        ----------
        points_mm : (N, 2) or (..., 2) float, mm
            Query points.
        signed : bool
            If True, positive on the raised side, negative on the other.

        Returns
        -------
        (N,) or (...) float, mm
            0 for a point on the contour.

        Raises
        ------
        InputError
            If the points do not have a last axis of length 2 or are not finite.
        """
        return self._distance_mm(as_points(points_mm), signed=signed)

    def transformed(
        self,
        *,
        rotation_deg: float = 0.0,
        offset_mm: tuple[float, float] = (0.0, 0.0),
        scale: float = 1.0,
    ) -> Self:
        """The same relief scaled, rotated (about the frame origin) and then translated.

        Parameters
        ----------
        rotation_deg : float, deg
            Counter-clockwise rotation about the origin.
        offset_mm : (x, y) float, mm
            Translation applied after rotation and scaling.
        scale : float
            Uniform scale factor about the origin (> 0); the step height is kept.

        Returns
        -------
        StepRelief
            Of the same class: a point ``p`` of this relief maps to
            ``scale * R p + offset_mm``.

        Raises
        ------
        InputError
            If the angle or offset is not finite or the scale is not positive.
        """
        rot, off, s = check_transform(rotation_deg, offset_mm, scale)
        return self._transformed(rot, off, s)

    @abstractmethod
    def _raised(self, x: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Whether each point ``(...)`` is on the raised set."""

    @abstractmethod
    def _distance_mm(self, pts: NDArray[np.float64], *, signed: bool) -> NDArray[np.float64]:
        """Distance ``(...)`` from checked points ``(..., 2)``; positive inside when signed."""

    @abstractmethod
    def _transformed(
        self, rotation_deg: float, offset_mm: tuple[float, float], scale: float
    ) -> Self:
        """This relief moved by a checked similarity transform."""
