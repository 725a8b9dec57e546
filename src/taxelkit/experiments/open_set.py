"""Experiment ``open-set``: "unknown" for shapes outside the memory, calibrated confidence.

The memory holds the five paper shapes (reference traces, improved rule).
Three disjoint sets of traces, each from its own
:class:`numpy.random.SeedSequence` child, all traced by the real tracer at a
random rotation, translation, start point, size (circumscribed diameter
:data:`DIAMETER_RANGE_MM`) and step height (:data:`STEP_RANGE_UM`):

* held-out in-set traces (``n_calibration`` per stored shape) fit the
  temperature and the rejection limits (:func:`~taxelkit.memory.open_set.fit_open_set`);
* evaluation in-set traces (``n_trials`` per stored shape) measure recognition,
  the reliability diagram and the expected calibration error (ECE), at every
  ``s`` of :data:`OPEN_SET_S_GRID`;
* out-of-set traces (``n_trials // 2`` per kind of
  :data:`~taxelkit.world.open_set_shapes.OUT_OF_SET_SHAPES`) measure how often
  a shape the memory does not hold is answered "unknown".

The codes of partial traces are Eq. 13 of the part traced so far (no 0 =
unknown elements), so nothing uses the contour's total length; ``s`` only
says, after the fact, how far the trace had gone. While the trace runs (``s <
1``) nothing is "unknown": too little evidence is "undecided"; the rejection
tests apply once the loop has closed (a trace that never closes is judged on
its probabilities only).
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.experiments.paper000_common import IMPROVED, reference_memory, reference_traces
from taxelkit.experiments.work_units import map_in_order
from taxelkit.memory.associatron import AssociativeMemory
from taxelkit.memory.calibration import expected_calibration_error
from taxelkit.memory.contour_recall import prefix_codes
from taxelkit.memory.open_set import (
    OpenSetCalibration,
    OpenSetResult,
    compactness_from_points,
    decided_at_s,
    fit_open_set,
    open_set_from_recall,
)
from taxelkit.motion.probe import SimulatedProbe
from taxelkit.tracing.tracer import Trace, find_edge, trace_edge
from taxelkit.world.open_set_shapes import OUT_OF_SET_SHAPES, open_set_relief
from taxelkit.world.relief import SHAPE_NAMES, relief_shape

__all__ = [
    "OPEN_SET_S_GRID",
    "REFERENCE_CALIBRATION",
    "OpenSetExperimentResult",
    "judge_trace",
    "run_open_set",
]

#: Traced fractions evaluated (after the fact).
OPEN_SET_S_GRID = (0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
#: Circumscribed diameters of the specimens, mm (90 mm -30 % / +40 %).
DIAMETER_RANGE_MM = (63.0, 126.0)
#: Step heights of the specimens, um.
STEP_RANGE_UM = (100.0, 200.0)
#: Largest translation of a specimen, mm.
MAX_OFFSET_MM = 20.0
#: Bins of the reliability diagram.
RELIABILITY_BINS = 10

#: The calibration of the built-in memory (improved rule) fitted by
#: ``taxelkit reproduce open-set`` with seed 0 (``docs/results/open-set.json``,
#: key ``calibration``; a test checks that the two agree). Used by
#: ``taxelkit trace --json`` so that a single trace needs no refit.
REFERENCE_CALIBRATION = OpenSetCalibration(
    temperature=0.023442288153199226,
    min_top_score=0.896667,
    reference_compactness=(
        ("circle", 0.997376),
        ("square", 0.794318),
        ("triangle", 0.604481),
        ("star", 0.282019),
        ("hexagon", 0.917355),
    ),
    compactness_tolerance=0.073084,
)

_Job = tuple[str, int, bool, np.random.SeedSequence]
_Row = tuple[str, int, bool, NDArray[np.int8], float, bool]


def _trace_job(job: _Job) -> _Row:
    """Trace one random specimen; return its prefix codes and compactness."""
    name, index, in_set, seq = job
    rng = np.random.default_rng(seq)
    angle = float(rng.uniform(0.0, 360.0))
    offset = rng.uniform(-MAX_OFFSET_MM, MAX_OFFSET_MM, 2)
    diameter = float(rng.uniform(*DIAMETER_RANGE_MM))
    step = float(rng.uniform(*STEP_RANGE_UM))
    where = (float(offset[0]), float(offset[1]))
    if in_set:
        relief: Any = relief_shape(
            name, diameter_mm=diameter, step_height_um=step, rotation_deg=angle, offset_mm=where
        )
    else:
        relief = open_set_relief(
            name, diameter_mm=diameter, step_height_um=step, rotation_deg=angle, offset_mm=where
        )
    probe = SimulatedProbe(relief, rng=rng)
    start = find_edge(probe, offset, direction=rng.normal(size=2))
    tr = trace_edge(probe, start)
    codes = prefix_codes(
        tr.moves_mm,
        reference_memory(IMPROVED),
        s=OPEN_SET_S_GRID,
        unknown_for_partial=False,
        phases=IMPROVED.phases,
    )
    q = compactness_from_points(tr.points_mm) if tr.closed else float("nan")
    return name, index, in_set, codes, q, tr.closed


@dataclass(frozen=True, eq=False)
class OpenSetExperimentResult:
    """Calibration and verdicts of the three trace sets.

    Attributes
    ----------
    calibration : OpenSetCalibration
        Fitted on the held-out in-set traces.
    s : tuple of float
    in_set : list of (name, verdicts per s, top probability per s, credit per s)
        The credit is 1 when the true shape alone has the top probability,
        ``1 / n`` when it shares it with ``n - 1`` others, else 0.
    out_of_set : list of (kind, verdicts per s)
    n_calibration, n_trials : int
    reasons : tuple of (set, name, reason)
        Why each full trace judged "unknown" was rejected (set ``"in"`` or
        ``"out"``, reason ``"score"`` or ``"compactness"``).
    """

    calibration: OpenSetCalibration
    s: tuple[float, ...]
    in_set: list[tuple[str, tuple[str, ...], NDArray[np.float64], NDArray[np.float64]]]
    out_of_set: list[tuple[str, tuple[str, ...]]]
    n_calibration: int
    n_trials: int
    reasons: tuple[tuple[str, str, str], ...] = ()

    def reliability(self) -> tuple[float, list[dict[str, Any]]]:
        """ECE over the evaluation in-set traces at every ``s``, and the diagram's bins."""
        conf = np.concatenate([p for _, _, p, _ in self.in_set])
        ok = np.concatenate([c for _, _, _, c in self.in_set])
        ece, acc, mean_conf, counts = expected_calibration_error(conf, ok, n_bins=RELIABILITY_BINS)
        bins = [
            {
                "low": k / RELIABILITY_BINS,
                "high": (k + 1) / RELIABILITY_BINS,
                "n": int(counts[k]),
                "accuracy": None if counts[k] == 0 else round(float(acc[k]), 4),
                "confidence": None if counts[k] == 0 else round(float(mean_conf[k]), 4),
            }
            for k in range(RELIABILITY_BINS)
        ]
        return ece, bins

    def to_json(self) -> dict[str, Any]:
        """Rates at full contour, per kind, per s; the reliability diagram; the calibration."""
        names = sorted({n for n, *_ in self.in_set}, key=SHAPE_NAMES.index)
        full_in = [v[-1] for _, v, _, _ in self.in_set]
        truth = [n for n, *_ in self.in_set]
        pairs = list(zip(full_in, truth, strict=True))
        right = sum(v == n for v, n in pairs)
        wrong = sum(v not in (n, "unknown", "undecided") for v, n in pairs)
        out_full = [v[-1] for _, v in self.out_of_set]
        kinds = list(dict.fromkeys(k for k, _ in self.out_of_set))
        ece, bins = self.reliability()
        decided = {
            n: [decided_at_s(self.s, v) for m, v, _, _ in self.in_set if m == n] for n in names
        }
        cal = self.calibration
        return {
            "experiment": "open-set",
            "rule": IMPROVED.label,
            "s": list(self.s),
            "n_calibration_per_shape": self.n_calibration,
            "n_trials_per_shape": self.n_trials,
            "calibration": {
                "temperature": cal.temperature,
                "min_top_score": round(cal.min_top_score, 6),
                "compactness_tolerance": round(cal.compactness_tolerance, 6),
                "reference_compactness": {n: round(q, 6) for n, q in cal.reference_compactness},
                "decide_probability": cal.decide_probability,
            },
            "in_set": {
                "n": len(full_in),
                "recognised": right / len(full_in),
                "wrong_names": wrong,
                "unknown": sum(v == "unknown" for v in full_in),
                "undecided": sum(v == "undecided" for v in full_in),
                "per_shape": {
                    n: _counts([v[-1] for m, v, _, _ in self.in_set if m == n]) for n in names
                },
                "recognised_per_s": [
                    float(np.mean([v[j] == n for n, v, _, _ in self.in_set]))
                    for j in range(len(self.s))
                ],
                "decided_at_s": decided,
            },
            "out_of_set": {
                "kinds": kinds,
                "n": len(out_full),
                "unknown_rate": sum(v == "unknown" for v in out_full) / len(out_full),
                "per_kind": {
                    k: _counts([v[-1] for m, v in self.out_of_set if m == k]) for k in kinds
                },
            },
            "unknown_reasons": {
                split: _counts([why for sp, _, why in self.reasons if sp == split])
                for split in ("in", "out")
            },
            "reliability": {"ece": round(ece, 6), "bins": bins},
            "targets": {"unknown_rate": 0.95, "recognised": 0.95, "wrong_names": 0, "ece": 0.05},
        }


