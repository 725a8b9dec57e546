"""Degraded relief specimens: a rough plate and a tilted plate around any relief.

Real plates are neither smooth nor level. Two wrappers add what a machined
specimen on a robot's table brings, each around any
:class:`~taxelkit.world.base.Relief` (the clean specimen stays available for
measuring tracing error):

* :class:`RoughRelief` - a seeded, stationary Gaussian height field of a given
  rms (``height_noise_um``) and correlation length, added everywhere within a
  square extent (the surface roughness or machining marks of the plate). The
  field is drawn once per specimen: it belongs to the plate, it does not
  change from one touch to the next;
* :class:`TiltedRelief` - the plate tilted by ``tilt_deg`` about a horizontal
  axis through ``pivot_mm``: a plane ``tan(tilt) * d`` is added, ``d`` the
  distance along the downhill-to-uphill direction ``azimuth_deg``.

Both return heights in mm, like every relief.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import ndimage

from taxelkit.errors import InputError, check_positive
from taxelkit.world._planar import UM_PER_MM, broadcast_xy, check_finite, check_xy
from taxelkit.world.base import Relief
from taxelkit.world.heightmap import HeightmapRelief

__all__ = [
    "DEFAULT_ROUGHNESS_CORRELATION_MM",
    "DEFAULT_ROUGHNESS_HALF_WIDTH_MM",
    "ROUGHNESS_SAMPLES_PER_CORRELATION",
    "RoughRelief",
    "TiltedRelief",
]

#: Correlation length of the roughness field, mm: the standard deviation of
#: the Gaussian that smooths white noise into the field. 1 mm is the size of
#: one feeler of the optical sensor of paper 000 (assumed: the paper gives no
#: roughness), so a bump is about as wide as what touches it.
DEFAULT_ROUGHNESS_CORRELATION_MM = 1.0
#: Half-width of the square the roughness covers, mm (centred on the pivot):
#: a 90 mm specimen enlarged by 40 % plus the sensor's reach fits inside.
DEFAULT_ROUGHNESS_HALF_WIDTH_MM = 100.0
#: Grid samples per correlation length of the roughness field (4: bilinear
#: interpolation between samples changes the field's rms by under 2 %).
ROUGHNESS_SAMPLES_PER_CORRELATION = 4


def _roughness_field(
    rms_mm: float,
    correlation_mm: float,
    half_width_mm: float,
    centre: tuple[float, float],
    rng: Any,
) -> HeightmapRelief:
    """White noise smoothed by a Gaussian of ``correlation_mm``, scaled to ``rms_mm``."""
    pixel = correlation_mm / ROUGHNESS_SAMPLES_PER_CORRELATION
    n = math.ceil(2.0 * half_width_mm / pixel) + 1
    gen = np.random.default_rng(rng)
    white = gen.standard_normal((n, n))
    smooth = ndimage.gaussian_filter(white, ROUGHNESS_SAMPLES_PER_CORRELATION, mode="wrap")
    std = float(smooth.std())
    heights = smooth * (rms_mm / std) if std > 0 and rms_mm > 0 else np.zeros_like(smooth)
    x0 = centre[0] - 0.5 * (n - 1) * pixel
    y0 = centre[1] - 0.5 * (n - 1) * pixel
    return HeightmapRelief(heights, pixel, x0, y0)


@dataclass(frozen=True, eq=False)
class RoughRelief:
    """A relief on a rough plate: ``base.height_mm + roughness``.

    Parameters
    ----------
    base : Relief
        The clean specimen.
    height_noise_um : float, um
        Rms of the added height field (>= 0; 0 adds nothing).
    correlation_mm : float, mm
        Correlation length (Gaussian smoothing width) of the field.
    half_width_mm : float, mm
        The field covers the square ``centre_mm +- half_width_mm``; outside it
        the plate is smooth.
    centre_mm : (x, y) float, mm
    rng : int, Generator or None, keyword-only
        Seed of the field: the same seed gives the same plate.

    Examples
    --------
    >>> from taxelkit.world.relief import relief_shape
    >>> plate = RoughRelief(relief_shape("square"), height_noise_um=5.0, rng=1)
    >>> h = plate.height_mm(np.linspace(-10, 10, 2001), 0.0) - 0.2
    >>> bool(abs(h.std() - 0.005) < 0.002)
    True
    """

    base: Relief
    height_noise_um: float
    correlation_mm: float = DEFAULT_ROUGHNESS_CORRELATION_MM
    half_width_mm: float = DEFAULT_ROUGHNESS_HALF_WIDTH_MM
    centre_mm: tuple[float, float] = (0.0, 0.0)
    rng: int | np.random.Generator | None = field(default=None, kw_only=True, repr=False)
    _field: HeightmapRelief = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not isinstance(self.base, Relief):
            raise InputError(f"base must be a Relief (height_mm), got {type(self.base).__name__}")
        rms = check_positive("height_noise_um", self.height_noise_um, allow_zero=True)
        corr = check_positive("correlation_mm", self.correlation_mm)
        half = check_positive("half_width_mm", self.half_width_mm)
        centre = check_xy("centre_mm", self.centre_mm)
        cells = 2.0 * half / (corr / ROUGHNESS_SAMPLES_PER_CORRELATION)
        if cells > 8192:
            raise InputError(
                f"half_width_mm / correlation_mm must be <= {8192 / 8:g} "
                f"(a field of at most 8192^2 samples), got {half / corr:g}"
            )
        object.__setattr__(
            self, "_field", _roughness_field(rms / UM_PER_MM, corr, half, centre, self.rng)
        )

    def height_mm(self, x_mm: ArrayLike, y_mm: ArrayLike) -> NDArray[np.float64]:
        """Height of the clean specimen plus the roughness at points, ``(...)`` mm."""
        x, y = broadcast_xy(x_mm, y_mm)
        out: NDArray[np.float64] = np.asarray(
            self.base.height_mm(x, y), dtype=np.float64
        ) + self._field.height_mm(x, y)
        return out


@dataclass(frozen=True, eq=False)
class TiltedRelief:
    """A relief on a plate tilted by ``tilt_deg``: ``base.height_mm + tan(tilt) d``.

    Parameters
    ----------
    base : Relief
        The clean specimen.
    tilt_deg : float, deg
        Tilt of the plate, in ``[0, 45]``.
    azimuth_deg : float, deg
        Direction in the plate in which the surface rises, from +x
        counter-clockwise.
    pivot_mm : (x, y) float, mm
        A point of the tilt axis (its height is unchanged).

    Examples
    --------
    >>> from taxelkit.world.relief import relief_shape
    >>> plate = TiltedRelief(relief_shape("circle", diameter_mm=20.0), 45.0)
    >>> round(float(plate.height_mm(30.0, 0.0)), 9), float(plate.height_mm(0.0, 30.0))
    (30.0, 0.0)
    """

    base: Relief
    tilt_deg: float
    azimuth_deg: float = 0.0
    pivot_mm: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self) -> None:
        if not isinstance(self.base, Relief):
            raise InputError(f"base must be a Relief (height_mm), got {type(self.base).__name__}")
        tilt = check_finite("tilt_deg", self.tilt_deg)
        if not 0.0 <= tilt <= 45.0:
            raise InputError(f"tilt_deg must be in [0, 45] deg, got {self.tilt_deg!r}")
        check_finite("azimuth_deg", self.azimuth_deg)
        check_xy("pivot_mm", self.pivot_mm)

    @property
    def slope(self) -> NDArray[np.float64]:
        """Height gradient of the tilted plane, ``(2,)`` mm/mm."""
        a = math.radians(self.azimuth_deg)
        return math.tan(math.radians(self.tilt_deg)) * np.array([math.cos(a), math.sin(a)])

    def height_mm(self, x_mm: ArrayLike, y_mm: ArrayLike) -> NDArray[np.float64]:
        """Height of the clean specimen plus the tilted plane at points, ``(...)`` mm."""
        x, y = broadcast_xy(x_mm, y_mm)
        gx, gy = self.slope
        px, py = self.pivot_mm
        out: NDArray[np.float64] = np.asarray(self.base.height_mm(x, y), dtype=np.float64) + (
            gx * (x - px) + gy * (y - py)
        )
        return out
