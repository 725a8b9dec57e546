"""Open-set recognition: calibrated probabilities, "unknown", "undecided", decided_at_s."""

from __future__ import annotations

import doctest
import math

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.memory import AssociativeMemory, ChainCodeConfig, open_set
from taxelkit.memory.calibration import (
    expected_calibration_error,
    fit_temperature,
    probabilities_from_scores,
)
from taxelkit.memory.open_set import (
    OpenSetCalibration,
    compactness_from_points,
    decided_at_s,
    fit_open_set,
    open_set_from_recall,
)


def test_docstring_examples() -> None:
    assert doctest.testmod(open_set).failed == 0


def test_probabilities_are_a_softmax_that_ignores_order() -> None:
    c = np.array([[0.9, 0.5, 0.7], [0.2, 0.2, 0.2]])
    p = probabilities_from_scores(c, 0.1)
    np.testing.assert_allclose(p.sum(axis=1), 1.0)
    np.testing.assert_allclose(p[0], np.exp(c[0] / 0.1) / np.exp(c[0] / 0.1).sum())
    np.testing.assert_allclose(p[1], 1 / 3)
    np.testing.assert_allclose(probabilities_from_scores(c[:, ::-1], 0.1), p[:, ::-1])
    with pytest.raises(InputError, match="temperature"):
        probabilities_from_scores(c, 0.0)


def test_fit_temperature_recovers_the_generating_temperature() -> None:
    rng = np.random.default_rng(0)
    scores = rng.uniform(0.0, 1.0, size=(4000, 5))
    true_t = 0.1
    p = probabilities_from_scores(scores, true_t)
    labels = np.array([rng.choice(5, p=row) for row in p])
    assert fit_temperature(scores, labels) == pytest.approx(true_t, rel=0.15)


def test_compactness_closed_forms_and_invariance() -> None:
    square = [(0, 0), (2, 0), (2, 2), (0, 2)]
    assert compactness_from_points(square) == pytest.approx(math.pi / 4)
    t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    assert compactness_from_points(np.column_stack([np.cos(t), np.sin(t)])) == pytest.approx(
        1.0, abs=1e-5
    )
    triangle = [(0, 0), (1, 0), (0.5, math.sqrt(3) / 2)]
    assert compactness_from_points(triangle) == pytest.approx(math.pi / (3 * math.sqrt(3)))
    a = 0.7
    rot = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
    turned = np.asarray(square, float) @ rot.T * 3 + 5
    assert compactness_from_points(turned) == pytest.approx(math.pi / 4)
    assert compactness_from_points([(0, 0), (1, 1)]) == 0.0


def test_ece_is_zero_when_confidence_equals_accuracy() -> None:
    conf = np.repeat([0.55, 0.85], 20)
    correct = np.concatenate([np.arange(20) < 11, np.arange(20) < 17])
    ece, _, _, counts = expected_calibration_error(conf, correct)
    assert ece == pytest.approx(0.0, abs=1e-12)
    assert counts.sum() == 40 and counts[5] == 20 and counts[8] == 20
    over, *_ = expected_calibration_error(np.full(10, 0.95), np.zeros(10, bool))
    assert over == pytest.approx(0.95)


def test_decided_at_s_is_the_start_of_the_final_run() -> None:
    s = [0.2, 0.4, 0.6, 0.8, 1.0]
    assert decided_at_s(s, ["undecided", "star", "star", "star", "star"]) == 0.4
    assert decided_at_s(s, ["star", "circle", "star", "star", "star"]) == 0.6
    assert decided_at_s(s, ["star", "star", "star", "star", "unknown"]) is None
    assert decided_at_s(s, ["star"] * 4 + ["undecided"]) is None


def _memory() -> AssociativeMemory:
    cfg = ChainCodeConfig(m=4, l=2, thresholds=(0.2, 0.4))
    x = np.array([[1, 1, -1, -1, 1, -1, -1, -1], [1, -1, 1, -1, -1, -1, -1, -1]], np.int8)
    return AssociativeMemory(("a", "b"), x, cfg, "matched")


def test_unknown_undecided_and_decided() -> None:
    mem = _memory()
    cal = OpenSetCalibration(
        temperature=0.05,
        min_top_score=0.9,
        reference_compactness=(("a", 0.8), ("b", 0.6)),
        compactness_tolerance=0.1,
    )
    queries = np.array(
        [
            mem.patterns[0],  # "a" exactly
            mem.patterns[0],  # "a", but its closed trace is far too round
            [1, 0, 0, 0, 0, 0, 0, 0],  # little evidence
            [1, 0, 0, 0, 0, 0, 0, 0],  # the same, still running
        ]
    )
    result = open_set_from_recall(
        mem.recall(queries),
        cal,
        compactness=[0.78, 1.0, np.nan, np.nan],
        closed=[True, True, True, False],
    )
    assert result.verdicts == ("a", "unknown", "unknown", "undecided")
    assert result.unknown_reasons == ("", "compactness", "score", "")
    assert result.recognised == ("a", None, None, None)
    np.testing.assert_allclose(result.probabilities.sum(axis=1), 1.0)
    assert result.probabilities[0, 0] > 0.99


def test_fit_open_set_learns_limits_from_held_out_traces() -> None:
    scores = np.array([[0.95, 0.6], [0.7, 0.9], [0.99, 0.5], [0.6, 0.97]])
    cal = fit_open_set(
        ["a", "b"],
        scores,
        [0, 1, 0, 1],
        full_top_scores=[0.95, 0.9, 0.99],
        reference_compactness={"a": 0.8, "b": 0.6},
        held_out_compactness=[0.82, 0.57],
        held_out_labels=[0, 1],
    )
    assert cal.min_top_score == pytest.approx(0.9 - open_set.REJECTION_SLACK)
    expected = open_set.COMPACTNESS_TOLERANCE_FACTOR * abs(math.log(0.57 / 0.6))
    assert cal.compactness_tolerance == pytest.approx(expected)
    assert dict(cal.reference_compactness) == {"a": 0.8, "b": 0.6}
    assert 0 < cal.temperature <= 1
