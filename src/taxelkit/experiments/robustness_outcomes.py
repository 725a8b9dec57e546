"""Scoring of the ``robustness`` sweeps: one outcome per recognition, and the JSON summary.

:class:`TrialOutcome` scores one verdict against the ground truth (a wrong
name is worse than a doubt; a sliding trial must not be given an identity);
:func:`outcomes_json` sums the outcomes per cell (engine x rate x
imperfection x object), per engine x rate x imperfection, for the sliding
trials and for the other arrays, and lists in each cell the rolls not
identified with their verdicts.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

from taxelkit.smart.tacteme_table import OBJECTS

__all__ = [
    "ARRAY_FAULTS",
    "ARRAY_RATE_HZ",
    "LIFT_OFF",
    "MAIN_ARRAY",
    "SLIDING",
    "TrialOutcome",
    "outcomes_json",
]

#: Label of the lift-off trials (the ``contact-loss`` preset on a clean sensor).
LIFT_OFF = "contact-loss"
#: Ground-truth label of the sliding trials.
SLIDING = "sliding"
#: The array of the main matrix (paper 001's Bonneville, 16 x 16 at 1.76 mm).
MAIN_ARRAY = "16x16@1.76"
#: Imperfections the other arrays are seen through.
ARRAY_FAULTS: tuple[str, ...] = ("none", "all")
#: Frame rate of the other arrays' trials, Hz.
ARRAY_RATE_HZ = 20.0


@dataclass(frozen=True)
class TrialOutcome:
    """One recognition of one motion seen through one sensor.

    Attributes
    ----------
    engine, fault : str
    rate_hz : float
    truth : str
        The object, or ``"sliding"``.
    trial : int
    array : str
        ``ROWSxCOLS@PITCH`` of the array (:data:`MAIN_ARRAY` for the main matrix).
    identified : str or None
        The recogniser's verdict (``"unknown"``, an object, or None: undecided).
    candidates : tuple of str
    faithful : str or None
        The verdict of paper 001's pipeline as printed on the same frames.
    named : tuple of str
        Every object the robust recogniser's events named ("identified"), in
        order: a live user saw each of them, whatever the final verdict.
    """

    engine: str
    rate_hz: float
    fault: str
    truth: str
    trial: int
    identified: str | None
    candidates: tuple[str, ...]
    array: str = MAIN_ARRAY
    faithful: str | None = None
    named: tuple[str, ...] = ()

    @property
    def correct(self) -> bool:
        """Right: the object named, or a sliding trial not given an identity."""
        if self.truth == SLIDING:
            return self.identified is None or self.identified == "unknown"
        return self.identified == self.truth

    @property
    def wrong(self) -> bool:
        """A wrong identity: another object named (the worst outcome)."""
        return self.identified not in (None, "unknown", self.truth)

    @property
    def named_wrongly(self) -> bool:
        """Another object named by an event at some moment (counted even if later withdrawn)."""
        return any(n not in ("unknown", self.truth) for n in self.named)


def _missed(items: list[TrialOutcome]) -> list[list[Any]]:
    """``[trial, verdict]`` of each trial not counted correct (verdict None: undecided)."""
    return [[o.trial, o.identified] for o in sorted(items, key=lambda o: o.trial) if not o.correct]


def outcomes_json(
    outcomes: Sequence[TrialOutcome],
    engines: Sequence[str],
    rates_hz: Sequence[float],
    faults: Sequence[str],
    n_trials: int,
    skipped: dict[str, str],
) -> dict[str, Any]:
    """The JSON document of a sweep (``experiment`` is ``"robustness"``).

    Parameters
    ----------
    outcomes : sequence of TrialOutcome
    engines, faults : sequence of str
    rates_hz : sequence of float
    n_trials : int
        Trials per cell.
    skipped : dict of str to str
        Engines that could not run, with the reason.
    """
    groups: dict[tuple[str, float, str, str], list[TrialOutcome]] = {}
    arrays: dict[tuple[str, str, str, str], list[TrialOutcome]] = {}
    main = [o for o in outcomes if o.array == MAIN_ARRAY]
    for o in main:
        groups.setdefault((o.engine, o.rate_hz, o.fault, o.truth), []).append(o)
    for o in outcomes:
        if o.array != MAIN_ARRAY:
            arrays.setdefault((o.array, o.engine, o.fault, o.truth), []).append(o)

    def stats(items: list[TrialOutcome]) -> dict[str, Any]:
        n = len(items)
        correct = sum(o.correct for o in items)
        paper = [replace(o, identified=o.faithful) for o in items]
        return {
            "n": n,
            "correct": correct,
            "wrong": sum(o.wrong for o in items),
            "named_wrongly": sum(o.named_wrongly for o in items),
            "unknown": sum(o.identified == "unknown" for o in items),
            "undecided": sum(o.identified is None for o in items),
            "accuracy": round(correct / n, 4) if n else None,
            "faithful_accuracy": round(sum(o.correct for o in paper) / n, 4) if n else None,
            "faithful_wrong": sum(o.wrong for o in paper),
        }

    cells = [
        {"engine": e, "rate_hz": r, "fault": f, "object": t, **stats(v), "missed": _missed(v)}
        for (e, r, f, t), v in sorted(groups.items())
    ]
    summary = []
    for e in engines:
        for r in rates_hz:
            for f in (*faults, LIFT_OFF):
                items = [
                    o
                    for (ge, gr, gf, gt), v in groups.items()
                    if (ge, gr, gf) == (e, r, f) and gt != SLIDING
                    for o in v
                ]
                if items:
                    summary.append({"engine": e, "rate_hz": r, "fault": f, **stats(items)})
    in_set = [o for o in main if o.truth != SLIDING]
    sliding = [o for o in main if o.truth == SLIDING]
    other = [
        {"array": a, "engine": e, "fault": f, "object": t, **stats(v)}
        for (a, e, f, t), v in sorted(arrays.items())
    ]
    other_summary = []
    for a in sorted({k[0] for k in arrays}):
        for e in engines:
            for f in ARRAY_FAULTS:
                items = [o for (ga, ge, gf, gt), v in arrays.items()
                         if (ga, ge, gf) == (a, e, f) and gt != SLIDING for o in v]  # fmt: skip
                slid = arrays.get((a, e, f, SLIDING), [])
                if items:
                    other_summary.append(
                        {"array": a, "engine": e, "fault": f, **stats(items),
                         "sliding_identified": sum(not o.correct for o in slid)}
                    )  # fmt: skip
    return {
        "experiment": "robustness",
        "engines": list(engines),
        "skipped_engines": dict(skipped),
        "rates_hz": list(rates_hz),
        "faults": list(faults),
        "lift_off": LIFT_OFF,
        "n_trials": n_trials,
        "objects": list(OBJECTS),
        "overall": stats(in_set),
        "sliding": {**stats(sliding), "identified": sum(not o.correct for o in sliding)},
        "summary": summary,
        "cells": cells,
        "arrays": {
            "rate_hz": ARRAY_RATE_HZ,
            "faults": list(ARRAY_FAULTS),
            "summary": other_summary,
            "cells": other,
        },
    }
