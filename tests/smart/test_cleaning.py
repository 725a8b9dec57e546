"""Image cleaning: each rule on a hand-made stream, batch == streaming, and its effect on rolls."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import taxelkit.smart.cleaning as cleaning_module
from taxelkit.errors import InputError
from taxelkit.motion.engines import scenario_from_engine
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.sensors import BONNEVILLE_16X16
from taxelkit.sensors.faults import fault_model
from taxelkit.smart.cleaning import CleaningConfig, clean_images
from taxelkit.smart.cleaning_stream import ImageCleaner
from taxelkit.smart.recogniser import recognise

T = np.arange(60) / 20.0


def blank(n: int = 60, shape: tuple[int, int] = (16, 16)) -> np.ndarray:
    return np.zeros((n, *shape), bool)


def test_a_taxel_on_from_the_start_is_masked_until_it_reads_off() -> None:
    f = blank()
    f[:40, 2, 2] = True  # stuck, then it recovers
    f[50:, 2, 2] = True  # a real touch later
    f[10:30, 8:10, 8:12] = True  # a real contact elsewhere
    out = clean_images(f, T)
    assert not out[:40, 2, 2].any()
    assert out[51:, 2, 2].all()  # a new touch counts (after one frame of persistence)
    assert out[11:30, 8:10, 8:12].all()


def test_an_isolated_taxel_on_for_longer_than_stuck_s_is_masked() -> None:
    f = blank(100)
    f[10:, 5, 5] = True  # becomes stuck at 0.5 s
    out = clean_images(f, np.arange(100) / 20.0, config=CleaningConfig(stuck_s=1.5))
    assert out[11 : 10 + 29, 5, 5].all()  # a still point for 1.5 s: kept
    assert not out[10 + 30 :, 5, 5].any()  # then taken for stuck


def test_dead_taxels_in_a_line_are_bridged() -> None:
    f = blank()
    f[5:, 7, 3:12] = True
    f[:, 7, 6] = False  # dead
    out = clean_images(f, T)
    assert out[6:, 7, 3:12].all()


def test_single_flickers_are_dropped_and_a_real_point_kept() -> None:
    rng = np.random.default_rng(1)
    f = rng.random((60, 16, 16)) < 0.005
    f[20:40, 8:10, 8:10] = True
    out = clean_images(f, T)
    assert out[21:40, 8:10, 8:10].all()
    elsewhere = out.copy()
    elsewhere[:, 7:11, 7:11] = False
    assert elsewhere.sum() <= 8  # of ~77 flips; each survives with probability ~9 x 0.005
    assert f.sum() - f[:, 7:11, 7:11].sum() > 50


def test_two_flips_riding_on_a_flip_the_frame_before_are_dropped() -> None:
    f = blank()
    f[1:, 8:11, 8:11] = True  # a real contact
    f[9, 1, 4] = True  # a flip ...
    f[10, 0, 3:5] = True  # ... and two beside it the next frame, far from the contact
    one = clean_images(f, T, config=CleaningConfig(persistence_depth=1))
    assert one[10, 0, 3:5].all()  # the one-frame test lets the pair through
    out = clean_images(f, T)
    assert not out[9:11, :2, 3:6].any()
    assert out[1:, 8:11, 8:11].all()  # a cluster of nine counts at once
    with pytest.raises(InputError, match="persistence_depth"):
        CleaningConfig(persistence_depth=3)


def test_strays_beside_a_larger_contact_are_dropped() -> None:
    f = blank()
    f[:, 3:6, 3:6] = True
    f[1:, 12, 12] = True  # persistent, far from the contact
    f[0, 3:6, 3:6] = False
    out = clean_images(f, T, config=CleaningConfig(stuck=False))
    assert not out[:, 12, 12].any()
    alone = blank()
    alone[1:, 12, 12] = True
    alone[0] = False
    kept = clean_images(alone, T, config=CleaningConfig(stuck=False))
    assert kept[2:, 12, 12].all()  # alone, a single taxel is a point contact


def test_everything_off_leaves_the_images_alone() -> None:
    f = np.random.default_rng(2).random((60, 16, 16)) < 0.2
    off = CleaningConfig(stuck=False, bridge=False, persistence=False, strays=False)
    np.testing.assert_array_equal(clean_images(f, T, config=off), f)


@given(
    seed=st.integers(0, 2**32 - 1),
    rows=st.integers(3, 20),
    cols=st.sampled_from([3, 8, 16, 17, 33, 64, 70, 128, 130]),
    density=st.floats(0.0, 0.4),
)
@settings(max_examples=40, deadline=None)
def test_streaming_equals_batch_and_one_word_equals_several(
    seed: int, rows: int, cols: int, density: float
) -> None:
    rng = np.random.default_rng(seed)
    f = rng.random((25, rows, cols)) < density
    f[:, rows // 2, :] |= rng.random(cols) < 0.5  # something persistent
    t = np.cumsum(rng.uniform(0.01, 0.1, 25))
    batch = clean_images(f, t)
    for depth in (1, 2):
        cfg = CleaningConfig(persistence_depth=depth)
        cleaner = ImageCleaner((rows, cols), config=cfg)
        stream = np.stack([cleaner.push(img, ts) for img, ts in zip(f, t, strict=True)])
        np.testing.assert_array_equal(stream, clean_images(f, t, config=cfg))
    np.testing.assert_array_equal(stream, batch)
    wide = cleaning_module._Words(cols)  # the path of arrays over 64 columns, forced
    original = cleaning_module._backend
    try:
        cleaning_module._backend = lambda _cols: wide
        np.testing.assert_array_equal(clean_images(f, t), batch)
    finally:
        cleaning_module._backend = original


def test_bad_input_is_refused() -> None:
    with pytest.raises(InputError, match="bool"):
        clean_images(np.zeros((3, 4, 4)), np.arange(3.0))
    with pytest.raises(InputError, match="t_s"):
        clean_images(np.zeros((3, 4, 4), bool), np.arange(4.0))
    with pytest.raises(InputError, match="stuck_s"):
        CleaningConfig(stuck_s=0.0)


@pytest.mark.parametrize("fault", ["stuck", "flicker"])
def test_cleaning_rescues_rolls_that_the_paper_pipeline_loses(fault: str) -> None:
    """Six rolls through a faulty sensor: identified with cleaning, mostly lost without."""
    cleaned = raw = 0
    for k, name in enumerate(
        ("sphere", "cylinder", "cube", "cone", "truncated-cone", "tetrahedron")
    ):
        sc = scenario_from_engine("kinematic", name, rng=100 + k)
        rec = frames_from_scenario(BONNEVILLE_16X16, sc, rng=k)
        seen = fault_model(fault).apply(rec, threshold=0.03, rng=k)
        cleaned += recognise(seen).identified == name
        raw += recognise(seen, cleaning=None).identified == name
    assert cleaned >= 5
    assert raw <= 3
