"""Records and summaries of the ``new-objects`` experiment (:mod:`.new_objects`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from taxelkit.smart.object_table import ObjectTable
from taxelkit.smart.tacteme_table import OBJECTS

__all__ = ["EXPLORE_HANDLINGS", "UNDECIDED", "UNKNOWN", "NewObjectsResult", "decidable"]

UNKNOWN, UNDECIDED = "unknown", "undecided"
#: Rolls of one object at most in the exploration protocol (fixed before any run).
EXPLORE_HANDLINGS = 5


def decidable(table: ObjectTable, name: str, seen: tuple[str, ...]) -> bool:
    """Whether the tactemes ``seen`` that ``name``'s row holds rule out every other object.

    A roll that showed only tactemes another object can produce too cannot be
    decided by elimination, however well it is recognised (the motion did
    not show what tells the object apart); a decidable roll must end
    identified unless a tacteme outside the object's row ruled it out.
    """
    own = {t for t in table.row(name).tactemes if t.value in seen}
    return not any(own <= r.tactemes for r in table.rows if r.name != name)


@dataclass(frozen=True, eq=False)
class NewObjectsResult:
    """Outcomes of the ten objects (and the outside one) with both tables.

    Attributes
    ----------
    table : ObjectTable
        The ten rows used.
    confusion : dict
        ``confusion[object][outcome]`` trials, ten-object table.
    baseline : dict
        The same with paper 001's six-object table (no face tactemes).
    outside : dict
        ``outside[object][outcome]``, ten-object table.
    outside_baseline : dict
        The same, six-object table.
    six_differences : dict
        For each of the six: tactemes where the row learnt from its mesh
        differs from Table 1 (empty: they agree).
    decidable : dict
        ``decidable[object] = (rolls decidable, of them identified)`` (see :func:`decidable`).
    n_trials, n_outside, seed : int
    checks : dict
        What the learning check of each example saw.
    explorations : dict
        ``explorations[object]``: for every trial (outside objects too), the
        exploration's outcome (ten-object table) and the handlings it used.
    handlings : int
        Most handlings of the exploration.
    imperfect : dict
        ``imperfect[fault]``: the same motions seen through a fault model of
        :data:`~taxelkit.sensors.faults.FAULT_PRESETS`, ten-object table:
        ``"confusion"`` (first roll, as :attr:`confusion` and :attr:`outside`
        together) and ``"explorations"`` (as :attr:`explorations`).
    """

    table: ObjectTable
    confusion: dict[str, dict[str, int]]
    baseline: dict[str, dict[str, int]]
    outside: dict[str, dict[str, int]]
    outside_baseline: dict[str, dict[str, int]]
    six_differences: dict[str, list[str]]
    decidable: dict[str, tuple[int, int]]
    n_trials: int
    n_outside: int
    seed: int
    checks: dict[str, Any] = field(default_factory=dict)
    explorations: dict[str, list[tuple[str, int]]] = field(default_factory=dict)
    handlings: int = EXPLORE_HANDLINGS
    imperfect: dict[str, dict[str, Any]] = field(default_factory=dict)

    def to_json(self) -> dict[str, Any]:
        """Confusions, rows, overlaps, per-object rates and the acceptance."""
        objects = self.table.objects
        overlaps = self.table.overlaps()
        never = sorted({o.first for o in overlaps})
        rows: list[dict[str, Any]] = []
        for name in objects:
            c = self.confusion[name]
            n = sum(c.values())
            rows.append(
                {
                    "object": name,
                    "trials": n,
                    "identified": c.get(name, 0),
                    "wrong": sum(v for k, v in c.items() if k in objects and k != name),
                    "unknown": c.get(UNKNOWN, 0),
                    "undecided": c.get(UNDECIDED, 0),
                    "distinguishable": name not in never,
                    "decidable": self.decidable[name][0],
                    "decidable_identified": self.decidable[name][1],
                    "baseline_identified": self.baseline[name].get(name, 0),
                    "baseline_wrong": sum(
                        v for k, v in self.baseline[name].items() if k in OBJECTS and k != name
                    ),
                }
            )
        dist = [r for r in rows if r["distinguishable"]]
        n_dist = sum(r["trials"] for r in dist)
        ident = sum(r["identified"] for r in dist)
        wrong = sum(r["wrong"] for r in rows)
        named_outside = sum(v for d in self.outside.values() for k, v in d.items() if k in objects)
        n_dec = sum(r["decidable"] for r in rows)
        dec_ident = sum(r["decidable_identified"] for r in rows)
        summary, acceptance = _scores(n_dist, ident, wrong, named_outside)
        return {
            "experiment": "new-objects",
            "seed": self.seed,
            "n_trials": self.n_trials,
            "n_outside": self.n_outside,
            "objects": list(objects),
            "rows": {r.name: r.to_json()["tactemes"] for r in self.table.rows},
            "checks": self.checks,
            "overlaps": [
                {
                    "first": o.first,
                    "second": o.second,
                    "identical": o.identical,
                    "sentence": o.sentence,
                }
                for o in overlaps
            ],
            "not_distinguishable": never,
            "confusion": self.confusion,
            "baseline": self.baseline,
            "outside": self.outside,
            "outside_baseline": self.outside_baseline,
            "per_object": rows,
            "six_differences": self.six_differences,
            "summary": {
                **summary,
                "decidable_trials": n_dec,
                "decidable_identified": dec_ident,
                "decidable_rate": dec_ident / n_dec if n_dec else 0.0,
            },
            "explore": self._explore_json(never),
            "imperfect": {
                fault: self._imperfect_json(never, views) for fault, views in self.imperfect.items()
            },
            "acceptance": {
                "six_rows_agree": all(not v for v in self.six_differences.values()),
                **acceptance,
            },
        }

    def _imperfect_json(self, never: list[str], views: dict[str, Any]) -> dict[str, Any]:
        """One imperfection: first roll per object, objects outside, the exploration."""
        objects = self.table.objects
        rows = []
        for name, c in views["confusion"].items():
            rows.append(
                {
                    "object": name,
                    "inside": name in objects,
                    "distinguishable": name in objects and name not in never,
                    "trials": sum(c.values()),
                    "identified": c.get(name, 0),
                    "wrong": sum(v for k, v in c.items() if k in objects and k != name),
                    "unknown": c.get(UNKNOWN, 0),
                    "undecided": c.get(UNDECIDED, 0),
                    "outcomes": dict(sorted(c.items())),
                }
            )
        dist = [r for r in rows if r["distinguishable"]]
        summary, acceptance = _scores(
            sum(r["trials"] for r in dist),
            sum(r["identified"] for r in dist),
            sum(r["wrong"] for r in rows if r["inside"]),
            sum(r["wrong"] for r in rows if not r["inside"]),
        )
        return {
            "per_object": rows,
            "summary": summary,
            "acceptance": acceptance,
            "explore": self._explore_json(never, views["explorations"]),
        }

    def _explore_json(
        self, never: list[str], explorations: dict[str, list[tuple[str, int]]] | None = None
    ) -> dict[str, Any]:
        """The exploration: per object, the outcome after each number of handlings."""
        objects = self.table.objects
        rows: list[dict[str, Any]] = []
        runs_of = self.explorations if explorations is None else explorations
        for name, runs in runs_of.items():
            right = [used for outcome, used in runs if outcome == name]
            rows.append(
                {
                    "object": name,
                    "inside": name in objects,
                    "distinguishable": name in objects and name not in never,
                    "trials": len(runs),
                    "identified": len(right),
                    "identified_by_handling": [
                        sum(u <= h for u in right) for h in range(1, self.handlings + 1)
                    ],
                    "wrong": sum(o in objects and o != name for o, _ in runs),
                    "unknown": sum(o == UNKNOWN for o, _ in runs),
                    "undecided": sum(o == UNDECIDED for o, _ in runs),
                    "mean_handlings": float(np.mean([u for _, u in runs])) if runs else 0.0,
                    "outcomes": {
                        o: sum(x == o for x, _ in runs) for o in sorted({x for x, _ in runs})
                    },
                }
            )
        dist = [r for r in rows if r["distinguishable"]]
        n_dist = sum(r["trials"] for r in dist)
        ident = sum(r["identified"] for r in dist)
        wrong = sum(r["wrong"] for r in rows if r["inside"])
        named_outside = sum(r["wrong"] for r in rows if not r["inside"])
        summary, acceptance = _scores(n_dist, ident, wrong, named_outside)
        return {
            "handlings": self.handlings,
            "per_object": rows,
            "summary": summary,
            "acceptance": acceptance,
        }


def _scores(
    n_dist: int, ident: int, wrong: int, named_outside: int
) -> tuple[dict[str, Any], dict[str, bool]]:
    """Summary and acceptance from the distinguishable trials, identified, wrong, outside named."""
    summary = {
        "distinguishable_trials": n_dist,
        "distinguishable_identified": ident,
        "distinguishable_rate": ident / n_dist if n_dist else 0.0,
        "wrong": wrong,
        "outside_named": named_outside,
    }
    acceptance = {
        "identified_ge_95_where_distinguishable": bool(n_dist and ident >= 0.95 * n_dist),
        "no_wrong_identity": wrong == 0,
        "outside_never_named": named_outside == 0,
    }
    return summary, acceptance
