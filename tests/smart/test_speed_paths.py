"""Speed-only paths of Levels 1-4 give exactly what the plain code gives."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.smart.levels12 import _touched


@pytest.mark.parametrize("shape", [(16, 16), (8, 8), (5, 7), (3, 1), (32, 33)])
@pytest.mark.parametrize("time_major", [True, False])
def test_touched_arrays_are_those_with_any_taxel_on(
    shape: tuple[int, int], time_major: bool
) -> None:
    rng = np.random.default_rng(sum(shape))
    for a, b in [(7, 5), (1, 9), (12, 1), (0, 3)]:
        images = rng.random((a, b, *shape)) < rng.random((a, b, 1, 1)) * 0.01
        axis = (0, 2, 3) if time_major else (1, 2, 3)
        np.testing.assert_array_equal(_touched(images, time_major), images.any(axis=axis))
        sliced = images[:, ::2]  # not contiguous
        axis_s = (0, 2, 3) if time_major else (1, 2, 3)
        np.testing.assert_array_equal(_touched(sliced, time_major), sliced.any(axis=axis_s))
