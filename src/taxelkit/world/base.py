"""What the simulator needs from the world: relief surfaces and solid bodies.

Both are protocols so that users can bring their own: anything with these
methods can be pressed into a simulated sensor.
"""

from __future__ import annotations

from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

__all__ = ["Relief", "Solid"]


@runtime_checkable
class Relief(Protocol):
    """A rigid plate whose top surface height varies with position (paper 000).

    The plate's base surface is ``z = 0``; raised relief has ``z > 0``.
    """

    def height_mm(self, x_mm: NDArray[Any], y_mm: NDArray[Any]) -> NDArray[np.float64]:
        """Surface height at points, mm.

        Parameters
        ----------
        x_mm, y_mm : (...) float, mm
            Point coordinates in the specimen frame; broadcast together.

        Returns
        -------
        (...) float, mm
            Height of the top surface above the base plane.
        """
        ...


@runtime_checkable
class Solid(Protocol):
    """A rigid convex body that can be pressed onto the sensor (paper 001).

    The body is defined in its own frame about a reference point (its centroid
    unless the class says otherwise). A pose rotates it about that point; the
    simulator then places the point above ``(x, y)`` on the sensor and lowers
    the body until its lowest point is ``indent_mm`` below the skin surface.
    """

    @property
    def name(self) -> str:
        """Short name of the body (``"cube"``, ``"mesh"``, ...)."""
        ...

    def lowest_z_mm(self, rotations: NDArray[Any]) -> NDArray[np.float64]:
        """Lowest z of the rotated body relative to its reference point.

        Parameters
        ----------
        rotations : (P, 3, 3) float
            Rotation matrices (body frame to sensor frame).

        Returns
        -------
        (P,) float, mm
        """
        ...

    def lowest_point_mm(self, rotations: NDArray[Any]) -> NDArray[np.float64]:
        """Lowest point of the rotated body relative to its reference point.

        Parameters
        ----------
        rotations : (P, 3, 3) float

        Returns
        -------
        (P, 3) float, mm
            Where several points tie (a face or an edge resting flat), their mean.
        """
        ...

    def lowest_segment_mm(self, rotations: NDArray[Any]) -> NDArray[np.float64]:
        """Ends of the body's lowest part: a point (twice), an edge or a generator.

        Parameters
        ----------
        rotations : (P, 3, 3) float

        Returns
        -------
        (P, 2, 3) float, mm
        """
        ...

    def bottom_mm(
        self, rotations: NDArray[Any], x_mm: NDArray[Any], y_mm: NDArray[Any]
    ) -> NDArray[np.floating[Any]]:
        """Height of the body's lower surface on vertical lines of a grid.

        Parameters
        ----------
        rotations : (P, 3, 3) float
            Rotation matrices.
        x_mm : (P, W) float, mm
            x of the grid columns relative to the reference point, per pose.
        y_mm : (P, H) float, mm
            y of the grid rows relative to the reference point, per pose.

        Returns
        -------
        (P, H, W) float, mm, in the dtype of ``x_mm``
            Lowest z of the rotated body on the vertical line through
            ``(x_mm[p, j], y_mm[p, i])``, relative to the reference point;
            ``+inf`` where the line misses the body.
        """
        ...
