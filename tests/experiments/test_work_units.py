"""The shared runners of experiments/work_units.py: results in the jobs' order, progress counted."""

from __future__ import annotations

import pytest

from taxelkit.experiments.work_units import map_in_order, run_units


def _square(x: int) -> int:
    return x * x


@pytest.mark.parametrize("workers", [1, 2])
def test_map_in_order_keeps_the_jobs_order_and_counts_progress(workers: int) -> None:
    seen: list[tuple[int, int]] = []
    jobs = list(range(7))
    out = map_in_order(
        _square, jobs, workers=workers, chunksize=2, progress=lambda d, n: seen.append((d, n))
    )
    assert out == [j * j for j in jobs]
    assert seen == [(k, 7) for k in range(1, 8)]


def test_run_units_gives_every_index_once() -> None:
    got = dict(run_units(_square, [3, 1, 2], workers=2))
    assert got == {0: 9, 1: 1, 2: 4}
