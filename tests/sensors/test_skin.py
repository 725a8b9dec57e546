"""Closed-form checks of the elastic skin model."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from taxelkit.errors import InputError
from taxelkit.sensors.skin import (
    SkinModel,
    coupling_kernel_1d,
    coupling_margin_taxels,
    displacement_from_penetration,
)


@pytest.mark.parametrize("spread_mm", [0.0, 0.5, 1.0, 2.5])
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_flat_press_gives_uniform_field(spread_mm: float, dtype: type) -> None:
    skin = SkinModel(spread_mm=spread_mm)
    pitch = 1.2
    m = coupling_margin_taxels(skin, pitch)
    p = np.full((3, 16 + 2 * m, 16 + 2 * m), 0.25, dtype=dtype)
    u = displacement_from_penetration(p, pitch_mm=pitch, skin=skin)
    assert u.shape == (3, 16, 16)
    assert u.dtype == dtype
    np.testing.assert_allclose(u, 0.25, rtol=1e-6)


@pytest.mark.parametrize("spread_mm", [0.0, 0.8, 1.5])
def test_step_under_half_the_array_separates_halves_by_step_height(spread_mm: float) -> None:
    skin = SkinModel(spread_mm=spread_mm)
    pitch, indent, step = 1.0, 0.1, 0.05
    m = coupling_margin_taxels(skin, pitch)
    cols = 24
    p = np.full((10 + 2 * m, cols + 2 * m), indent)
    p[:, (cols + 2 * m) // 2 :] += step  # raised half on the +x side
    u = displacement_from_penetration(p, pitch_mm=pitch, skin=skin)
    far = m + 1  # taxels farther than the kernel reach from the step
    low, high = u[:, : cols // 2 - far], u[:, cols // 2 + far :]
    np.testing.assert_allclose(low, indent, atol=1e-12)
    np.testing.assert_allclose(high, indent + step, atol=1e-12)
    # the profile across the step never decreases
    assert np.all(np.diff(u, axis=1) >= -1e-15)


def test_coupling_rounds_the_step_on_the_low_side_only() -> None:
    skin = SkinModel(spread_mm=1.0)
    m = coupling_margin_taxels(skin, 1.0)
    p = np.zeros((5 + 2 * m, 12 + 2 * m))
    p[:, (12 + 2 * m) // 2 :] = 0.2
    u = displacement_from_penetration(p, pitch_mm=1.0, skin=skin)
    centre = p[m:-m, m:-m]
    assert np.all(u >= centre)  # the skin never sits above the body
    first_low = u[:, 12 // 2 - 1]
    assert np.all(first_low > 0.0) and np.all(first_low < 0.2)  # sag next to the step


def _sphere_penetration(radius: float, depth: float, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    r2 = x[None, :] ** 2 + y[:, None] ** 2
    z = radius - np.sqrt(np.maximum(radius**2 - r2, 0.0))  # height of the sphere surface
    z[r2 > radius**2] = np.inf
    return np.maximum(depth - z, 0.0)


@pytest.mark.parametrize(("radius", "depth"), [(6.0, 0.2), (10.0, 0.5), (4.0, 0.05)])
def test_sphere_contact_radius_is_sqrt_2rd(radius: float, depth: float) -> None:
    """Without coupling the touched region is the spherical cap: radius sqrt(2Rd - d^2)."""
    pitch = 0.05
    skin = SkinModel(spread_mm=0.0)
    n = 121
    x = (np.arange(n) - (n - 1) / 2) * pitch
    u = displacement_from_penetration(
        _sphere_penetration(radius, depth, x, x), pitch_mm=pitch, skin=skin
    )
    area = np.count_nonzero(u > 0) * pitch**2
    expected = np.sqrt(2 * radius * depth - depth**2)
    assert np.sqrt(area / np.pi) == pytest.approx(expected, abs=pitch)
    assert expected == pytest.approx(np.sqrt(2 * radius * depth), rel=0.03)
    assert u.max() == pytest.approx(depth, abs=1e-12)


def test_sphere_with_coupling_keeps_contact_and_adds_bounded_sag() -> None:
    radius, depth, pitch = 6.0, 0.2, 0.1
    skin = SkinModel(spread_mm=0.5)
    m = coupling_margin_taxels(skin, pitch)
    n = 81
    x = (np.arange(n + 2 * m) - (n + 2 * m - 1) / 2) * pitch
    p = _sphere_penetration(radius, depth, x, x)
    u = displacement_from_penetration(p, pitch_mm=pitch, skin=skin)
    touched = p[m:-m, m:-m] > 0
    eq_radius = np.sqrt(np.count_nonzero(u > 0.01 * depth) * pitch**2 / np.pi)
    cap = np.sqrt(2 * radius * depth - depth**2)
    # the sag widens the visible contact by at most the kernel reach
    assert cap - pitch <= eq_radius <= cap + 3 * skin.spread_mm
    np.testing.assert_array_equal(u[touched] >= p[m:-m, m:-m][touched], True)


def test_kernel_is_normalised_and_symmetric() -> None:
    w = coupling_kernel_1d(SkinModel(spread_mm=0.8), 0.5)
    assert w.sum() == pytest.approx(1.0)
    np.testing.assert_allclose(w, w[::-1])
    assert coupling_margin_taxels(SkinModel(spread_mm=0.8), 0.5) == 5  # ceil(3 * 0.8 / 0.5)


@settings(max_examples=40, deadline=None)
@given(arrays(np.float64, (9, 11), elements=st.floats(0.0, 1.0)))
def test_displacement_never_below_penetration(p: np.ndarray) -> None:
    skin = SkinModel(spread_mm=0.6, coupling=0.7)
    u = displacement_from_penetration(p, pitch_mm=0.5, skin=skin)
    m = coupling_margin_taxels(skin, 0.5)
    assert np.all(u >= p[m:-m, m:-m])
    assert np.all(u <= p.max() + 1e-12)


def test_bad_inputs_raise_input_error() -> None:
    skin = SkinModel(spread_mm=1.0)
    with pytest.raises(InputError, match="penetration_mm"):
        displacement_from_penetration(np.zeros((4, 4)), pitch_mm=1.0, skin=skin)
    with pytest.raises(InputError, match="coupling"):
        SkinModel(spread_mm=1.0, coupling=1.5)
    with pytest.raises(InputError, match="spread_mm"):
        SkinModel(spread_mm=-1.0)


@pytest.mark.parametrize("coupling", [1.0, 0.6])
def test_spread_is_the_valid_2d_correlation_with_the_outer_product_kernel(coupling: float) -> None:
    """Against a direct sum over the (2m+1)^2 taps, in float64, for a random field."""
    skin = SkinModel(spread_mm=1.3, coupling=coupling)
    pitch = 0.9
    m = coupling_margin_taxels(skin, pitch)
    w = coupling_kernel_1d(skin, pitch)
    kernel = np.outer(w, w)
    p = np.random.default_rng(3).uniform(0.0, 1.0, (2, 5 + 2 * m, 7 + 2 * m))
    direct = np.zeros((2, 5, 7))
    for i in range(2 * m + 1):
        for j in range(2 * m + 1):
            direct += kernel[i, j] * p[:, i : i + 5, j : j + 7]
    expected = np.maximum(p[:, m:-m, m:-m], coupling * direct)
    u = displacement_from_penetration(p, pitch_mm=pitch, skin=skin)
    np.testing.assert_allclose(u, expected, rtol=0.0, atol=1e-15)
