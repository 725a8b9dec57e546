"""Measurement noise and quantisation of taxel displacements."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import check_positive

__all__ = ["NoiseModel", "RngLike", "apply_noise"]

RngLike = int | np.random.Generator | None


@dataclass(frozen=True)
class NoiseModel:
    """Additive Gaussian noise followed by quantisation.

    Parameters
    ----------
    sigma_mm : float
        Standard deviation of the additive white Gaussian noise, mm; 0 for none.
    resolution_mm : float
        Quantisation step of the read-out, mm (for example 0.006 mm for the
        Bonneville array of paper 001); 0 for none.
    """

    sigma_mm: float = 0.0
    resolution_mm: float = 0.0

    def __post_init__(self) -> None:
        check_positive("sigma_mm", self.sigma_mm, allow_zero=True)
        check_positive("resolution_mm", self.resolution_mm, allow_zero=True)

    @property
    def is_identity(self) -> bool:
        """True when the model changes nothing."""
        return self.sigma_mm == 0.0 and self.resolution_mm == 0.0


def apply_noise(
    displacement_mm: NDArray[Any], noise: NoiseModel, rng: RngLike = None
) -> NDArray[np.floating[Any]]:
    """Add seeded Gaussian noise, then quantise to the read-out resolution.

    Parameters
    ----------
    displacement_mm : (...) float, mm
        Noise-free displacements.
    noise : NoiseModel
    rng : int, numpy.random.Generator or None
        Seed or generator; same seed, same output.

    Returns
    -------
    (...) float, mm
        A new array (float32 stays float32); negative values are kept: they
        are measurement noise.
    """
    u = np.array(displacement_mm, copy=True)
    if u.dtype != np.float32:
        u = u.astype(np.float64)
    if noise.sigma_mm > 0.0:
        gen = np.random.default_rng(rng)
        draw = gen.standard_normal(u.shape, dtype=u.dtype)  # float32 drawn natively: faster
        draw *= u.dtype.type(noise.sigma_mm)
        u += draw
    if noise.resolution_mm > 0.0:
        np.round(u / noise.resolution_mm, out=u)
        u *= noise.resolution_mm
    return u
