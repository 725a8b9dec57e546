"""The chunked rolling mean of :mod:`taxelkit.smart.track_stream` gives the batch's floats."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.smart.track_geometry import rolling_mean
from taxelkit.smart.track_stream import RollingMean


@pytest.mark.parametrize("seed", range(20))
def test_rolling_mean_in_chunks_of_any_size_is_the_batch_one(seed: int) -> None:
    rng = np.random.default_rng(seed)
    n, w = int(rng.integers(1, 400)), int(rng.integers(1, 40))
    x = rng.normal(0, 10, (n, 7)) * rng.choice([1e-3, 1.0, 1e3], (1, 7))
    cuts = sorted(set(rng.integers(0, n + 1, int(rng.integers(0, 30))).tolist()))
    roll = RollingMean(w, 7)
    got = [roll.push(x[a:b]) for a, b in zip([0, *cuts], [*cuts, n], strict=True)]
    np.testing.assert_array_equal(np.concatenate(got), rolling_mean(x, w))  # the same floats
    assert roll.seen == n
