"""The robustness sweep: same result on a local Dask cluster as in-process; scoring; CLI."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from taxelkit.cli import run
from taxelkit.errors import InputError
from taxelkit.experiments.robustness import (
    FAULTS,
    LIFT_OFF,
    RobustnessResult,
    TrialOutcome,
    run_robustness,
)


def small(**kw: object) -> RobustnessResult:
    return run_robustness(seed=3, n_trials=1, engines=["kinematic"], rates_hz=[20.0], **kw)  # type: ignore[arg-type]


def test_a_small_sweep_on_a_local_dask_cluster_equals_the_in_process_one() -> None:
    distributed = pytest.importorskip("distributed", reason="needs the dask extra")
    here = small(workers=1)
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None
    ) as cluster:
        there = small(scheduler=cluster.scheduler_address)
    assert here.outcomes == there.outcomes
    doc = here.to_json()
    assert doc["n_trials"] == 1 and doc["engines"] == ["kinematic"]
    assert len(here.outcomes) == 6 * (len(FAULTS) + 1) + len(FAULTS)
    assert doc["sliding"]["identified"] == 0
    assert doc["overall"]["wrong"] == 0


def test_outcomes_score_wrong_names_worse_than_doubt() -> None:
    def o(truth: str, ident: str | None) -> TrialOutcome:
        return TrialOutcome("kinematic", 20.0, "none", truth, 0, ident, ())

    assert o("cube", "cube").correct and not o("cube", "cube").wrong
    assert not o("cube", None).correct and not o("cube", None).wrong
    assert o("cube", "tetrahedron").wrong
    assert o("sliding", "unknown").correct and o("sliding", None).correct
    assert not o("sliding", "cylinder").correct


def test_unknown_engines_and_trials_are_refused() -> None:
    with pytest.raises(InputError, match="unknown engine"):
        run_robustness(engines=["bullet"], n_trials=1)
    with pytest.raises(InputError, match="n_trials"):
        run_robustness(n_trials=0)


def test_reproduce_robustness_writes_json_and_heat_map(tmp_path: Path) -> None:
    args = ["reproduce", "robustness", "--out", str(tmp_path), "--trials", "1"]
    code = run([*args, "--workers", "1", "--seed", "2"])
    assert code == 0
    doc = json.loads((tmp_path / "robustness.json").read_text())
    assert doc["experiment"] == "robustness"
    assert {c["fault"] for c in doc["cells"]} == {*FAULTS, LIFT_OFF}
    assert (tmp_path / "robustness.png").stat().st_size > 10_000
