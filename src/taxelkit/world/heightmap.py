"""Heightmap specimens: a relief given as a regular grid of heights.

Grid convention (the same as the taxel array's, see
:mod:`taxelkit.sensors.array_geometry`): ``heights_mm[i, j]`` is the height at

    x = x0_mm + j * pixel_mm,    y = y0_mm + i * pixel_mm,

so rows run along +y and columns along +x (``imshow(..., origin="lower")``).
When the origin is not given the map is centred on ``(0, 0)``:
``x0_mm = -(W - 1) / 2 * pixel_mm`` and ``y0_mm = -(H - 1) / 2 * pixel_mm``.

Between samples the height is interpolated bilinearly, so a step of the
underlying relief is a ramp one pixel wide. Outside the closed rectangle
spanned by the samples the height is 0 (the base plane).

File format (``.npz``, read by :func:`load_heightmap`): ``height_mm`` (H, W)
float, ``pixel_mm`` scalar, and optionally ``x0_mm`` and ``y0_mm`` scalars.
:meth:`HeightmapRelief.to_arrays` returns exactly these arrays, so
``np.savez(path, **relief.to_arrays())`` writes a file that loads back
unchanged; writing is left to the caller (the core writes no files).
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import CorruptRecordingError, InputError, check_positive
from taxelkit.io.npz_read import read_npz
from taxelkit.world._planar import broadcast_xy
from taxelkit.world.base import Relief

__all__ = [
    "HEIGHTMAP_OPTIONAL_KEYS",
    "HEIGHTMAP_REQUIRED_KEYS",
    "MAX_HEIGHT_MM",
    "MAX_ORIGIN_MM",
    "MAX_PIXEL_MM",
    "HeightmapRelief",
    "heightmap_from_relief",
    "load_heightmap",
    "relief_from_heightmap",
]

#: Arrays an ``.npz`` heightmap must hold.
HEIGHTMAP_REQUIRED_KEYS: tuple[str, ...] = ("height_mm", "pixel_mm")

#: Arrays an ``.npz`` heightmap may hold; absent means "centred on the origin".
HEIGHTMAP_OPTIONAL_KEYS: tuple[str, ...] = ("x0_mm", "y0_mm")

#: Slack, in pixels, when counting how many samples fit in a rasterising
#: extent, so that an extent that is a whole number of pixels keeps its last
#: sample despite rounding.
_EXTENT_SLACK_PIXELS = 1e-9

#: Largest height magnitude a heightmap may hold, mm: a relief taller than a
#: metre is not a tactile specimen, and the bound keeps every product of
#: heights and coordinates far from float64 overflow.
MAX_HEIGHT_MM = 1e3

#: Largest sample spacing, mm.
MAX_PIXEL_MM = 1e3

#: Largest magnitude of the map's origin coordinates, mm (a kilometre).
MAX_ORIGIN_MM = 1e6


def _check_scalar(name: str, value: Any) -> float:
    arr = np.asarray(value)
    if arr.ndim != 0 or arr.dtype.kind not in "fiu":
        raise InputError(
            f"{name} must be a real scalar, got dtype {arr.dtype} and shape {arr.shape}"
        )
    v = float(arr)
    if not (math.isfinite(v) and abs(v) <= MAX_ORIGIN_MM):
        raise InputError(f"{name} must be finite and within +-{MAX_ORIGIN_MM:g} mm, got {v!r}")
    return v


@dataclass(frozen=True, eq=False)
class HeightmapRelief:
    """A relief sampled on a regular grid, interpolated bilinearly.

    Parameters
    ----------
    heights_mm : (H, W) float, mm
        Heights above the base plane at the grid samples (negative values are
        grooves). Stored as a read-only float64 copy.
    pixel_mm : float
        Sample spacing along x and y, mm (> 0).
    x0_mm, y0_mm : float
        Coordinates of sample ``[0, 0]``, mm. :func:`relief_from_heightmap`
        fills them in to centre the map on the origin.

    Raises
    ------
    InputError
        If the heights are not a non-empty finite real 2-D array, the pixel is
        not positive, or the origin is not finite.

    Notes
    -----
    Equality is identity (``eq=False``): the height array is not hashable.
    """

    heights_mm: NDArray[np.float64]
    pixel_mm: float
    x0_mm: float
    y0_mm: float

    def __post_init__(self) -> None:
        raw = np.asarray(self.heights_mm)
        if raw.dtype.kind not in "fiu":
            raise InputError(f"height_mm must hold real numbers, got dtype {raw.dtype}")
        if raw.ndim != 2:
            raise InputError(f"height_mm must have shape (H, W) (2 dimensions), got {raw.shape}")
        if raw.size == 0:
            raise InputError(f"height_mm must not be empty, got shape {raw.shape}")
        heights = np.array(raw, dtype=np.float64)
        if not np.all(np.isfinite(heights)):
            n_bad = int(np.count_nonzero(~np.isfinite(heights)))
            raise InputError(f"height_mm must be finite, got {n_bad} NaN/Inf value(s)")
        peak = float(np.abs(heights).max())
        if peak > MAX_HEIGHT_MM:
            raise InputError(
                f"height_mm must be within +-{MAX_HEIGHT_MM:g} mm, got a height of {peak:g} mm"
            )
        heights.setflags(write=False)
        object.__setattr__(self, "heights_mm", heights)
        pixel = check_positive("pixel_mm", self.pixel_mm)
        if pixel > MAX_PIXEL_MM:
            raise InputError(f"pixel_mm must be <= {MAX_PIXEL_MM:g} mm, got {pixel!r}")
        object.__setattr__(self, "pixel_mm", pixel)
        object.__setattr__(self, "x0_mm", _check_scalar("x0_mm", self.x0_mm))
        object.__setattr__(self, "y0_mm", _check_scalar("y0_mm", self.y0_mm))

    def __reduce__(self) -> tuple[Any, ...]:
        # Rebuild through __init__ so that a copy is validated and read-only.
        return (type(self), (np.array(self.heights_mm), self.pixel_mm, self.x0_mm, self.y0_mm))

    @property
    def shape(self) -> tuple[int, int]:
        """``(H, W)``: rows (along y) and columns (along x)."""
        h, w = self.heights_mm.shape
        return int(h), int(w)

    @property
    def x_mm(self) -> NDArray[np.float64]:
        """(W,) float, mm: x of the sample columns."""
        return self.x0_mm + self.pixel_mm * np.arange(self.shape[1], dtype=np.float64)

    @property
    def y_mm(self) -> NDArray[np.float64]:
        """(H,) float, mm: y of the sample rows."""
        return self.y0_mm + self.pixel_mm * np.arange(self.shape[0], dtype=np.float64)

    @property
    def extent_mm(self) -> tuple[float, float, float, float]:
        """``(x_min, x_max, y_min, y_max)`` of the samples, mm; height is 0 outside."""
        h, w = self.shape
        return (
            self.x0_mm,
            self.x0_mm + (w - 1) * self.pixel_mm,
            self.y0_mm,
            self.y0_mm + (h - 1) * self.pixel_mm,
        )

    def height_mm(self, x_mm: ArrayLike, y_mm: ArrayLike) -> NDArray[np.float64]:
        """Bilinearly interpolated height at points, mm.

        Parameters
        ----------
        x_mm, y_mm : (...) float, mm
            Point coordinates in the specimen frame; broadcast together.

        Returns
        -------
        (...) float, mm
            The bilinear interpolation of the four surrounding samples; a
            sample's own value at its coordinates; 0 outside :attr:`extent_mm`
            (and for non-finite coordinates).
        """
        x, y = broadcast_xy(x_mm, y_mm)
        n_rows, n_cols = self.shape
        u = (x - self.x0_mm) / self.pixel_mm  # fractional column index
        v = (y - self.y0_mm) / self.pixel_mm  # fractional row index
        inside = (u >= 0.0) & (u <= n_cols - 1) & (v >= 0.0) & (v <= n_rows - 1)
        out = np.zeros(x.shape, dtype=np.float64)
        ui, vi = u[inside], v[inside]
        # Lower-left sample of the cell; the last column/row belongs to the cell before it.
        j0 = np.minimum(np.floor(ui).astype(np.intp), max(n_cols - 2, 0))
        i0 = np.minimum(np.floor(vi).astype(np.intp), max(n_rows - 2, 0))
        j1 = np.minimum(j0 + 1, n_cols - 1)
        i1 = np.minimum(i0 + 1, n_rows - 1)
        fu, fv = ui - j0, vi - i0
        z = self.heights_mm
        bottom = (1.0 - fu) * z[i0, j0] + fu * z[i0, j1]
        top = (1.0 - fu) * z[i1, j0] + fu * z[i1, j1]
        out[inside] = (1.0 - fv) * bottom + fv * top
        return out

    def to_arrays(self) -> dict[str, NDArray[np.float64]]:
        """The arrays of the ``.npz`` format, for ``np.savez(path, **arrays)``.

        Returns
        -------
        dict
            ``height_mm`` (H, W) float, ``pixel_mm``, ``x0_mm``, ``y0_mm``
            0-d float arrays, mm.
        """
        return {
            "height_mm": np.array(self.heights_mm),
            "pixel_mm": np.array(self.pixel_mm),
            "x0_mm": np.array(self.x0_mm),
            "y0_mm": np.array(self.y0_mm),
        }


def relief_from_heightmap(
    heights_mm: ArrayLike,
    *,
    pixel_mm: float,
    x0_mm: float | None = None,
    y0_mm: float | None = None,
) -> HeightmapRelief:
    """A heightmap relief, centred on the origin unless its origin is given.

    Parameters
    ----------
    heights_mm : (H, W) float, mm
        ``heights_mm[i, j]`` is the height at ``(x0 + j pixel, y0 + i pixel)``.
    pixel_mm : float
        Sample spacing, mm (> 0).
    x0_mm, y0_mm : float or None, mm
        Coordinates of sample ``[0, 0]``; ``None`` centres the map:
        ``-(W - 1) / 2 * pixel_mm`` and ``-(H - 1) / 2 * pixel_mm``.

    Returns
    -------
    HeightmapRelief

    Raises
    ------
    InputError
        See :class:`HeightmapRelief`.

    Examples
    --------
    >>> r = relief_from_heightmap([[0.0, 1.0, 3.0]], pixel_mm=0.5)
    >>> r.extent_mm
    (-0.5, 0.5, 0.0, 0.0)
    >>> float(r.height_mm(0.25, 0.0)), float(r.height_mm(0.6, 0.0))
    (2.0, 0.0)
    """
    pixel = check_positive("pixel_mm", pixel_mm)
    arr = np.asarray(heights_mm)
    if arr.ndim != 2:
        raise InputError(f"height_mm must have shape (H, W) (2 dimensions), got {arr.shape}")
    n_rows, n_cols = arr.shape
    x0 = 0.5 * (1 - n_cols) * pixel if x0_mm is None else x0_mm
    y0 = 0.5 * (1 - n_rows) * pixel if y0_mm is None else y0_mm
    return HeightmapRelief(arr, pixel, x0, y0)


def heightmap_from_relief(
    relief: Relief,
    *,
    pixel_mm: float,
    extent_mm: tuple[float, float, float, float],
) -> HeightmapRelief:
    """Rasterise any relief by point-sampling it on a regular grid.

    Parameters
    ----------
    relief : Relief
        Anything with ``height_mm(x_mm, y_mm)``.
    pixel_mm : float
        Sample spacing, mm (> 0).
    extent_mm : (x_min, x_max, y_min, y_max) float, mm
        Region to sample. The first sample sits at ``(x_min, y_min)``; samples
        follow every ``pixel_mm`` up to and including ``x_max`` / ``y_max``
        when the extent is a whole number of pixels (otherwise the last
        sample falls short of it).

    Returns
    -------
    HeightmapRelief
        ``heights_mm[i, j] = relief.height_mm(x_min + j pixel, y_min + i pixel)``.

    Raises
    ------
    InputError
        If the pixel is not positive or the extent is not finite and ordered.
    """
    pixel = check_positive("pixel_mm", pixel_mm)
    ext = np.asarray(extent_mm, dtype=np.float64)
    if ext.shape != (4,) or not np.all(np.isfinite(ext)):
        raise InputError(
            f"extent_mm must be four finite numbers (x_min, x_max, y_min, y_max), got {extent_mm!r}"
        )
    x_min, x_max, y_min, y_max = (float(e) for e in ext)
    if x_max < x_min or y_max < y_min:
        raise InputError(
            f"extent_mm must have x_min <= x_max and y_min <= y_max, got {extent_mm!r}"
        )
    n_cols = math.floor((x_max - x_min) / pixel + _EXTENT_SLACK_PIXELS) + 1
    n_rows = math.floor((y_max - y_min) / pixel + _EXTENT_SLACK_PIXELS) + 1
    xs = x_min + pixel * np.arange(n_cols, dtype=np.float64)
    ys = y_min + pixel * np.arange(n_rows, dtype=np.float64)
    heights = np.asarray(relief.height_mm(xs[None, :], ys[:, None]), dtype=np.float64)
    return HeightmapRelief(np.broadcast_to(heights, (n_rows, n_cols)), pixel, x_min, y_min)


def load_heightmap(path: str | os.PathLike[str]) -> HeightmapRelief:
    """Read a heightmap specimen from an ``.npz`` file.

    Parameters
    ----------
    path : str or path-like
        ``.npz`` archive holding ``height_mm`` (H, W) float, mm and
        ``pixel_mm`` scalar, mm; optionally ``x0_mm`` and ``y0_mm`` scalars,
        mm (absent: the map is centred on the origin). Other arrays are ignored.

    Returns
    -------
    HeightmapRelief

    Raises
    ------
    InputError
        If an array has the wrong shape or type, holds NaN/Inf, a height
        beyond :data:`MAX_HEIGHT_MM`, or ``pixel_mm`` is not in
        ``(0, MAX_PIXEL_MM]``. The message names the file.
    RecordingNotFoundError, RecordingAccessError
        If the file does not exist or is not a regular file.
    FileTooLargeError
        If the file or its arrays exceed the read limit
        (:func:`taxelkit.io.limits.max_read_bytes`), checked before reading.
    UnsafeFileError
        If an archive member name carries a path.
    CorruptRecordingError
        If the file is not a readable ``.npz`` archive (empty, not a zip, a
        bare ``.npy``, truncated, damaged, pickled objects) or lacks a
        required array.
    """
    p = Path(path)
    contents = read_npz(p, (*HEIGHTMAP_REQUIRED_KEYS, *HEIGHTMAP_OPTIONAL_KEYS), what="heightmap")
    arrays = contents.arrays
    missing = [k for k in HEIGHTMAP_REQUIRED_KEYS if k not in arrays]
    if missing:
        raise CorruptRecordingError(
            f"{p}: missing array(s) {', '.join(missing)}; a heightmap needs "
            f"{' and '.join(HEIGHTMAP_REQUIRED_KEYS)} (optional: "
            f"{', '.join(HEIGHTMAP_OPTIONAL_KEYS)})"
        )
    try:
        return relief_from_heightmap(
            arrays["height_mm"],
            pixel_mm=_check_scalar("pixel_mm", arrays["pixel_mm"]),
            x0_mm=_check_scalar("x0_mm", arrays["x0_mm"]) if "x0_mm" in arrays else None,
            y0_mm=_check_scalar("y0_mm", arrays["y0_mm"]) if "y0_mm" in arrays else None,
        )
    except InputError as exc:
        raise InputError(f"{p}: {exc}") from None
