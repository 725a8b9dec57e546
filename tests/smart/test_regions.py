"""Segmentation into contact regions: connectivity, merged fragments, vectorised over frames."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.smart.regions import RegionConfig, disc_offsets, segment_frames


def test_diagonal_taxels_are_one_component_and_frames_never_connect() -> None:
    img = np.zeros((2, 8, 8), bool)
    img[0, [1, 2, 3], [1, 2, 3]] = True  # a 45 deg line: 8-connected
    img[1, [1, 2, 3], [1, 2, 3]] = True  # the same taxels one frame later: a new region
    reg = segment_frames(img, pitch_mm=1.0, config=RegionConfig(merge_gap_pitches=0.0))
    assert reg.n_regions == 2
    assert reg.frame.tolist() == [0, 1]
    assert reg.n_taxels.tolist() == [3, 3]


def test_a_dead_taxel_does_not_split_a_line_but_distant_contacts_stay_apart() -> None:
    img = np.zeros((1, 10, 16), bool)
    img[0, 2, 1:9] = True
    img[0, 2, 4] = False  # a dead taxel: one missing in the line
    img[0, 8, 10:13] = True  # a second object far away
    plain = segment_frames(img, pitch_mm=1.5, config=RegionConfig(merge_gap_pitches=0.0))
    assert plain.n_regions == 3
    merged = segment_frames(img, pitch_mm=1.5)
    assert merged.n_regions == 2
    assert merged.n_taxels.tolist() == [7, 3]
    np.testing.assert_allclose(merged.centre_mm[1], [11 * 1.5, 8 * 1.5])
    np.testing.assert_allclose(merged.area_mm2, merged.n_taxels * 1.5**2)


def test_the_merge_gap_is_in_pitches_so_it_scales_with_the_array() -> None:
    img = np.zeros((1, 5, 12), bool)
    img[0, 2, [2, 6]] = True  # three taxels between: four pitches apart
    assert segment_frames(img, pitch_mm=1.0).n_regions == 2
    cfg = RegionConfig(merge_gap_pitches=4.0)
    assert segment_frames(img, pitch_mm=1.0, config=cfg).n_regions == 1
    assert segment_frames(img, pitch_mm=3.0, config=cfg).n_regions == 1
    assert cfg.merge_gap_mm(3.0) == 12.0


def test_batch_equals_frame_by_frame_and_translation_moves_the_centroid() -> None:
    rng = np.random.default_rng(5)
    img = rng.random((20, 12, 12)) < 0.15
    whole = segment_frames(img, pitch_mm=2.0)
    for t in range(img.shape[0]):
        one = segment_frames(img[t : t + 1], pitch_mm=2.0)
        idx = whole.in_frame(t)
        np.testing.assert_array_equal(one.n_taxels, whole.n_taxels[idx])
        np.testing.assert_allclose(one.centre_mm, whole.centre_mm[idx])
    shifted = segment_frames(
        np.roll(img[:1], 1, axis=2) & ~np.roll(img[:1], 1, axis=2), pitch_mm=2.0
    )
    assert shifted.n_regions == 0
    blob = np.zeros((1, 12, 12), bool)
    blob[0, 3:5, 2:6] = True
    a = segment_frames(blob, pitch_mm=2.0)
    b = segment_frames(np.roll(blob, 3, axis=2), pitch_mm=2.0)
    np.testing.assert_allclose(b.centre_mm - a.centre_mm, [[6.0, 0.0]])


def test_labels_number_regions_in_frame_order() -> None:
    img = np.zeros((3, 6, 6), bool)
    img[0, 0, 0] = img[0, 5, 5] = img[2, 2, 2] = True
    reg = segment_frames(img, pitch_mm=1.0)
    assert reg.frame.tolist() == [0, 0, 2]
    assert set(np.unique(reg.labels).tolist()) == {0, 1, 2, 3}
    assert reg.in_frame(1).size == 0


def test_bad_input_is_refused() -> None:
    with pytest.raises(InputError, match="images"):
        segment_frames(np.zeros((4, 4)), pitch_mm=1.0)
    with pytest.raises(InputError, match="pitch_mm"):
        segment_frames(np.zeros((1, 4, 4), bool), pitch_mm=0.0)
    with pytest.raises(InputError, match="merge_gap_pitches"):
        RegionConfig(merge_gap_pitches=-1.0)
    assert disc_offsets(1.5).sum() == 9 and disc_offsets(1.0).sum() == 5


@pytest.mark.parametrize("seed", range(8))
def test_repeated_frames_are_segmented_once_with_the_same_regions(seed: int) -> None:
    """A stack whose frames repeat is segmented one distinct image at a time, unseen."""
    from taxelkit.smart.regions import RegionConfig, _changed, _segment

    rng = np.random.default_rng(seed)
    t = int(rng.integers(2, 40))
    img = rng.uniform(size=(t, int(rng.integers(2, 20)), int(rng.integers(2, 20)))) < 0.15
    img = np.repeat(img, rng.integers(1, 6, t), axis=0)
    img[rng.integers(0, img.shape[0], 3)] = False  # empty frames among them
    for gap in (0.0, 3.0, 5.0):
        cfg = RegionConfig(merge_gap_pitches=gap)
        fast, plain = segment_frames(img, pitch_mm=1.5, config=cfg), _segment(img, 1.5, cfg)
        for name in ("labels", "frame", "n_taxels", "centre_mm", "area_mm2", "taxel_rc"):
            got, want = getattr(fast, name), getattr(plain, name)
            assert got.dtype == want.dtype and np.array_equal(got, want), name
        assert np.array_equal(fast.taxel_start, plain.taxel_start)
    assert _changed(np.repeat(img[:1], 8, axis=0)) is not None  # repeats: segmented once