def judge_trace(
    trace: Trace,
    memory: AssociativeMemory,
    calibration: OpenSetCalibration,
    *,
    phases: int,
    s: tuple[float, ...] = OPEN_SET_S_GRID,
) -> tuple[OpenSetResult, float | None]:
    """Open-set verdicts of one trace at every ``s``, and ``decided_at_s``.

    The codes are those of the part traced so far (no total length); the
    rejection tests apply to the closed trace only (``s = 1``).

    Parameters
    ----------
    trace : Trace
    memory : AssociativeMemory
    calibration : OpenSetCalibration
    phases : int
        Sector phases of the memory's code.
    s : tuple of float
        Traced fractions, the last 1.0.

    Returns
    -------
    (OpenSetResult, float or None)
        Rows follow ``s``; the smallest ``s`` from which the verdict stayed
        one named shape (None if the final verdict is not a name).
    """
    codes = prefix_codes(trace.moves_mm, memory, s=s, unknown_for_partial=False, phases=phases)
    ended = np.asarray(s) >= 1.0
    q = compactness_from_points(trace.points_mm) if trace.closed else float("nan")
    verdict = open_set_from_recall(
        memory.recall(codes),
        calibration,
        compactness=np.where(ended, q, np.nan),
        closed=ended & trace.closed,
    )
    return verdict, decided_at_s(s, verdict.verdicts)


