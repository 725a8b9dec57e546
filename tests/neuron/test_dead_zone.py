"""The noise-adaptive dead zone: faithful on clean scans, above the noise on rough ones."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.neuron.dead_zone import (
    DEFAULT_NOISE_FACTOR,
    adaptive_direction_outputs,
    robust_noise_level,
)
from taxelkit.neuron.mechanoreceptor import NeuronParams, direction_output

DT_S = 0.02
PARAMS = NeuronParams(tau_s=0.1)  # a 5-sample window
FLOOR = 0.01


def _step_scan(rng: np.random.Generator, noise_mm: float) -> np.ndarray:
    """(31, 6, 6) frames: column j climbs a 0.2 mm step at sample 10 + j, plus noise, 1 um steps."""
    t = np.arange(31)[:, None, None]
    frames = np.where(t >= 10 + np.arange(6)[None, None, :], 0.2, 0.0) * np.ones((31, 6, 6))
    frames = frames + rng.normal(0.0, noise_mm, frames.shape)
    return np.round(frames / 0.001) * 0.001


def test_robust_noise_level_is_the_standard_deviation_of_a_gaussian() -> None:
    d = np.random.default_rng(3).normal(0.0, 0.004, 200_000)
    assert robust_noise_level(d) == pytest.approx(0.004, rel=0.01)
    # a few large outliers (the edge samples) do not move it
    d[:2000] = 1.0
    assert robust_noise_level(d) == pytest.approx(0.004, rel=0.03)


def test_clean_scans_give_the_faithful_outputs_bit_for_bit() -> None:
    rng = np.random.default_rng(0)
    scans = [_step_scan(rng, 0.001), _step_scan(rng, 0.001)]
    outputs, zone = adaptive_direction_outputs(scans, DT_S, epsilon_floor=FLOOR, params=PARAMS)
    assert zone.epsilon == FLOOR and zone.baselines == (0.0, 0.0)
    for z, s in zip(outputs, scans, strict=True):
        assert np.array_equal(z, direction_output(s, DT_S, epsilon=FLOOR, params=PARAMS))


def test_rough_scans_raise_the_dead_zone_above_the_noise() -> None:
    rng = np.random.default_rng(1)
    scans = [_step_scan(rng, 0.006), _step_scan(rng, 0.006)]
    outputs, zone = adaptive_direction_outputs(scans, DT_S, epsilon_floor=FLOOR, params=PARAMS)
    # u is a difference of two readings 5 samples apart: sigma_u = sqrt(2) x 6 um; the
    # step's samples (every element, 5 of 31 samples: 16 %) inflate the median by up to
    # 1 / 0.84 in quantile, i.e. the MAD by Phi^-1(0.595) / Phi^-1(0.5 + 0.25) = 1.24
    sigma_u = np.sqrt(2) * 0.006
    assert sigma_u * 0.95 <= zone.noise_level <= sigma_u * 1.35
    assert zone.epsilon == pytest.approx(DEFAULT_NOISE_FACTOR * zone.noise_level)
    fixed = direction_output(scans[0], DT_S, epsilon=FLOOR, params=PARAMS)
    spurious = (outputs[0] == -1).sum()  # the step only climbs
    assert spurious < (fixed == -1).sum() and spurious <= 2
    assert np.all((outputs[0] == 1).any(axis=0))  # every element still sees the step


def test_a_tilt_is_a_baseline_not_an_edge() -> None:
    """A constant slope (1 deg at 10 mm/s) fires every neuron with a fixed dead zone, none here."""
    slope_mm = np.tan(np.deg2rad(1.0)) * 0.2  # per sample: 0.2 mm travelled
    frames = (np.arange(31) * slope_mm)[:, None, None] * np.ones((31, 6, 6))
    fixed = direction_output(frames, DT_S, epsilon=FLOOR, params=PARAMS)
    assert (fixed != 0).mean() > 0.5
    outputs, zone = adaptive_direction_outputs([frames], DT_S, epsilon_floor=FLOOR, params=PARAMS)
    assert zone.baselines[0] == pytest.approx(5 * slope_mm)
    assert not np.any(outputs[0])


def test_bad_arguments_are_refused() -> None:
    with pytest.raises(InputError, match="at least one scan"):
        adaptive_direction_outputs([], DT_S, epsilon_floor=FLOOR)
    with pytest.raises(InputError, match="noise_factor"):
        adaptive_direction_outputs([np.zeros((4, 2, 2))], DT_S, epsilon_floor=FLOOR,
                                   noise_factor=-1.0)  # fmt: skip
