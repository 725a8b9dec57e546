"""The committed figures (``docs/results/*.json``) are what the code produces now.

Cheap experiments are re-run whole through ``taxelkit reproduce`` at their
committed seed and compared leaf by leaf with the committed JSON, within the
tolerances measured from their seed-to-seed spread (``_truth.py`` says how
they are chosen; ``seed_spread.json`` holds them, ``_seed_spread.py``
regenerates them). Expensive experiments are checked on a deterministic slice:
trials picked by index, re-run from the same seed sequence as the committed
run. Where the JSON keeps every trial (``multi-object``, ``trace-robustness``)
the slice must equal the committed trials; where it keeps counts only
(``smart-sensor``, ``tacteme-table``), the slice is a whole row and its counts
must equal the committed row; where a row is too expensive (``robustness``,
``recall-vs-s``) a few trials must fit inside the committed counts (no more
correct, wrong, unknown or undecided trials than committed) and the whole row
is compared under the ``slow`` marker. The ``slow`` tests also re-run the
remaining experiments whole (``pytest -m slow tests/experiments/test_figure_truth.py``).

When one of these fails after a deliberate change, regenerate the experiment
(``taxelkit reproduce NAME --out docs/results --readme README.md``) and commit
the new JSON with the change.
"""

from __future__ import annotations

import json
from collections import Counter
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from taxelkit.cli import cli
from tests.experiments._truth import committed, differences, flatten, tolerances

#: Bookkeeping leaves that are not figures.
SKIP = ("seed",)


def reproduce(name: str, out: Path, *extra: str) -> dict[str, Any]:
    """Run ``taxelkit reproduce NAME --out OUT`` and return the JSON it wrote."""
    res = CliRunner().invoke(cli, ["reproduce", name, "--out", str(out), *extra])
    assert res.exit_code == 0, res.output
    assert (out / f"{name}.png").read_bytes()[:4] == b"\x89PNG"
    doc: dict[str, Any] = json.loads((out / f"{name}.json").read_text(encoding="utf-8"))
    return doc


@pytest.mark.parametrize("name", ["fig7", "fig8", "fig9", "cylinder"])
def test_cheap_experiment_reproduces_its_committed_json(name: str, tmp_path: Path) -> None:
    doc = reproduce(name, tmp_path)
    diff = differences(doc, committed(name), tolerances(name), skip=SKIP)
    assert not diff, "\n".join(diff[:20])


def test_the_comparison_catches_a_regression_beyond_the_seed_spread() -> None:
    old = committed("fig7")
    tol = tolerances("fig7")
    worse = json.loads(json.dumps(old))
    worse["abs_r"][1] -= 10 * tol["abs_r/1"]
    assert differences(worse, old, tol) == [
        f"abs_r/1: now {worse['abs_r'][1]!r}, committed {old['abs_r'][1]!r} "
        f"(tolerance {tol['abs_r/1']:.3g})"
    ]
    within = json.loads(json.dumps(old))
    within["abs_r"][1] -= 0.5 * tol["abs_r/1"]
    within["seed"] = 7
    assert differences(within, old, tol, skip=SKIP) == []
    assert differences({"a": [1, 2]}, {"a": [1]}, {}) == ["a/1: only in the new result"]
    assert flatten({"a": {"b": [True, None]}}) == {"a/b/0": True, "a/b/1": None}


# --- paper 001: smart-sensor and tacteme-table keep counts; a whole row is the slice ---


def _paper001_trials(names: list[str], pick: range, seed: int) -> list[Any]:
    """Trials ``pick`` of a run over ``names``, from the run's own seed sequence."""
    from taxelkit.experiments.paper001 import _trial

    seqs = np.random.SeedSequence(seed).spawn(len(names))
    return [_trial((names[k], seqs[k])) for k in pick]


def test_smart_sensor_truncated_cone_row_equals_the_committed_row() -> None:
    from taxelkit.experiments.paper001 import OBJECTS

    doc = committed("smart-sensor")
    n = doc["n_trials_per_object"]
    names = [o for o in OBJECTS for _ in range(n)] + ["sliding"] * doc["sliding_trials"]
    i = OBJECTS.index("truncated-cone")  # the row with every outcome: right, unknown, undecided
    got = Counter(out for _, out, _, _ in _paper001_trials(names, range(i * n, (i + 1) * n), 0))
    want = {k: v for k, v in doc["confusion"]["truncated-cone"].items() if v}
    assert dict(got) == want


