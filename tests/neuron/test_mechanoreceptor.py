"""The neuron model against closed forms of paper 000, Eq. 1-6 and 9."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from taxelkit.errors import InputError
from taxelkit.neuron import (
    NeuronParams,
    StreamingNeuron,
    direction_output,
    membrane_potential,
    pulse_density,
    ramp,
    receptor_output,
    spatial_summation,
    temporal_summation,
    ternary,
)


def test_ramp_and_ternary_follow_eq6_and_eq9() -> None:
    np.testing.assert_array_equal(ramp([-1.0, 0.0, 2.5]), [0.0, 0.0, 2.5])
    np.testing.assert_array_equal(ternary([-0.3, -0.1, 0.1, 0.3], 0.2), [-1, 0, 0, 1])
    assert ternary([0.2], 0.2)[0] == 0  # |q| <= eps is 0
    with pytest.raises(InputError, match="epsilon"):
        ternary([0.0], -1.0)


def test_receptor_output_is_a_times_rate() -> None:
    u = np.array([0.0, 0.1, 0.3, 0.3, 0.2])[:, None, None]
    s = receptor_output(u, 0.5, gain_a=2.0)
    np.testing.assert_allclose(s[:, 0, 0], [0.0, 0.4, 0.8, 0.0, 0.4])
    signed = receptor_output(u, 0.5, gain_a=2.0, signed=True)
    np.testing.assert_allclose(signed[:, 0, 0], [0.0, 0.4, 0.8, 0.0, -0.4])


@settings(max_examples=30, deadline=None)
@given(
    arrays(np.float64, (40, 2, 3), elements=st.floats(-1, 1)),
    st.floats(0.001, 0.1),
    st.integers(1, 12),
)
def test_signed_temporal_summation_is_the_displacement_change_over_tau(
    u: np.ndarray, dt: float, n: int
) -> None:
    """With the square kernel, integral of dU/dt over tau = U(t) - U(t - tau)."""
    params = NeuronParams(gain_a=1.0, tau_s=n * dt)
    pot = membrane_potential(u, dt, params, signed=True)
    expected = np.empty_like(u)
    expected[:n] = u[:n] - u[0]
    expected[n:] = u[n:] - u[:-n]
    np.testing.assert_allclose(pot, expected, atol=1e-9)


def test_temporal_summation_of_a_constant_saturates_after_tau() -> None:
    s = np.ones((10, 1))
    out = temporal_summation(s, 0.1, 0.3)
    np.testing.assert_allclose(out[:, 0], [0.1, 0.2, 0.3] + [0.3] * 7)


def test_spatial_summation_sums_the_receptive_field() -> None:
    p = np.zeros((1, 5, 5))
    p[0, 2, 2] = 1.0
    out = spatial_summation(p, 3)
    np.testing.assert_array_equal(out[0, 1:4, 1:4], np.ones((3, 3)))
    assert out.sum() == 9.0
    full = spatial_summation(np.ones((2, 4, 4)), 3)
    assert full[0, 0, 0] == 4.0 and full[0, 1, 1] == 9.0  # corner sees 2 x 2
    with pytest.raises(InputError, match="odd"):
        spatial_summation(p, 2)


@pytest.mark.parametrize("k", [3, 5])
def test_spatial_summation_equals_the_direct_sum_on_a_random_field(k: int) -> None:
    p = np.random.default_rng(4).normal(size=(3, 6, 7))
    padded = np.pad(p, ((0, 0), (k // 2, k // 2), (k // 2, k // 2)))
    direct = sum(padded[:, i : i + 6, j : j + 7] for i in range(k) for j in range(k))
    np.testing.assert_allclose(spatial_summation(p, k), direct, rtol=0.0, atol=1e-13)


def test_pulse_density_fires_only_above_threshold() -> None:
    u = np.concatenate([np.zeros(5), np.linspace(0, 0.2, 5), np.full(20, 0.2)])[:, None, None]
    params = NeuronParams(tau_s=0.05, threshold_h=0.05)
    z = pulse_density(u, 0.01, params)
    assert np.all(z >= 0)
    assert z[:5].max() == 0.0  # at rest
    assert z[5:12].max() > 0.0  # firing while pressed
    assert z[-1, 0, 0] == 0.0  # adapted: a rapidly adapting unit stops firing


def test_direction_output_is_plus_on_rising_and_minus_on_falling_steps() -> None:
    t = np.arange(60)
    step = np.where((t >= 20) & (t < 40), 0.05, 0.0)[:, None, None]
    z = direction_output(step, 0.01, epsilon=0.01, params=NeuronParams(tau_s=0.05))
    assert set(np.unique(z[18:26, 0, 0])) == {0, 1}
    assert set(np.unique(z[38:46, 0, 0])) == {-1, 0}
    assert z[:20].max() == 0 and z[50:].min() == 0


def test_streaming_equals_batch() -> None:
    rng = np.random.default_rng(0)
    u = np.cumsum(rng.normal(0, 0.01, (200, 3, 4)), axis=0)
    params = NeuronParams(tau_s=0.07, threshold_h=0.005, receptive_field=3)
    neuron = StreamingNeuron((3, 4), 0.01, params)
    stream = np.stack([neuron.push(f) for f in u])
    np.testing.assert_allclose(stream, pulse_density(u, 0.01, params), atol=1e-12)
    signed = StreamingNeuron((3, 4), 0.01, params, signed=True, epsilon=0.01)
    stream_z = np.stack([signed.push(f) for f in u])
    np.testing.assert_array_equal(stream_z, direction_output(u, 0.01, epsilon=0.01, params=params))
    neuron.reset()
    assert np.all(neuron.push(u[0]) == 0.0)


def test_bad_inputs() -> None:
    with pytest.raises(InputError, match="receptive_field"):
        NeuronParams(receptive_field=2)
    with pytest.raises(InputError, match="tau_s"):
        NeuronParams(tau_s=0.0)
    with pytest.raises(InputError, match="finite"):
        receptor_output(np.array([[np.nan]]), 0.1)
    with pytest.raises(InputError, match="shape"):
        StreamingNeuron((2, 2), 0.1).push(np.zeros((3, 3)))
