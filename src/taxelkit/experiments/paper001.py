"""Paper 001 experiments: ``cylinder`` (Fig. 3 / Table 2), ``smart-sensor`` and ``tacteme-table``.

The scenarios (the world) come from :mod:`taxelkit.motion.scenarios`; the
recogniser sees only the simulated frames. The scenario's ground truth (the
object's name) is used only to score the outcome.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.experiments.work_units import map_in_order
from taxelkit.frames import TactileFrames
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import cylinder_fig3_scenario, make_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart.recogniser import Recognition, recognise
from taxelkit.smart.tacteme_table import OBJECTS, TABLE
from taxelkit.smart.tactemes import PAPER_LEVEL3

__all__ = [
    "CylinderResult",
    "SmartSensorResult",
    "TactemeTableResult",
    "run_cylinder",
    "run_smart_sensor",
    "run_tacteme_table",
]

#: Outcome labels of a trial besides the object names.
UNDECIDED = "undecided"
UNKNOWN = "unknown"
OUTCOMES: tuple[str, ...] = (*OBJECTS, UNKNOWN, UNDECIDED)
#: Paper 001's figure: 3 tests x 6 objects, 83 % recognised.
PAPER_ACCURACY = 0.83


@dataclass(frozen=True, eq=False)
class CylinderResult:
    """The paper's Fig. 3 sequence on the simulated sensor.

    ``recognition`` is paper 001's pipeline as printed (no cleaning, no
    Level 2 limits, Level 3 in frames, k = 3); ``robust`` is the default
    pipeline on the same frames.
    """

    recording: TactileFrames
    recognition: Recognition
    robust: Recognition

    def to_json(self) -> dict[str, Any]:
        """``classes`` per frame, ``tactemes``, ``identified``."""
        r = self.recognition
        return {
            "experiment": "cylinder",
            "classes": r.class_names(),
            "tactemes": [{"name": n, "frame": f} for n, f in r.tactemes],
            "identified": r.identified,
            "candidates": list(r.candidates),
            "paper": {"tactemes": ["AC", "PC", "LC", "LCMP"], "identified": "cylinder"},
            "pipeline": "faithful (paper 001 as printed)",
            "robust": {
                "tactemes": [{"name": n, "frame": f} for n, f in self.robust.tactemes],
                "identified": self.robust.identified,
            },
        }


def run_cylinder(
    *, seed: int = 0, progress: Callable[[int, int], None] | None = None
) -> CylinderResult:
    """Simulate the cylinder of Fig. 3 (end, rim, side, roll) and recognise it."""
    scenario = cylinder_fig3_scenario()
    rec = frames_from_scenario(BONNEVILLE_16X16, scenario, rng=seed)
    contact = TactileFrames(
        BONNEVILLE_16X16.contact_from_displacement(rec.frames),
        rec.t_s,
        rec.pitch_mm,
        sensor=rec.sensor,
    )
    faithful = recognise(contact, cleaning=None, limits=None, config=PAPER_LEVEL3)
    robust = recognise(contact)
    if progress is not None:
        progress(1, 1)
    return CylinderResult(contact, faithful, robust)


def _trial(args: tuple[str, np.random.SeedSequence]) -> tuple[str, str, int | None, list[str]]:
    name, seq = args
    rng = np.random.default_rng(seq)
    scenario = make_scenario(name, rng=rng)
    rec = frames_from_scenario(BONNEVILLE_16X16, scenario, rng=rng)
    result = recognise(rec)
    outcome = result.identified or UNDECIDED
    frame = next((e.frame for e in result.events if e.kind == "identified"), None)
    return name, outcome, frame, sorted({t for t, _ in result.tactemes})


def _run_trials(
    names: list[str], seed: int, workers: int | None, progress: Callable[[int, int], None] | None
) -> list[tuple[str, str, int | None, list[str]]]:
    seqs = np.random.SeedSequence(seed).spawn(len(names))
    jobs = list(zip(names, seqs, strict=True))
    n_workers = min(4, os.cpu_count() or 1) if workers is None else max(1, int(workers))
    return map_in_order(_trial, jobs, workers=n_workers, chunksize=8, progress=progress)


@dataclass(frozen=True, eq=False)
class SmartSensorResult:
    """Randomised trials of every object, plus sliding trials.

    Attributes
    ----------
    confusion : (6, 8) int
        Rows: objects; columns: :data:`OUTCOMES` (objects, unknown, undecided).
    sliding_outcomes : dict outcome -> count
    frames_to_identify : dict object -> median frame of identification (correct trials)
    n_trials : int
        Trials per object.
    """

    confusion: NDArray[np.int64]
    sliding_outcomes: dict[str, int]
    frames_to_identify: dict[str, float | None]
    n_trials: int

    def to_json(self) -> dict[str, Any]:
        """Accuracy, wrong, confusion, frames to identify and sliding trials identified."""
        correct = int(np.trace(self.confusion[:, : len(OBJECTS)]))
        total = int(self.confusion.sum())
        wrong = int(self.confusion[:, : len(OBJECTS)].sum()) - correct
        return {
            "experiment": "smart-sensor",
            "n_trials_per_object": self.n_trials,
            "member_trials": total,
            "accuracy": correct / total if total else None,
            "wrong": wrong,
            "unknown": int(self.confusion[:, len(OBJECTS)].sum()),
            "undecided": int(self.confusion[:, len(OBJECTS) + 1].sum()),
            "confusion": {
                obj: {out: int(self.confusion[i, j]) for j, out in enumerate(OUTCOMES)}
                for i, obj in enumerate(OBJECTS)
            },
            "frames_to_identify": self.frames_to_identify,
            "sliding_trials": int(sum(self.sliding_outcomes.values())),
            "sliding_identified": int(
                sum(v for k, v in self.sliding_outcomes.items() if k in OBJECTS)
            ),
            "sliding_outcomes": self.sliding_outcomes,
            "paper_accuracy": PAPER_ACCURACY,
        }


def run_smart_sensor(
    *,
    seed: int = 0,
    n_trials: int = 100,
    n_sliding: int = 100,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> SmartSensorResult:
    """``n_trials`` randomised scenarios per object (sizes +-30 %, noise on) and sliding trials."""
    names = [o for o in OBJECTS for _ in range(n_trials)] + ["sliding"] * n_sliding
    results = _run_trials(names, seed, workers, progress)
    confusion = np.zeros((len(OBJECTS), len(OUTCOMES)), dtype=np.int64)
    sliding: dict[str, int] = {}
    frames: dict[str, list[int]] = {o: [] for o in OBJECTS}
    for name, outcome, frame, _ in results:
        if name == "sliding":
            sliding[outcome] = sliding.get(outcome, 0) + 1
            continue
        confusion[OBJECTS.index(name), OUTCOMES.index(outcome)] += 1
        if outcome == name and frame is not None:
            frames[name].append(frame)
    median = {o: (float(np.median(v)) if v else None) for o, v in frames.items()}
    return SmartSensorResult(confusion, sliding, median, n_trials)


@dataclass(frozen=True, eq=False)
class TactemeTableResult:
    """Which tactemes each simulated object produced, beside the table.

    Attributes
    ----------
    counts : (n_tactemes, 6) int
        Trials of each object in which each tacteme appeared.
    n_trials : int
    """

    counts: NDArray[np.int64]
    n_trials: int

    def violations(self) -> list[dict[str, Any]]:
        """Tactemes produced by an object that the table says the object cannot produce."""
        out = []
        for i, row in enumerate(TABLE):
            for j, obj in enumerate(OBJECTS):
                if obj in row.eliminates and self.counts[i, j] > 0:
                    out.append(
                        {
                            "tacteme": row.tacteme.value,
                            "object": obj,
                            "trials": int(self.counts[i, j]),
                        }
                    )
        return out

    def to_json(self) -> dict[str, Any]:
        """Produced tactemes per object, the table's eliminations, and violations."""
        return {
            "experiment": "tacteme-table",
            "n_trials_per_object": self.n_trials,
            "produced": {
                obj: {row.tacteme.value: int(self.counts[i, j]) for i, row in enumerate(TABLE)}
                for j, obj in enumerate(OBJECTS)
            },
            "table": [
                {"tacteme": r.tacteme.value, "eliminates": sorted(r.eliminates), "reason": r.reason}
                for r in TABLE
            ],
            "violations": self.violations(),
        }


def run_tacteme_table(
    *,
    seed: int = 0,
    n_trials: int = 50,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> TactemeTableResult:
    """Run ``n_trials`` randomised scenarios per object and count the tactemes produced."""
    names = [o for o in OBJECTS for _ in range(n_trials)]
    results = _run_trials(names, seed, workers, progress)
    index = {row.tacteme.value: i for i, row in enumerate(TABLE)}
    counts = np.zeros((len(TABLE), len(OBJECTS)), dtype=np.int64)
    for name, _, _, tactemes in results:
        for t in tactemes:
            counts[index[t], OBJECTS.index(name)] += 1
    return TactemeTableResult(counts, n_trials)
