"""Experiment ``recall-vs-s``: recognition rate against traced fraction, random poses.

For each shape, ``n_trials`` specimens at a random rotation (0-360 deg),
translation (+-20 mm) and start point (the edge search leaves the centre in a
random direction) are traced and recalled against the reference memory at
``s = 0.2, 0.3, ..., 1.0`` with the paper's rule and the improved one. Trials
run in worker processes; each trial's seed comes from a
:class:`numpy.random.SeedSequence`, so results do not depend on the number of
workers.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.experiments.paper000_common import (
    FAITHFUL,
    IMPROVED,
    RecallSetup,
    reference_memory,
    trace_shape,
)
from taxelkit.experiments.work_units import map_in_order
from taxelkit.memory.contour_recall import recall_curve
from taxelkit.world.relief import SHAPE_NAMES

__all__ = ["RECALL_S_GRID", "RecallVsSResult", "run_recall_vs_s"]

#: Normalised arc lengths evaluated.
RECALL_S_GRID = (0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
#: Largest translation of a random specimen, mm.
MAX_OFFSET_MM = 20.0


@dataclass(frozen=True, eq=False)
class RecallVsSResult:
    """Fraction correctly recognised at each ``s``.

    Attributes
    ----------
    names : tuple of str
    s : tuple of float
    n_trials : int
        Trials per shape.
    correct : dict label -> (shapes, trials, S) bool
        The true shape alone top-ranked (a tie is never correct).
    tied : dict label -> (shapes, trials, S) bool
        Two or more stored shapes tied at the top: "undecided".
    margin : dict label -> (shapes, trials, S) float
        Best ``c`` minus the second best.
    closed : (shapes, trials) bool
        Whether each trace closed.
    """

    names: tuple[str, ...]
    s: tuple[float, ...]
    n_trials: int
    correct: dict[str, NDArray[np.bool_]]
    tied: dict[str, NDArray[np.bool_]]
    margin: dict[str, NDArray[np.float64]]
    closed: NDArray[np.bool_]

    def fraction(self, setup: RecallSetup) -> NDArray[np.float64]:
        """``(shapes, S)`` fraction correct."""
        out: NDArray[np.float64] = self.correct[setup.label].mean(axis=1)
        return out

    def to_json(self) -> dict[str, Any]:
        """Fractions per shape and s for both rules."""

        def table(setup: RecallSetup) -> dict[str, Any]:
            f = self.fraction(setup)
            ties = self.tied[setup.label].sum(axis=1)  # (shapes, S)
            margin = self.margin[setup.label]
            return {
                "rule": setup.label,
                "fraction_correct": {n: [float(v) for v in f[i]] for i, n in enumerate(self.names)},
                "ties": {n: [int(v) for v in ties[i]] for i, n in enumerate(self.names)},
                "ties_per_s": [int(v) for v in ties.sum(axis=0)],
                "mean_margin": {
                    n: [round(float(v), 6) for v in margin[i].mean(axis=0)]
                    for i, n in enumerate(self.names)
                },
            }

        return {
            "experiment": "recall-vs-s",
            "s": list(self.s),
            "n_trials_per_shape": self.n_trials,
            "improved": table(IMPROVED),
            "faithful": table(FAITHFUL),
            "closed_fraction": {n: float(self.closed[i].mean()) for i, n in enumerate(self.names)},
            "target": {"improved_at_s_ge_0.5": 0.95},
        }


def _trial(
    args: tuple[int, int, np.random.SeedSequence],
) -> tuple[int, int, list[tuple[list[bool], list[bool], list[float]]], bool]:
    shape_idx, trial, seq = args
    rng = np.random.default_rng(seq)
    name = SHAPE_NAMES[shape_idx]
    angle = float(rng.uniform(0.0, 360.0))
    offset = rng.uniform(-MAX_OFFSET_MM, MAX_OFFSET_MM, 2)
    direction = rng.normal(size=2)
    tr = trace_shape(
        name, rotation_deg=angle, offset_mm=offset, start_direction=direction, seed=rng
    )
    rows = []
    for setup in (FAITHFUL, IMPROVED):
        curve = recall_curve(
            tr.moves_mm, reference_memory(setup), s=RECALL_S_GRID, phases=setup.phases
        )
        rows.append(
            (
                [r == name for r in curve.recognised],
                [r is None for r in curve.recognised],
                [float(v) for v in curve.margin],
            )
        )
    return shape_idx, trial, rows, tr.closed


def run_recall_vs_s(
    *,
    seed: int = 0,
    n_trials: int = 50,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> RecallVsSResult:
    """Run the random-pose recognition trials.

    Parameters
    ----------
    seed : int
        Root seed.
    n_trials : int
        Trials per shape (the issue asks for at least 50).
    workers : int, optional
        Worker processes (default: all cores, at most 4; 1 runs in-process).
    progress : callable, optional
        ``progress(done, total)``.
    """
    n_shapes = len(SHAPE_NAMES)
    seqs = np.random.SeedSequence(seed).spawn(n_shapes * n_trials)
    jobs = [(i, t, seqs[i * n_trials + t]) for i in range(n_shapes) for t in range(n_trials)]
    shape = (n_shapes, n_trials, len(RECALL_S_GRID))
    setups = (FAITHFUL, IMPROVED)
    correct = {s.label: np.zeros(shape, bool) for s in setups}
    tied = {s.label: np.zeros(shape, bool) for s in setups}
    margin = {s.label: np.zeros(shape) for s in setups}
    closed = np.zeros((n_shapes, n_trials), bool)
    n_workers = min(4, os.cpu_count() or 1) if workers is None else max(1, int(workers))

    for i, t, rows, was_closed in map_in_order(
        _trial, jobs, workers=n_workers, chunksize=4, progress=progress
    ):
        for setup, (ok, tie, gap) in zip(setups, rows, strict=True):
            correct[setup.label][i, t] = ok
            tied[setup.label][i, t] = tie
            margin[setup.label][i, t] = gap
        closed[i, t] = was_closed
    return RecallVsSResult(
        tuple(SHAPE_NAMES), RECALL_S_GRID, n_trials, correct, tied, margin, closed
    )
