"""Geometry of a rectangular taxel array.

Coordinate convention (used everywhere in taxelkit): the array lies in the
sensor plane; taxel ``(i, j)`` (row ``i``, column ``j``) has its centre at
``x = (j - (cols - 1) / 2) * pitch_mm`` and ``y = (i - (rows - 1) / 2) *
pitch_mm`` relative to the array centre. Rows therefore run along +y and
columns along +x, the same convention as a heightmap ``height_mm[i, j]`` and
as ``imshow(..., origin="lower")``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError, check_positive

__all__ = ["ActiveRegion", "TaxelArray"]


@dataclass(frozen=True)
class ActiveRegion:
    """A rectangular block of taxels that an algorithm uses.

    Parameters
    ----------
    row0, col0 : int
        Index of the block's first row and column.
    rows, cols : int
        Size of the block in taxels.
    """

    row0: int
    col0: int
    rows: int
    cols: int

    def __post_init__(self) -> None:
        for name in ("row0", "col0"):
            if int(getattr(self, name)) < 0:
                raise InputError(f"{name} must be >= 0, got {getattr(self, name)!r}")
        for name in ("rows", "cols"):
            if int(getattr(self, name)) < 1:
                raise InputError(f"{name} must be >= 1, got {getattr(self, name)!r}")

    @property
    def slices(self) -> tuple[slice, slice]:
        """Row and column slices selecting the block from a ``(rows, cols)`` frame."""
        return (
            slice(self.row0, self.row0 + self.rows),
            slice(self.col0, self.col0 + self.cols),
        )


@dataclass(frozen=True)
class TaxelArray:
    """Rows, columns and spacing of a taxel array.

    Parameters
    ----------
    rows, cols : int
        Number of taxel rows (along y) and columns (along x).
    pitch_mm : float
        Centre-to-centre spacing of neighbouring taxels, mm.
    element_size_mm : float
        Side of the square sensing area of one taxel, mm; at most ``pitch_mm``.
        The simulator averages the penetration over this area.
    active : ActiveRegion or None
        The block of taxels an algorithm uses (for example the central 6 x 6
        of the optical three-axis sensor of paper 000); ``None`` means all.

    Raises
    ------
    InputError
        If a size is not positive, the element is larger than the pitch, or the
        active region does not fit inside the array.
    """

    rows: int
    cols: int
    pitch_mm: float
    element_size_mm: float
    active: ActiveRegion | None = None

    def __post_init__(self) -> None:
        for name in ("rows", "cols"):
            value = getattr(self, name)
            if not isinstance(value, int | np.integer) or value < 1:
                raise InputError(f"{name} must be an integer >= 1, got {value!r}")
        check_positive("pitch_mm", self.pitch_mm)
        check_positive("element_size_mm", self.element_size_mm)
        if self.element_size_mm > self.pitch_mm * (1 + 1e-9):
            raise InputError(
                f"element_size_mm must be <= pitch_mm ({self.pitch_mm}), "
                f"got {self.element_size_mm!r}"
            )
        a = self.active
        if a is not None and (a.row0 + a.rows > self.rows or a.col0 + a.cols > self.cols):
            raise InputError(f"active region {a} does not fit in a {self.rows} x {self.cols} array")

    @property
    def shape(self) -> tuple[int, int]:
        """``(rows, cols)``."""
        return (int(self.rows), int(self.cols))

    @property
    def width_mm(self) -> float:
        """Extent along x, ``cols * pitch_mm``."""
        return float(self.cols * self.pitch_mm)

    @property
    def height_mm(self) -> float:
        """Extent along y, ``rows * pitch_mm``."""
        return float(self.rows * self.pitch_mm)

    @property
    def active_region(self) -> ActiveRegion:
        """The active block, or the whole array when none is set."""
        if self.active is None:
            return ActiveRegion(0, 0, int(self.rows), int(self.cols))
        return self.active

    def centre_offsets_mm(
        self, *, margin: int = 0
    ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Taxel-centre coordinates relative to the array centre.

        Parameters
        ----------
        margin : int, optional
            Extra rings of virtual taxels on every side (for the skin's lateral
            coupling, which needs the penetration just outside the array).

        Returns
        -------
        x_mm : (cols + 2 * margin,) float, mm
            Column-centre x coordinates, increasing.
        y_mm : (rows + 2 * margin,) float, mm
            Row-centre y coordinates, increasing.
        """
        if margin < 0:
            raise InputError(f"margin must be >= 0, got {margin!r}")
        cols = np.arange(-margin, self.cols + margin, dtype=np.float64)
        rows = np.arange(-margin, self.rows + margin, dtype=np.float64)
        x = (cols - (self.cols - 1) / 2.0) * self.pitch_mm
        y = (rows - (self.rows - 1) / 2.0) * self.pitch_mm
        return x, y

    def centres_mm(self) -> NDArray[np.float64]:
        """Taxel centres as a ``(rows, cols, 2)`` array of ``(x, y)`` in mm."""
        x, y = self.centre_offsets_mm()
        xx, yy = np.meshgrid(x, y)
        return np.stack([xx, yy], axis=-1)
