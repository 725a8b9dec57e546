"""The :class:`~taxelkit.world.base.Solid` methods, written and documented once.

Each family of analytic bodies (convex polyhedra, bodies of revolution) has
its own vectorised geometry; :class:`SolidMethods` turns that geometry into
the four public methods of the protocol, so a family defines only the four
private kernels, one line each.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["SolidMethods"]


class SolidMethods(ABC):
    """Base of the analytic solids: the public methods of a :class:`~taxelkit.world.base.Solid`.

    A subclass implements ``_lowest_z``, ``_lowest_point``, ``_lowest_segment``
    and ``_bottom`` with the signatures and results of the public methods
    below; the public methods only dispatch to them.
    """

    def lowest_z_mm(self, rotations: ArrayLike) -> NDArray[np.float64]:
        """Lowest z of the rotated body relative to its reference point, ``(P,)`` mm.

        Parameters
        ----------
        rotations : (P, 3, 3) float
            Body-to-sensor rotation matrices.
        """
        return self._lowest_z(rotations)

    def lowest_point_mm(self, rotations: ArrayLike) -> NDArray[np.float64]:
        """Lowest point of the rotated body, ``(P, 3)`` mm (a mean where several tie)."""
        return self._lowest_point(rotations)

    def lowest_segment_mm(self, rotations: ArrayLike) -> NDArray[np.float64]:
        """Ends of the lowest point, edge or generator, ``(P, 2, 3)`` mm."""
        return self._lowest_segment(rotations)

    def bottom_mm(self, rotations: ArrayLike, x_mm: ArrayLike, y_mm: ArrayLike) -> NDArray[Any]:
        """Bottom of the rotated body on vertical lines through a grid.

        Parameters
        ----------
        rotations : (P, 3, 3) float
            Body-to-sensor rotation matrices.
        x_mm : (P, W) float, mm
            x of the grid columns relative to the reference point, per pose.
        y_mm : (P, H) float, mm
            y of the grid rows relative to the reference point, per pose.

        Returns
        -------
        (P, H, W) float, mm
            Lowest z of the body on each line relative to the reference point,
            in the dtype of ``x_mm`` (float32 or float64); ``+inf`` where the
            line misses.
        """
        return self._bottom(rotations, x_mm, y_mm)

    @abstractmethod
    def _lowest_z(self, rotations: ArrayLike) -> NDArray[np.float64]: ...

    @abstractmethod
    def _lowest_point(self, rotations: ArrayLike) -> NDArray[np.float64]: ...

    @abstractmethod
    def _lowest_segment(self, rotations: ArrayLike) -> NDArray[np.float64]: ...

    @abstractmethod
    def _bottom(self, rotations: ArrayLike, x_mm: ArrayLike, y_mm: ArrayLike) -> NDArray[Any]: ...
