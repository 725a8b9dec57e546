"""A tiny ``trace-robustness``: the JSON's shape, the acceptance entries, determinism."""

from __future__ import annotations

import matplotlib.pyplot as plt
import pytest

from taxelkit.errors import InputError
from taxelkit.experiments.registry import EXPERIMENTS
from taxelkit.experiments.trace_robustness import (
    CONDITIONS,
    Condition,
    run_trace_robustness,
)
from taxelkit.plotting.experiments import plot_experiment

ROUGH = next(c for c in CONDITIONS if c.name == "200 um, noise 20 um")


def test_registered() -> None:
    assert EXPERIMENTS["trace-robustness"].workers and EXPERIMENTS["trace-robustness"].trials


def test_a_rough_triangle_is_traced_and_named_by_the_robust_tracer_only() -> None:
    result = run_trace_robustness(n_trials=1, conditions=(ROUGH,), shapes=("triangle",), workers=1)
    doc = result.to_json()
    robust, faithful = (doc["summary"][ROUGH.name][t] for t in ("robust", "faithful"))
    assert robust["n"] == 1 and robust["closed"] == 1 and robust["recognised"] == 1
    assert robust["error_mean_mm"] < 0.5
    assert faithful["closed"] == 0
    holds = doc["acceptance"]["holds"]
    assert holds["robust"][ROUGH.name] is True and holds["faithful"][ROUGH.name] is False
    assert holds["robust"]["tilt 0.5 deg"] is None  # not run here
    assert {t["tracer"] for t in doc["traces"]} == {"faithful", "robust"}
    # the figure: one bar per tracer in each panel; loops closed 0 (faithful) and 1 (robust)
    fig = plot_experiment("trace-robustness", result)
    error, closed, named = fig.axes[:3]
    labels = [t.get_text() for t in error.get_legend().get_texts()]
    widths = dict(zip(labels, [bar.get_width() for bar in closed.patches], strict=True))
    assert widths == {"faithful": 0.0, "robust": 1.0}
    assert [bar.get_width() for bar in named.patches][labels.index("robust")] == 1.0
    assert error.patches[labels.index("robust")].get_width() == robust["error_mean_mm"]
    plt.close(fig)


def test_same_seed_same_result() -> None:
    clean = (CONDITIONS[0],)
    runs = [
        run_trace_robustness(seed=3, n_trials=1, conditions=clean, shapes=("circle",), workers=1)
        for _ in range(2)
    ]
    assert runs[0].to_json() == runs[1].to_json()


def test_bad_arguments_are_refused() -> None:
    with pytest.raises(InputError, match="n_trials"):
        run_trace_robustness(n_trials=0)
    with pytest.raises(InputError, match="CONDITIONS"):
        run_trace_robustness(conditions=(Condition("mine", 30.0),))