def test_tacteme_table_cube_row_equals_the_committed_row() -> None:
    from taxelkit.experiments.paper001 import OBJECTS

    doc = committed("tacteme-table")
    n = doc["n_trials_per_object"]
    names = [o for o in OBJECTS for _ in range(n)]
    i = OBJECTS.index("cube")  # the row with the most tactemes (faces, edges, tipping)
    got: Counter[str] = Counter()
    for _, _, _, tactemes in _paper001_trials(names, range(i * n, (i + 1) * n), 0):
        got.update(tactemes)
    assert {t: got[t] for t in doc["produced"]["cube"]} == doc["produced"]["cube"]


# --- multi-object and trace-robustness keep every trial: the slice equals them ---


def _scene(
    engine: str, n_objects: int, trial: int, seed: int, imperfections: list[str], rates: list[float]
) -> Any:
    from taxelkit.experiments import multi_object as mo

    e_key = int.from_bytes(engine.encode()[:8], "little")
    ent = np.random.SeedSequence([seed, e_key, n_objects, trial]).generate_state(1)
    unit = mo._Unit(engine, n_objects, trial, int(ent[0]), tuple(imperfections), tuple(rates))
    return mo._run_unit(unit)


@pytest.mark.parametrize("n_objects", [2, 3])
def test_multi_object_scenes_equal_the_committed_scenes(n_objects: int) -> None:
    doc = committed("multi-object")
    imperfections = doc.get("imperfections", ["none"])
    rates = doc.get("rates_hz", [20.0])
    want = [s for s in doc["scenes"] if s["engine"] == "kinematic" and s["n_objects"] == n_objects]
    # the first three scenes at the first rate (both views); the higher rates cost more
    want = [s for s in want if s.get("rate_hz", rates[0]) == rates[0] and s["trial"] < 3]
    for scene in want:
        views = _scene(
            "kinematic", n_objects, scene["trial"], doc["seed"], imperfections, rates[:1]
        )
        got = views[imperfections.index(scene.get("imperfection", "none"))]
        now = {
            "names": list(got.names),
            "outcomes": list(got.outcomes),
            "purities": pytest.approx(list(got.purities), abs=1e-9),
            "mixed_wrong": got.mixed_wrong,
            "merges": got.merges,
            "splits": got.splits,
        }
        assert now == {k: scene[k] for k in now}, scene["trial"]


@pytest.mark.parametrize(
    ("condition", "shape"),
    [
        ("200 um, noise 10 um", "star"),
        ("200 um, noise 10 um", "triangle"),
    ],
)
def test_trace_robustness_traces_equal_the_committed_traces(condition: str, shape: str) -> None:
    from taxelkit.experiments import trace_robustness as tr

    doc = committed("trace-robustness")
    ci = next(i for i, c in enumerate(tr.CONDITIONS) if c.name == condition)
    si = tr.CONDITIONS[ci].shapes.index(shape)
    unit = (ci, shape, 0, np.random.SeedSequence([doc["seed"], ci, si, 0]))
    got = {o.tracer: o for o in tr._run_unit(unit)}
    key = (condition, shape, 0)
    want = [t for t in doc["traces"] if (t["condition"], t["shape"], t["trial"]) == key]
    assert {t["tracer"] for t in want} == set(got)
    for t in want:
        o = got[t["tracer"]]
        assert (o.closed, o.stop_reason, o.sections, o.recognised) == (
            t["closed"], t["stop_reason"], t["sections"], t["recognised"]
        ), t["tracer"]  # fmt: skip
        assert (round(o.error_mean_mm, 4), round(o.error_max_mm, 4)) == (
            t["error_mean_mm"], t["error_max_mm"]
        ), t["tracer"]  # the JSON keeps 4 decimals  # fmt: skip


# --- robustness and recall-vs-s keep counts and a row is expensive: a few trials must fit ---


def _robustness_stats(outcomes: list[Any]) -> dict[tuple[float, str], Counter[str]]:
    """Per (rate, imperfection): the counts the committed cells hold."""
    out: dict[tuple[float, str], Counter[str]] = {}
    for o in outcomes:
        c = out.setdefault((o.rate_hz, o.fault), Counter())
        c["n"] += 1
        c["correct"] += o.correct
        c["wrong"] += o.wrong
        c["unknown"] += o.identified == "unknown"
        c["undecided"] += o.identified is None
        c["faithful_correct"] += o.faithful == o.truth
        c["faithful_wrong"] += o.faithful not in (None, "unknown", o.truth)
    return out


