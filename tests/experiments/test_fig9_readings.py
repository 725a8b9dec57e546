"""The Fig. 9 readings: codes from counts or fractions, and the orthogonal threshold search."""

from __future__ import annotations

import numpy as np

from taxelkit.experiments import fig9_readings as fr


def test_count_code_fills_in_as_the_trace_grows_relative_code_does_not() -> None:
    d = (2.0, 7.0, 8.0, 9.0)
    early, late = np.zeros(12), np.zeros(12)
    early[0], late[0] = 3.0, 30.0
    assert (fr._code(early, d, "count").reshape(4, 12)[:, 0] == [1, -1, -1, -1]).all()
    assert (fr._code(late, d, "count").reshape(4, 12)[:, 0] == 1).all()
    rel = (0.1, 0.2, 0.3, 0.4)
    np.testing.assert_array_equal(fr._code(early, rel, "relative"), fr._code(late, rel, "relative"))


def test_orthogonal_thresholds_minimise_the_overlap_of_the_stored_codes() -> None:
    rng = np.random.default_rng(0)
    hists = [rng.integers(0, 30, 12).astype(float) for _ in range(5)]
    d = fr._orthogonal(hists, "count")
    assert len(d) == 4 and list(d) == sorted(d)

    def overlap(th: tuple[float, ...]) -> float:
        x = np.stack([fr._code(h, th, "count") for h in hists]).astype(float)
        g = x @ x.T
        return float(np.sum(np.triu(g, 1) ** 2))

    for _ in range(20):
        other = tuple(sorted(rng.choice(fr.ORTHOGONAL_GRID_COUNT, 4, replace=False)))
        assert overlap(d) <= overlap(other)
