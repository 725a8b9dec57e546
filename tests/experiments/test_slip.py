"""The slip experiment: ground truth, scoring, a smoke run and its README block."""

from __future__ import annotations

import json

import matplotlib.pyplot as plt
import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.experiments.registry import get_experiment
from taxelkit.experiments.report import render_block
from taxelkit.experiments.slip import pitch_reached_s, run_slip, score_trial, slip_phases
from taxelkit.experiments.slip_result import SlipResult, SlipTrial
from taxelkit.motion.scenarios import make_scenario
from taxelkit.motion.slip_scenarios import make_partial_slip_scenario
from taxelkit.plotting.experiments import plot_experiment


def test_ground_truth_phases() -> None:
    assert slip_phases(make_scenario("cylinder", rng=1)) == []
    sc = make_partial_slip_scenario("cube", rng=1)
    ((a, b, kind),) = slip_phases(sc)
    assert kind == "area"
    assert sc.phase[a + 1] == "sliding" and sc.phase[a] != "sliding"  # the slide leaves frame a
    assert sc.phase[b - 1] == "sliding"


def test_a_phase_whose_contacts_tie_takes_the_first_seen() -> None:
    """Equal counts of two contacts: the first seen, in every process (not a set's order)."""

    class Tie:
        t_s = np.arange(12) * 0.1
        contact = ["none"] * 2 + ["line"] * 4 + ["area"] * 4 + ["none"] * 2
        phase = ["sliding"] * 12

        def slip_mm(self) -> np.ndarray:
            mm = np.zeros(11)
            mm[2:9] = 0.5  # 5 mm/s from frame 2 to frame 9
            return mm

    assert slip_phases(Tie()) == [(2, 9, "line")]  # type: ignore[arg-type]


def test_scoring_latency_and_false_alarms() -> None:
    t = np.arange(100) * 0.05
    phases = [(20, 40, "area"), (60, 70, "line")]
    found, fa = score_trial(t, phases, [19, 23, 50, 90])
    # 19 is 0.05 s early (allowed, latency 0); 23 belongs to the same phase and is not a
    # false alarm; the line is missed; 50 (0.5 s after the face's end) and 90 are false alarms
    assert found == [("area", 0.0), ("line", None)] and fa == 2
    found, fa = score_trial(t, phases, [24, 64])
    assert [round(x or 0.0, 6) for _, x in found] == [0.2, 0.2] and fa == 0


def test_smoke_run_and_readme_block() -> None:
    assert get_experiment("slip").trials == 30
    # two of the default rates (20, 100, 240 frames/s) keep the test short
    res = run_slip(seed=5, n_trials=1, engines=["kinematic"], rates_hz=[20.0, 100.0], workers=1)
    doc = res.to_json()
    assert len(res.trials) == 3 * 6 * 2 * 2  # kinds x objects x rates x imperfections
    assert res.imperfections == ("none", "all")
    assert set(doc["overall_imperfect"]) == {"all"}
    assert doc["overall_imperfect"]["all"]["20"]["sliding_identified"] == 0
    assert {s["kind"] for s in doc["summaries"]} == {"roll", "partial", "slide"}
    assert set(doc["overall"]) == {"20", "100"}
    for o in doc["overall"].values():
        assert o["sliding_identified"] == 0
        assert o["detectable"]["phases"] >= 5  # five partial slips of faces and lines, and slides
        bands = o["detectable_by_speed"]
        assert sum(b["phases"] for b in bands) == o["detectable"]["phases"]
        assert sum(b["in_time"] for b in bands) == o["detectable"]["in_time"]
    speeds = [p["speed_mm_s"] for t in doc["trials"] if t["kind"] == "slide" for p in t["phases"]]
    assert speeds and all(2.5 < v < 12.0 for v in speeds)  # the scripts slide at 3-6 mm/s
    block = render_block("slip", {"slip": doc})
    assert (
        "| kinematic | 20 | partial | 6 |" in block and "Acceptance (imperfection none):" in block
    )
    assert "| 20 frames/s | all |" in block and "with imperfection all:" in block
    assert "below 4 mm/s, 4-5 mm/s, from 5 mm/s" in block
    for o in doc["overall"].values():
        p = o["detectable_from_pitch"]
        assert p["phases"] + p["unresolvable"] == o["detectable"]["phases"]
    assert "in time from one pitch" in block
    # the figure draws these numbers: one latency curve per rate, the partial rolls' bars
    fig = plot_experiment("slip", res)
    left, right = fig.axes
    assert [t.get_text() for t in left.get_legend().get_texts()] == [
        "20 frames/s",
        "20 frames/s, all",
        "100 frames/s",
        "100 frames/s, all",
    ]
    for curve in left.get_lines()[:2]:
        y = np.asarray(curve.get_ydata())
        assert np.all(np.diff(y) >= 0) and 0.0 <= y[0] <= y[-1] <= 1.0  # a share found by then
    parts = [o["partial"] for o in doc["overall"].values()]
    bare = [o["partial_without_slip"] for o in doc["overall"].values()]
    want = [p["identified"] / sum(p.values()) for p in parts]
    want += [b["identified"] / sum(p.values()) for b, p in zip(bare, parts, strict=True)]
    assert [bar.get_height() for bar in right.patches] == pytest.approx(want)
    plt.close(fig)


