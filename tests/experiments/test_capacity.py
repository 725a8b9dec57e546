"""The capacity experiment: same result in-process and on Dask; scoring; report blocks."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.experiments.capacity import run_capacity
from taxelkit.experiments.capacity_rules import CAPACITY_RULES, partition_memories
from taxelkit.experiments.report import render_block
from taxelkit.plotting.experiments import plot_experiment

TINY = {
    "seed": 5,
    "n_trials": 1,
    "n_shapes": 4,
    "sizes": (2, 4),
    "s": (0.6, 1.0),
    "rules": ("hebbian", "dense", "signature", "signature-dense"),
    "n_twin_trials": 1,
}


@pytest.fixture(scope="module")
def tiny() -> object:
    return run_capacity(workers=1, **TINY)  # type: ignore[arg-type]


def test_a_tiny_run_is_the_same_on_a_local_dask_cluster(tiny: object) -> None:
    distributed = pytest.importorskip("distributed", reason="needs the dask extra")
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None
    ) as cluster:
        there = run_capacity(scheduler=cluster.scheduler_address, **TINY)  # type: ignore[arg-type]
    assert there.to_json() == tiny.to_json()  # type: ignore[attr-defined]


def test_the_json_holds_every_rule_size_and_s_and_renders(tiny: object) -> None:
    doc = tiny.to_json()  # type: ignore[attr-defined]
    assert doc["sizes"] == [2, 4] and doc["s"] == [0.6, 1.0] and doc["n_queries"] == 4
    assert set(doc["rules"]) == set(TINY["rules"])  # type: ignore[arg-type]
    for r in doc["rules"].values():
        acc, und = np.array(r["accuracy"]), np.array(r["undecided"])
        assert acc.shape == und.shape == (2, 2)
        assert np.all((acc >= 0) & (acc + und <= 1 + 1e-12))
    assert doc["rules"]["hebbian"]["faithful"] and doc["rules"]["signature-dense"]["associative"]
    # the order-aware code names every full trace of these four shapes right
    assert doc["rules"]["signature"]["accuracy"][-1][-1] == 1.0
    assert set(doc["twins"]["named"]) == {"square / l-shape", "square / cross", "star / pentagon"}
    assert "(`signature`)" in render_block("capacity", {"capacity": doc})
    assert "square / l-shape" in render_block("capacity-twins", {"capacity": doc})
    # the figure: every rule's accuracy against stored shapes at s = 0.6 and at s = 1
    fig = plot_experiment("capacity", tiny)
    for ax, col in zip(fig.axes[:2], (0, 1), strict=True):
        curves = {c.get_label(): c for c in ax.get_lines()}
        for name, rule in doc["rules"].items():
            c = curves[f"{rule['label']} ({name})"]
            assert list(c.get_xdata()) == [2, 4]
            assert list(c.get_ydata()) == [row[col] for row in rule["accuracy"]]
    plt.close(fig)


def test_memories_partition_the_shapes() -> None:
    groups = partition_memories(20, 5, np.random.default_rng(0))
    assert len(groups) == 4
    assert sorted(np.concatenate(groups).tolist()) == list(range(20))


def test_every_rule_is_labelled_and_the_paper_rule_is_the_only_faithful_one() -> None:
    assert [k for k, r in CAPACITY_RULES.items() if r.faithful] == ["hebbian"]
    assert {k for k, r in CAPACITY_RULES.items() if not r.associative} == {"matched", "signature"}


def test_bad_arguments_are_refused() -> None:
    with pytest.raises(InputError, match="divide"):
        run_capacity(n_shapes=10, sizes=(3,))
    with pytest.raises(InputError, match="unknown rule"):
        run_capacity(n_shapes=4, sizes=(4,), rules=("nope",))