def _counts(verdicts: list[str]) -> dict[str, int]:
    out: dict[str, int] = {}
    for v in verdicts:
        out[v] = out.get(v, 0) + 1
    return dict(sorted(out.items()))


def run_open_set(
    *,
    seed: int = 0,
    n_trials: int = 20,
    n_calibration: int = 12,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> OpenSetExperimentResult:
    """Trace the three sets, fit the calibration, and judge every trace.

    Parameters
    ----------
    seed : int
        Root seed; the three sets use separate children of it.
    n_trials : int
        Evaluation traces per stored shape; ``max(1, n_trials // 2)`` per
        out-of-set kind.
    n_calibration : int
        Held-out traces per stored shape.
    workers : int, optional
        Worker processes (default: all cores, at most 4; 1 runs in-process).
    progress : callable, optional
        ``progress(done, total)`` over traces.
    """
    cal_seq, eval_seq, out_seq = np.random.SeedSequence(seed).spawn(3)
    n_out = max(1, n_trials // 2)
    jobs: list[tuple[str, _Job]] = []
    for split, seq, kinds, n, member in (
        ("cal", cal_seq, SHAPE_NAMES, n_calibration, True),
        ("eval", eval_seq, SHAPE_NAMES, n_trials, True),
        ("out", out_seq, OUT_OF_SET_SHAPES, n_out, False),
    ):
        children = seq.spawn(len(kinds) * n)
        jobs += [
            (split, (k, i, member, children[j * n + i]))
            for j, k in enumerate(kinds)
            for i in range(n)
        ]
    n_workers = min(4, os.cpu_count() or 1) if workers is None else max(1, int(workers))
    rows = map_in_order(
        _trace_job, [j for _, j in jobs], workers=n_workers, chunksize=2, progress=progress
    )
    splits = [split for split, _ in jobs]
    memory = reference_memory(IMPROVED)
    names = memory.names
    cal = [r for r, sp in zip(rows, splits, strict=True) if sp == "cal"]
    cal_recalls = [memory.recall(r[3]) for r in cal]
    labels = np.concatenate([np.full(len(OPEN_SET_S_GRID), names.index(r[0])) for r in cal])
    closed = [(r, rec) for r, rec in zip(cal, cal_recalls, strict=True) if r[5]]
    ref_q = {
        n: compactness_from_points(t.points_mm)
        for n, t in zip(SHAPE_NAMES, reference_traces(), strict=True)
    }
    calibration = fit_open_set(
        names,
        np.vstack([rec.correlations for rec in cal_recalls]),
        labels,
        full_top_scores=[rec.correlations[-1].max() for rec in cal_recalls],
        reference_compactness=ref_q,
        held_out_compactness=[r[4] for r, _ in closed],
        held_out_labels=[names.index(r[0]) for r, _ in closed],
    )
    in_set: list[tuple[str, tuple[str, ...], NDArray[np.float64], NDArray[np.float64]]] = []
    out_of_set: list[tuple[str, tuple[str, ...]]] = []
    reasons: list[tuple[str, str, str]] = []
    for r, sp in zip(rows, splits, strict=True):
        if sp == "cal":
            continue
        recall = memory.recall(r[3])
        # Only the closed trace (s = 1) is complete: before it, low evidence is "undecided".
        ended = np.asarray(OPEN_SET_S_GRID) >= 1.0
        qc = np.where(ended, r[4], np.nan)
        verdict = open_set_from_recall(recall, calibration, compactness=qc, closed=ended & r[5])
        if verdict.unknown[-1]:
            reasons.append(("in" if sp == "eval" else "out", r[0], verdict.unknown_reasons[-1]))
        if sp == "eval":
            p = verdict.probabilities
            at_top = p >= p.max(axis=1, keepdims=True) - 1e-12  # (S, K): ties share the credit
            credit = at_top[:, names.index(r[0])] / at_top.sum(axis=1)
            in_set.append((r[0], verdict.verdicts, p.max(axis=1), credit))
        else:
            out_of_set.append((r[0], verdict.verdicts))
    return OpenSetExperimentResult(
        calibration, OPEN_SET_S_GRID, in_set, out_of_set, n_calibration, n_trials, tuple(reasons)
    )
