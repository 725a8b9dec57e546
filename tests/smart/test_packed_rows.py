"""Line extents from packed rows equal those of the bool images, float for float."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.smart.moments import image_stats
from taxelkit.smart.packed_rows import line_extents_from_rows, line_extents_of_images, pack_rows
from taxelkit.smart.track_geometry import line_extents


@pytest.mark.parametrize("shape", [(16, 16), (9, 12), (5, 7), (20, 8), (3, 16), (16, 1), (4, 20)])
def test_extents_equal_those_of_the_bool_images(shape: tuple[int, int]) -> None:
    rng = np.random.default_rng(sum(shape))
    images = rng.random((2000, *shape)) < rng.random((2000, 1, 1))  # sparse to full
    images[:50] = False
    images[:50, rng.integers(shape[0], size=50), rng.integers(shape[1], size=50)] = True
    stats = image_stats(images, pitch_mm=1.7625)
    on = stats.n_taxels > 0
    want = line_extents(images[on], stats.centre_mm[on], stats.orientation_deg[on], 1.7625)
    got = line_extents_of_images(images[on], stats.centre_mm[on], stats.orientation_deg[on], 1.7625)
    np.testing.assert_array_equal(got, want)
    assert np.all(want[:, 0] < want[:, 1])


def test_rows_are_packed_bit_c_for_column_c() -> None:
    images = np.zeros((2, 3, 12), bool)
    images[0, 1, [0, 3, 11]] = True
    images[1, 2, 8] = True
    assert pack_rows(images).tolist() == [[0, 1 + 8 + 2048, 0], [0, 0, 256]]
    assert pack_rows(images[:, :, :8]).dtype == np.uint8


def test_empty_frames_and_wide_rows_are_refused() -> None:
    words = np.zeros((2, 4), np.uint16)
    words[0, 1] = 3
    centre, angle = np.zeros((2, 2)), np.zeros(2)
    with pytest.raises(InputError, match="no empty frame"):
        line_extents_from_rows(words, 16, centre, angle, 1.0)
    with pytest.raises(InputError, match="cols"):
        line_extents_from_rows(words[:1], 17, centre[:1], angle[:1], 1.0)