def _committed_cells(doc: dict[str, Any], engine: str, truth: str) -> dict[Any, Counter[str]]:
    out = {}
    for c in doc["cells"]:
        if (c["engine"], c["object"]) == (engine, truth):
            n = c["n"]
            out[(c["rate_hz"], c["fault"])] = Counter(
                n=n, correct=c["correct"], wrong=c["wrong"], unknown=c["unknown"],
                undecided=c["undecided"], faithful_correct=round(c["faithful_accuracy"] * n),
                faithful_wrong=c["faithful_wrong"],
            )  # fmt: skip
    return out


def _robustness_row(truth: str, trials: range) -> dict[Any, Counter[str]]:
    from taxelkit.experiments import robustness as rb

    doc = committed("robustness")
    units = rb._units(["kinematic"], doc["rates_hz"], doc["n_trials"], doc["seed"])
    mine = [u for u in units if u.truth == truth and u.trial in trials]
    return _robustness_stats([o for u in mine for o in rb._run_unit(u)])


def _fits_inside(part: Counter[str], whole: Counter[str]) -> bool:
    """Every count of ``part``, and of its complement, is within ``whole``'s."""
    missed = part["n"] - part["correct"], part["n"] - part["faithful_correct"]
    allowed = whole["n"] - whole["correct"], whole["n"] - whole["faithful_correct"]
    return all(part[k] <= whole[k] for k in whole) and all(
        m <= a for m, a in zip(missed, allowed, strict=True)
    )


def test_robustness_truncated_cone_trials_fit_inside_the_committed_cells() -> None:
    doc = committed("robustness")
    want = _committed_cells(doc, "kinematic", "truncated-cone")
    got = _robustness_row("truncated-cone", range(3))
    assert set(got) == set(want)
    bad = {k: (dict(v), dict(want[k])) for k, v in got.items() if not _fits_inside(v, want[k])}
    assert not bad


@pytest.mark.slow
def test_robustness_truncated_cone_row_equals_the_committed_cells() -> None:
    doc = committed("robustness")
    assert _robustness_row("truncated-cone", range(doc["n_trials"])) == _committed_cells(
        doc, "kinematic", "truncated-cone"
    )


def _recall_rows(shape: str, trials: range) -> tuple[dict[str, Any], list[Any]]:
    from taxelkit.experiments import recall_vs_s as rv
    from taxelkit.world.relief import SHAPE_NAMES

    doc = committed("recall-vs-s")
    n = doc["n_trials_per_shape"]
    i = SHAPE_NAMES.index(shape)
    seqs = np.random.SeedSequence(doc["seed"]).spawn(len(SHAPE_NAMES) * n)
    return doc, [rv._trial((i, t, seqs[i * n + t])) for t in trials]


def _recall_counts(rows: list[Any]) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Per rule (faithful, improved): right and tied trials at each s."""
    out = {}
    for k, rule in enumerate(("faithful", "improved")):
        ok = np.array([r[2][k][0] for r in rows])
        tie = np.array([r[2][k][1] for r in rows])
        out[rule] = (ok.sum(axis=0), tie.sum(axis=0))
    return out


def test_recall_vs_s_triangle_trials_fit_inside_the_committed_row() -> None:
    doc, rows = _recall_rows("triangle", range(2))
    n = doc["n_trials_per_shape"]
    for rule, (ok, tie) in _recall_counts(rows).items():
        right = np.rint(np.array(doc[rule]["fraction_correct"]["triangle"]) * n)
        ties = np.array(doc[rule]["ties"]["triangle"])
        k = len(rows)
        assert np.all(ok <= right) and np.all(k - ok <= n - right), rule
        assert np.all(tie <= ties) and np.all(k - tie <= n - ties), rule


@pytest.mark.slow
def test_recall_vs_s_triangle_row_equals_the_committed_row() -> None:
    doc, rows = _recall_rows("triangle", range(committed("recall-vs-s")["n_trials_per_shape"]))
    n = doc["n_trials_per_shape"]
    for rule, (ok, tie) in _recall_counts(rows).items():
        assert (ok / n).tolist() == doc[rule]["fraction_correct"]["triangle"], rule
        assert tie.tolist() == doc[rule]["ties"]["triangle"], rule


@pytest.mark.slow
@pytest.mark.parametrize(
    "name", ["fig9-readings", "contact-classes", "smart-sensor", "tacteme-table", "open-set"]
)
def test_experiment_reproduces_its_committed_json_whole(name: str, tmp_path: Path) -> None:
    from taxelkit.experiments.registry import EXPERIMENTS

    doc = reproduce(name, tmp_path, *(["--workers", "2"] if EXPERIMENTS[name].workers else []))
    diff = differences(doc, committed(name), {}, skip=SKIP)
    assert not diff, "\n".join(diff[:20])