def test_the_imperfect_view_leaves_the_trials_as_they_were() -> None:
    kw = {"seed": 4, "n_trials": 1, "engines": ["kinematic"], "workers": 1, "rates_hz": [20.0]}
    both = run_slip(**kw)
    clean = run_slip(**kw, imperfections=["none"])
    assert [t for t in both.trials if t.imperfection == "none"] == list(clean.trials)
    doc, doc_clean = both.to_json(), clean.to_json()
    for key in ("summaries", "overall", "acceptance"):  # NaN latencies: compared as JSON
        assert json.dumps(doc[key]) == json.dumps(doc_clean[key])
    seen = [t for t in both.trials if t.imperfection == "all"]
    assert [(t.kind, t.obj, t.rate_hz) for t in seen] == [
        (t.kind, t.obj, t.rate_hz) for t in clean.trials
    ]
    with pytest.raises(InputError, match="unknown imperfection"):
        run_slip(n_trials=1, imperfections=["rust"])
    with pytest.raises(InputError, match="rates_hz"):
        run_slip(n_trials=1, rates_hz=[2000.0])


def test_pitch_reached_by_a_dragged_face() -> None:
    """A face dragged at a constant speed has slid one pitch at pitch / speed."""
    sc = make_partial_slip_scenario("cube", rng=1)
    ((a, b, _),) = slip_phases(sc)
    t = np.asarray(sc.t_s)
    speed = float(np.nan_to_num(sc.slip_mm(), nan=0.0)[a:b].sum() / (t[b] - t[a]))
    (p,) = pitch_reached_s(sc, [(a, b, "area")], 1.7625)
    assert p is not None and abs(p - 1.7625 / speed) <= 0.051  # within a frame at 20 frames/s
    assert pitch_reached_s(sc, [(a, b, "area")], 100.0) == [None]  # never 100 mm


def test_in_time_from_one_pitch_counts_only_resolvable_phases() -> None:
    def trial(phases: tuple, pitch_s: tuple) -> SlipTrial:
        return SlipTrial(
            "kinematic", "slide", "cube", 20.0, 0, None, "slid", None, phases,
            (4.0,) * len(phases), 0, 1.0, pitch_s,
        )  # fmt: skip

    res = SlipResult(
        (
            trial((("area", 0.5), ("line", None)), (0.4, 0.3)),  # 0.1 s after a pitch: in time
            trial((("area", 0.7), ("area", 0.1)), (0.4, None)),  # 0.3 s late; never a pitch
        ),
        ("kinematic",), 1, 0, {},
    )  # fmt: skip
    p = res.to_json()["overall"]["20"]["detectable_from_pitch"]
    assert (p["phases"], p["detected"], p["in_time"]) == (3, 2, 1)
    assert (p["unresolvable"], p["unresolvable_detected"]) == (1, 1)


def test_the_held_out_run_and_its_readme_block() -> None:
    from pathlib import Path

    from taxelkit.experiments.slip_heldout import run_slip_heldout

    assert get_experiment("slip-heldout").trials == 30
    held = run_slip_heldout(n_trials=1, engines=["kinematic"], rates_hz=[20.0], workers=1)
    doc = held.to_json()
    assert doc["experiment"] == "slip-heldout"
    assert (doc["tuned_on_seed"], doc["held_out_seed"]) == (0, 11)
    direct = run_slip(seed=11, n_trials=1, engines=["kinematic"], rates_hz=[20.0], workers=1)
    assert doc["trials"] == direct.to_json()["trials"]  # the slip experiment on seed 11
    committed = Path(__file__).resolve().parents[2] / "docs" / "results" / "slip.json"
    tuned = json.loads(committed.read_text())
    block = render_block("slip-heldout", {"slip": tuned, "slip-heldout": doc})
    o = tuned["overall"]["20"]["detectable"]
    mine = doc["overall"]["20"]["detectable"]
    assert f"| 20 frames/s | none | {o['in_time']}/{o['phases']} (" in block
    assert f" / {mine['in_time']}/{mine['phases']} " in block or mine["phases"] == 0
    assert "| 20 frames/s | all |" in block and "Acceptance on seed 11" in block
    fig = plot_experiment("slip-heldout", held)
    assert len(fig.axes) == 2
    plt.close(fig)
