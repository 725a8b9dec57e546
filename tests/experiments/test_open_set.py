"""The open-set experiment: the committed calibration, a tiny run, the CLI fields."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from taxelkit.experiments import open_set as os_exp
from taxelkit.experiments.open_set import REFERENCE_CALIBRATION, judge_trace
from taxelkit.experiments.paper000_common import IMPROVED, reference_memory, trace_shape

ROOT = Path(__file__).resolve().parents[2]


def test_reference_calibration_is_the_committed_fit() -> None:
    doc = json.loads((ROOT / "docs" / "results" / "open-set.json").read_text(encoding="utf-8"))
    cal = doc["calibration"]
    ref = REFERENCE_CALIBRATION
    assert ref.temperature == pytest.approx(cal["temperature"], abs=1e-9)
    assert ref.min_top_score == pytest.approx(cal["min_top_score"], abs=1e-6)
    assert ref.compactness_tolerance == pytest.approx(cal["compactness_tolerance"], abs=1e-6)
    assert dict(ref.reference_compactness) == pytest.approx(cal["reference_compactness"])
    assert ref.decide_probability == cal["decide_probability"]


def test_judge_trace_names_a_traced_square_and_says_when() -> None:
    tr = trace_shape("square", rotation_deg=17.0, seed=3)
    verdict, decided = judge_trace(
        tr, reference_memory(IMPROVED), REFERENCE_CALIBRATION, phases=IMPROVED.phases
    )
    assert verdict.verdicts[-1] == "square"
    assert not verdict.unknown[-1]
    assert verdict.probabilities[-1].max() > 0.9
    assert decided is not None and 0.2 <= decided <= 1.0
    assert all(v != "unknown" for v in verdict.verdicts[:-1])  # running traces are never unknown


def test_a_trace_job_is_deterministic() -> None:
    seq = np.random.SeedSequence(5)
    a = os_exp._trace_job(("l-shape", 0, False, seq))
    b = os_exp._trace_job(("l-shape", 0, False, seq))
    assert a[0] == "l-shape" and a[3].shape == (len(os_exp.OPEN_SET_S_GRID), 192)
    np.testing.assert_array_equal(a[3], b[3])
    assert a[4] == b[4] and a[5] == b[5]


def test_to_json_counts_verdicts_and_reliability() -> None:
    s = os_exp.OPEN_SET_S_GRID
    n = len(s)
    good = ("undecided",) * (n - 1) + ("star",)
    bad = ("undecided",) * (n - 1) + ("unknown",)
    result = os_exp.OpenSetExperimentResult(
        REFERENCE_CALIBRATION,
        s,
        [
            ("star", good, np.full(n, 0.95), np.ones(n)),
            ("circle", bad, np.full(n, 0.5), np.zeros(n)),
        ],
        [("cross", bad), ("pentagon", good)],
        n_calibration=1,
        n_trials=1,
    )
    doc = result.to_json()
    assert doc["in_set"]["recognised"] == 0.5 and doc["in_set"]["unknown"] == 1
    assert doc["in_set"]["wrong_names"] == 0
    assert doc["in_set"]["decided_at_s"] == {"circle": [None], "star": [1.0]}
    assert doc["out_of_set"]["unknown_rate"] == 0.5
    assert doc["out_of_set"]["per_kind"] == {"cross": {"unknown": 1}, "pentagon": {"star": 1}}
    assert doc["reliability"]["ece"] == pytest.approx(0.5 * 0.05 + 0.5 * 0.5)
