"""The area's held mark along many rows at once: each row's held_high."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.smart.hysteresis import held_high, held_high_rows


@pytest.mark.parametrize("enter_s", [0.0, 0.1, 0.5])
def test_rows_are_each_rows_held_high(enter_s: float) -> None:
    rng = np.random.default_rng(int(enter_s * 10))
    for _ in range(300):
        m, t = int(rng.integers(1, 4)), int(rng.integers(1, 12))
        value = rng.random((m, t)) * (rng.random((m, t)) < rng.random())
        t_s = np.cumsum(rng.choice([0.004, 0.05, 0.3, 1.0], size=(m, t)), axis=1)
        run = (rng.integers(0, 4, m) * (rng.random(m) < 0.5)).astype(np.int64)
        t_prev = rng.choice([np.nan, -0.5], m)
        held, run_end, t_last = held_high_rows(value, 0.5, t_s, enter_s, run, t_prev)
        for i in range(m):
            want, want_run, want_t = held_high(
                value[i], 0.5, t_s[i], enter_s, int(run[i]), float(t_prev[i])
            )
            np.testing.assert_array_equal(held[i], want)
            assert (int(run_end[i]), float(t_last[i])) == (want_run, want_t)
