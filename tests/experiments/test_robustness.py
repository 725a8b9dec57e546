"""The robustness sweep: same result on a local Dask cluster as in-process; scoring; CLI."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
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
from taxelkit.experiments.robustness_outcomes import outcomes_json


def small(**kw: object) -> RobustnessResult:
    return run_robustness(
        seed=3,
        n_trials=1,
        engines=["kinematic"],
        rates_hz=[20.0],
        arrays=[(12, 2.5)],
        array_trials=1,
        **kw,
    )  # type: ignore[arg-type]


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
    # the main matrix: six objects x (faults + lift-off), sliding x faults; the 12 x 12
    # array: seven motions x (none, all)
    assert len(here.outcomes) == 6 * (len(FAULTS) + 1) + len(FAULTS) + 7 * 2
    assert {c["array"] for c in doc["arrays"]["cells"]} == {"12x12@2.5"}
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


def test_a_name_withdrawn_later_still_counts_as_named_wrongly() -> None:
    def o(truth: str, ident: str | None, named: tuple[str, ...]) -> TrialOutcome:
        return TrialOutcome("kinematic", 20.0, "none", truth, 0, ident, (), named=named)

    withdrawn = o("truncated-cone", "unknown", ("cylinder",))
    assert not withdrawn.wrong and withdrawn.named_wrongly
    assert not o("cube", "cube", ("cube",)).named_wrongly
    assert not o("cube", None, ()).named_wrongly
    assert o("sliding", None, ("cylinder",)).named_wrongly
    doc = outcomes_json([withdrawn, o("cube", "cube", ("cube",))], ["kinematic"], [20.0],
                        ["none"], 1, {})  # fmt: skip
    assert doc["overall"]["named_wrongly"] == 1 and doc["overall"]["wrong"] == 0


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


def test_the_held_out_sweep_is_the_sweep_on_another_seed_marked_as_such() -> None:
    from taxelkit.experiments.robustness_heldout import HELD_OUT_OFFSET, run_robustness_heldout

    held = run_robustness_heldout(
        seed=3,
        n_trials=1,
        engines=["kinematic"],
        rates_hz=[20.0],
        untuned_rates_hz=[30.0],
        arrays=[],
        workers=1,
    )
    same = run_robustness(
        seed=3 + HELD_OUT_OFFSET,
        n_trials=1,
        engines=["kinematic"],
        rates_hz=[20.0],
        arrays=[],
        workers=1,
    )
    assert held.result.outcomes == same.outcomes
    doc = held.to_json()
    assert doc["experiment"] == "robustness-heldout"
    assert (doc["tuned_on_seed"], doc["held_out_seed"]) == (3, 3 + HELD_OUT_OFFSET)
    assert doc["cells"] == same.to_json()["cells"]
    # the README block puts both seeds side by side, one row per engine and object
    from taxelkit.experiments.report import robustness_heldout_markdown

    text = robustness_heldout_markdown({"robustness": same.to_json(), "robustness-heldout": doc})
    assert "| kinematic | cone |" in text and "held out" in text
    # the same motions at a rate outside the matrix: kept apart, one row per engine and rate
    assert held.untuned is not None and held.untuned.rates_hz == (30.0,)
    assert {o.rate_hz for o in held.untuned.outcomes} == {30.0}
    extra = doc["untuned_rates"]
    assert extra["rates_hz"] == [30.0] and {c["rate_hz"] for c in extra["cells"]} == {30.0}
    assert len(held.untuned.outcomes) == len(same.outcomes)  # every motion, fault and object
    assert text.count("\n| kinematic |") == 7
    assert "| kinematic | 30 | " in text and "outside the matrix" in text


def test_the_held_out_rates_outside_the_matrix_must_be_outside_it() -> None:
    from taxelkit.experiments.robustness_heldout import run_robustness_heldout

    with pytest.raises(InputError, match="both in the matrix and outside it"):
        run_robustness_heldout(
            n_trials=1, engines=["kinematic"], rates_hz=[20.0], untuned_rates_hz=[20.0]
        )


def test_the_misses_block_names_the_failing_rolls_and_the_wrong_names() -> None:
    from taxelkit.experiments.report import robustness_misses_markdown
    from taxelkit.experiments.robustness_heldout import held_out_json

    def outcome(rate: float, fault: str, truth: str, trial: int, ident: str | None) -> TrialOutcome:
        return TrialOutcome("mujoco", rate, fault, truth, trial, ident, ())

    outcomes = [
        outcome(rate, fault, "cone", t, None if t == 1 else "cone")
        for rate in (20.0, 100.0)
        for fault in ("none", "dead")
        for t in range(3)
    ]
    outcomes.append(outcome(5.0, "none", "truncated-cone", 4, "cone"))  # a wrong name at 5 fps
    outcomes.append(outcome(20.0, "none", "truncated-cone", 4, "truncated-cone"))
    result = RobustnessResult(
        tuple(outcomes), ("mujoco",), (5.0, 20.0, 100.0), ("none", "dead"), 3, {}
    )
    doc = result.to_json()
    cone = [c for c in doc["cells"] if c["object"] == "cone"]
    assert all(c["missed"] == [[1, None]] for c in cone)
    text = robustness_misses_markdown(
        {"robustness": doc, "robustness-heldout": held_out_json(doc, 0)}
    )
    assert "| mujoco | cone | 4 of 4 | 1 (4) | none |" in text
    assert "| mujoco | truncated-cone | 0 of 1 | none | cone (5 frames/s, none, roll 4) |" in text
    assert "Seed 11 (held out)" in text


def test_the_sampling_line_tells_established_misses_from_chance() -> None:
    from taxelkit.experiments.report_robustness import _sampling, cell_interval

    low, high = cell_interval(48, 50)
    assert low < 0.96 < high and high > 0.98  # 2 misses of 50: not established
    assert cell_interval(45, 50)[1] < 0.98  # 5 misses of 50: established
    assert cell_interval(50, 50)[1] == pytest.approx(1.0)

    def cell(correct: int) -> dict[str, float]:
        return {"n": 50, "correct": correct, "accuracy": correct / 50}

    cells = [cell(50), cell(48), cell(45), cell(49)]
    text = _sampling(cells)
    assert "Of the 2 cells below 0.98" in text and ", 1 lies below it" in text
    # the count chance alone gives, against a seeded simulation of cells at the pooled accuracy
    pooled = (50 + 48 + 45 + 49) / 200
    draws = np.random.default_rng(0).binomial(50, pooled, size=(20000, 4))
    simulated = float((draws < 49).sum(axis=1).mean())
    stated = float(text.split("about ")[1].split(" of the")[0])
    assert abs(stated - simulated) < 0.5 + 1e-9
    assert _sampling([cell(50)] * 3).startswith("- Of the 0 cells") and "about 0 of the 3" in (
        _sampling([cell(50)] * 3)
    )
    assert _sampling([]) == ""


def test_the_misses_are_counted_as_rolls_seen_in_several_cells() -> None:
    from taxelkit.experiments.report_robustness import _rolls

    def cell(engine: str, rate: float, missed: list[list[object]]) -> dict[str, object]:
        return {"engine": engine, "object": "cone", "rate_hz": rate, "missed": missed}

    low = [
        cell("mujoco", 20.0, [[43, None], [8, "unknown"]]),
        cell("mujoco", 100.0, [[43, "truncated-cone"]]),
        cell("kinematic", 20.0, [[43, None]]),  # another engine: another motion
    ]
    text = _rolls(low)
    assert "Their misses are 3 roll(s), 1 of them missed in more than one" in text
    assert "(at most 2)" in text
    assert _rolls([]) == "" and _rolls([cell("mujoco", 20.0, [])]) == ""
