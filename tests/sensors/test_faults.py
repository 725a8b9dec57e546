"""Sensor imperfections: each model does what it says, composes, and is seeded."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from taxelkit.errors import InputError
from taxelkit.frames import TactileFrames
from taxelkit.sensors.faults import (
    FAULT_PRESETS,
    FLICKER_ON_LEVEL,
    ContactLoss,
    Crosstalk,
    DeadTaxels,
    FaultModel,
    Flicker,
    OffsetDrift,
    StuckTaxels,
    ThresholdSpread,
    fault_model,
)
from taxelkit.sensors.frame_rate import frames_at_rate

THR = 0.03


def analog(seed: int, t: int = 40, shape: tuple[int, int] = (12, 10)) -> np.ndarray:
    return np.random.default_rng(seed).uniform(0.0, 0.1, (t, *shape))


@given(seed=st.integers(0, 2**32 - 1), count=st.integers(0, 6), boolean=st.booleans())
@settings(max_examples=40, deadline=None)
def test_dead_taxels_read_zero_in_every_frame(seed: int, count: int, boolean: bool) -> None:
    f = analog(seed) > THR if boolean else analog(seed)
    out = FaultModel((DeadTaxels(count),)).apply_frames(f, np.arange(40.0), threshold=THR, rng=seed)
    always_off = ~np.any(out != 0, axis=0)
    assert always_off.sum() >= count
    changed = np.any(out != f, axis=0)
    assert changed.sum() <= count  # nothing but the dead taxels changed


@given(seed=st.integers(0, 2**32 - 1), count=st.integers(0, 6), boolean=st.booleans())
@settings(max_examples=40, deadline=None)
def test_stuck_taxels_read_contact_in_every_frame(seed: int, count: int, boolean: bool) -> None:
    f = analog(seed) > THR if boolean else analog(seed)
    out = FaultModel((StuckTaxels(count),)).apply_frames(
        f, np.arange(40.0), threshold=THR, rng=seed
    )
    on = out if boolean else out > THR
    # a taxel of these random frames is on in all 40 frames with probability 0.7**40
    assert np.all(on, axis=0).sum() == count
    assert np.any(out != f, axis=0).sum() <= count


@given(seed=st.integers(0, 2**32 - 1), name=st.sampled_from(FAULT_PRESETS))
@settings(max_examples=40, deadline=None)
def test_same_seed_same_frames_for_every_preset(seed: int, name: str) -> None:
    f = analog(seed)
    t = np.arange(40) / 20.0
    a = fault_model(name).apply_frames(f, t, threshold=THR, rng=seed)
    b = fault_model(name).apply_frames(f, t, threshold=THR, rng=seed)
    np.testing.assert_array_equal(a, b)
    assert a.shape == f.shape and a.dtype == f.dtype
    np.testing.assert_array_equal(f, analog(seed))  # the input is never changed


def test_flicker_flips_at_its_rate() -> None:
    f = np.zeros((400, 16, 16), bool)
    out = Flicker(0.01).apply(f, np.arange(400.0), threshold=THR, rng=np.random.default_rng(0))
    assert out.mean() == pytest.approx(0.01, rel=0.1)
    full = Flicker(1.0).apply(
        analog(1, 5), np.arange(5.0), threshold=THR, rng=np.random.default_rng(0)
    )
    base = analog(1, 5)
    assert np.all((full > THR) != (base > THR))
    assert np.all(full[base <= THR] == pytest.approx(FLICKER_ON_LEVEL * THR))
    none = Flicker(0.0).apply(base, np.arange(5.0), threshold=THR, rng=np.random.default_rng(0))
    np.testing.assert_array_equal(none, base)


def test_threshold_spread_and_drift_need_analog_frames() -> None:
    rng = np.random.default_rng(0)
    for fault in (ThresholdSpread(0.2), OffsetDrift()):
        with pytest.raises(InputError, match="analog"):
            fault.apply(np.zeros((3, 4, 4), bool), np.arange(3.0), threshold=THR, rng=rng)
    f = analog(2)
    same = ThresholdSpread(0.0).apply(f, np.arange(40.0), threshold=THR, rng=rng)
    np.testing.assert_allclose(same, f)
    gain = ThresholdSpread(0.2).apply(np.ones((2, 6, 6)), np.arange(2.0), threshold=THR, rng=rng)
    np.testing.assert_array_equal(gain[0], gain[1])  # a property of the taxel, not of the frame
    assert gain.min() >= 1 / 1.6 and gain.max() <= 1 / 0.4


def test_drift_grows_with_time() -> None:
    f = np.zeros((11, 3, 3))
    out = OffsetDrift(offset=0.0, drift_per_s=0.5).apply(
        f, np.arange(11.0), threshold=THR, rng=np.random.default_rng(0)
    )
    np.testing.assert_allclose(out[:, 1, 1], 0.5 * THR * np.arange(11.0))


def test_crosstalk_row_reads_its_neighbour() -> None:
    f = np.zeros((2, 6, 6), bool)
    f[:, 3, 1:4] = True
    rng = np.random.default_rng(3)
    out = Crosstalk(rows=6, coupling=0.5).apply(f, np.arange(2.0), threshold=THR, rng=rng)
    assert np.array_equal(out[:, 2, 1:4], f[:, 3, 1:4])  # row 2 reads row 3
    assert np.array_equal(out[:, 4], f[:, 3]) or np.array_equal(out[:, 4], f[:, 5])
    a = np.zeros((1, 4, 4))
    a[0, 1, 2] = 0.2
    out_a = Crosstalk(rows=4, coupling=0.25).apply(a, np.arange(1.0), threshold=THR, rng=rng)
    assert out_a[0, 0, 2] == pytest.approx(0.05)  # row 0 reads a quarter of row 1
    with pytest.raises(InputError, match="crosstalk on 7 lines"):
        Crosstalk(rows=7).apply(a, np.arange(1.0), threshold=THR, rng=rng)


def test_contact_loss_blanks_one_window_in_contact() -> None:
    f = np.zeros((100, 4, 4))
    f[20:80, 2, 2] = 1.0
    t = np.arange(100) / 100.0
    out = ContactLoss(0.07).apply(f, t, threshold=0.5, rng=np.random.default_rng(5))
    lost = np.flatnonzero((f[:, 2, 2] > 0) & (out[:, 2, 2] == 0))
    assert lost.size == 7 and np.all(np.diff(lost) == 1)
    empty = np.zeros((10, 4, 4))
    np.testing.assert_array_equal(
        ContactLoss().apply(empty, t[:10], threshold=0.5, rng=np.random.default_rng(5)), empty
    )


def test_models_compose_in_order_and_keep_the_recording() -> None:
    rec = TactileFrames(analog(4), t_s=np.arange(40) / 20.0, pitch_mm=1.5, units="mm", sensor="x")
    out = fault_model("all").apply(rec, threshold=THR, rng=1)
    assert (out.pitch_mm, out.units, out.sensor) == (1.5, "mm", "x")
    np.testing.assert_array_equal(out.t_s, rec.t_s)
    last = FaultModel((StuckTaxels(3), DeadTaxels(120)))  # dead after stuck: all dark
    assert not np.any(last.apply(rec, threshold=THR, rng=0).frames > THR)


def test_bad_fault_parameters_are_refused() -> None:
    with pytest.raises(InputError, match="unknown fault model 'melt'"):
        fault_model("melt")
    with pytest.raises(InputError, match="rate"):
        Flicker(1.5)
    with pytest.raises(InputError, match="count"):
        DeadTaxels(-1)
    with pytest.raises(InputError, match="level"):
        StuckTaxels(1, level=0.5)
    with pytest.raises(InputError, match="threshold"):
        fault_model("none").apply_frames(analog(0), np.arange(40.0), threshold=0.0)


def test_frames_at_rate_samples_and_holds() -> None:
    rec = TactileFrames(
        np.arange(241)[:, None, None] * np.ones((1, 2, 2)), t_s=np.arange(241) / 240.0
    )
    slow = frames_at_rate(rec, 5.0)
    assert slow.n_frames == 6
    np.testing.assert_allclose(slow.t_s, np.arange(6) / 5.0)
    np.testing.assert_array_equal(slow.frames[:, 0, 0], [0, 48, 96, 144, 192, 240])
    with pytest.raises(InputError, match="rate_hz"):
        frames_at_rate(rec, 0.0)
