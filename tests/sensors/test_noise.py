"""Noise and quantisation are seeded and do what they say."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.sensors.noise import NoiseModel, apply_noise


def test_same_seed_same_noise_and_different_seed_differs() -> None:
    u = np.zeros((50, 16, 16))
    noise = NoiseModel(sigma_mm=0.002)
    a, b = apply_noise(u, noise, 7), apply_noise(u, noise, 7)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, apply_noise(u, noise, 8))


def test_noise_statistics_match_sigma() -> None:
    out = apply_noise(np.zeros(200_000), NoiseModel(sigma_mm=0.003), 1)
    assert out.std() == pytest.approx(0.003, rel=0.02)
    assert abs(out.mean()) < 1e-4


def test_quantisation_gives_multiples_of_the_resolution() -> None:
    res = 0.006
    out = apply_noise(np.linspace(0, 0.1, 101), NoiseModel(resolution_mm=res))
    np.testing.assert_allclose(out / res, np.round(out / res), atol=1e-9)
    assert np.max(np.abs(out - np.linspace(0, 0.1, 101))) <= res / 2 + 1e-12


def test_float32_is_preserved_and_input_untouched() -> None:
    u = np.full((4, 4), 0.1, dtype=np.float32)
    out = apply_noise(u, NoiseModel(sigma_mm=0.01), 0)
    assert out.dtype == np.float32
    np.testing.assert_array_equal(u, 0.1 * np.ones((4, 4), np.float32))


def test_negative_sigma_rejected() -> None:
    with pytest.raises(InputError, match="sigma_mm"):
        NoiseModel(sigma_mm=-0.1)
