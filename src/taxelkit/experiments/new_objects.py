"""Experiment ``new-objects``: the six objects of paper 001 plus four learnt from meshes.

The four shipped examples (:mod:`taxelkit.learn.examples`) are learnt as a
user would (:func:`~taxelkit.learn.check.learn_solid`: row derived from the
mesh, checked by 24 simulated rolls on a seed the trials do not use) and
joined to the six hand-written rows. Then every object is rolled
``n_trials`` times on the simulated Bonneville 16 x 16 (kinematic engine,
20 frames/s, noise on; the six with their scripts of
:mod:`taxelkit.motion.scenarios`, sizes +-30 %; the four with the mesh
scripts of :mod:`taxelkit.motion.mesh_scenarios` at their learnt size) and
recognised with the ten-object table and the face tactemes. An object the
table cannot tell apart from another (its row is held in another's:
:meth:`~taxelkit.smart.object_table.ObjectTable.overlaps`) is *not
distinguishable*; the acceptance asks >= 95 % identified over the
distinguishable ones and no wrong identity at all.

Beside it: the same frames recognised as paper 001's six-object table does
(``baseline``), and ``n_outside`` rolls of an object in neither table (a
triangular prism) with both, which must never be given a name.
Ground truth serves only for scoring.

*Exploration* (beyond paper 001): one roll decides only what its motion
shows (a cylinder placed straight on its side and rolled is a cylinder or a
capsule). A trial is also scored as a robot handling the object until it is
decided: while the ten-object verdict is undecided the object is handled
again (another roll drawn from the trial's seed: another placement, face
and motion), up to :data:`EXPLORE_HANDLINGS` rolls, and Level 4 runs over the
tactemes of all its contacts (:func:`~taxelkit.smart.one_object.one_object_verdict`).
The first handling is the single roll above; the number of handlings was
fixed before any run, and the outcome after each is reported.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cache
from typing import Any

import numpy as np

from taxelkit.experiments.work_units import map_in_order
from taxelkit.frames import TactileFrames
from taxelkit.learn.check import DEFAULT_CHECK_ROLLS, learn_solid
from taxelkit.learn.derive import derive_row
from taxelkit.learn.examples import EXAMPLE_OBJECTS, OUTSIDE_OBJECTS, example_mesh
from taxelkit.motion.mesh_scenarios import make_mesh_scenario
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import make_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart.object_table import PAPER_OBJECTS, ObjectTable
from taxelkit.smart.one_object import ContactEvidence, contacts_of, one_object_verdict
from taxelkit.smart.recogniser import recognise
from taxelkit.smart.tacteme_table import OBJECTS
from taxelkit.smart.tactemes import TactemeConfig
from taxelkit.world.mesh_features import MeshFeatures, mesh_features
from taxelkit.world.mesh_solid import MeshSolid
from taxelkit.world.solids import make_solid

__all__ = [
    "CHECK_SEED_OFFSET",
    "EXPLORE_HANDLINGS",
    "NewObjectsResult",
    "decidable",
    "run_new_objects",
    "six_rows_agree",
]

#: The learning check runs on ``seed + CHECK_SEED_OFFSET``, a stream the trials do not use.
CHECK_SEED_OFFSET = 7919
UNKNOWN, UNDECIDED = "unknown", "undecided"
#: Rolls of one object at most in the exploration protocol (fixed before any run).
EXPLORE_HANDLINGS = 5
#: Spawn-key element of the handlings after the first (the first is the trial's own roll).
_HANDLING_KEY = 104729


@cache
def _mesh(name: str) -> tuple[MeshSolid, MeshFeatures]:
    mesh = example_mesh(name)
    return MeshSolid.from_trimesh(mesh, label=name), mesh_features(mesh)


def six_rows_agree() -> dict[str, list[str]]:
    """For each of the six: tactemes where the row learnt from its mesh differs from Table 1."""
    out = {}
    for name in OBJECTS:
        mesh = make_solid(name).to_trimesh()
        row = derive_row(MeshSolid.from_trimesh(mesh), mesh_features(mesh), name)
        out[name] = sorted(t.value for t in row.tactemes ^ PAPER_OBJECTS.row(name).tactemes)
    return out


def _recording(name: str, rng: np.random.Generator) -> TactileFrames:
    """One randomised roll of ``name`` on the simulated Bonneville 16 x 16."""
    if name in OBJECTS:
        scenario = make_scenario(name, rng=rng)
    else:
        solid, feats = _mesh(name)
        scenario = make_mesh_scenario(solid, feats, name=name, rng=rng)
    return frames_from_scenario(BONNEVILLE_16X16, scenario, rng=rng)


def _handling_rng(seq: np.random.SeedSequence, j: int) -> np.random.Generator:
    """Generator of handling ``j >= 1`` of a trial (handling 0 uses ``seq`` itself)."""
    spawn = (*seq.spawn_key, _HANDLING_KEY, j)
    return np.random.default_rng(np.random.SeedSequence(seq.entropy, spawn_key=spawn))


def _trial(
    args: tuple[str, np.random.SeedSequence, ObjectTable, int],
) -> tuple[str, str, str, tuple[str, ...], tuple[str, int, tuple[str, ...]]]:
    """One trial: object, outcomes of its first roll with the ten-object table and with
    the six, tactemes seen; then the exploration's outcome, handlings used and tactemes."""
    name, seq, table, handlings = args
    config = TactemeConfig(face_shapes=True, objects=table)
    rec = _recording(name, np.random.default_rng(seq))
    ten = recognise(rec, config=config)
    six = recognise(rec)
    seen = tuple(sorted({t for t, _ in ten.tactemes}))
    contacts: list[ContactEvidence] = list(contacts_of(ten.events))
    used = 1
    while used < handlings:
        if contacts and one_object_verdict(contacts, table=table).outcome is not None:
            break
        more = recognise(_recording(name, _handling_rng(seq, used)), config=config)
        contacts += contacts_of(more.events)
        used += 1
    outcome = one_object_verdict(contacts, table=table).outcome if contacts else None
    seen_all = tuple(sorted({t for c in contacts for t, _ in c.tactemes}))
    explored = (outcome or UNDECIDED, used, seen_all)
    return name, ten.identified or UNDECIDED, six.identified or UNDECIDED, seen, explored


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
            "acceptance": {
                "six_rows_agree": all(not v for v in self.six_differences.values()),
                **acceptance,
            },
        }

    def _explore_json(self, never: list[str]) -> dict[str, Any]:
        """The exploration: per object, the outcome after each number of handlings."""
        objects = self.table.objects
        rows: list[dict[str, Any]] = []
        for name, runs in self.explorations.items():
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


def _learn(seed: int) -> tuple[ObjectTable, dict[str, Any]]:
    rows, checks = [], {}
    for k, name in enumerate(EXAMPLE_OBJECTS):
        solid, _ = _mesh(name)
        learnt = learn_solid(
            solid, name, source=f"{name}.stl", n_check=DEFAULT_CHECK_ROLLS,
            rng=seed + CHECK_SEED_OFFSET + k,
        )  # fmt: skip
        rows.append(learnt.row)
        checks[name] = {
            "rolls": learnt.rolls,
            "added": [t.value for t in learnt.outside],
            "rare": [t.value for t in learnt.rare],
            "left_out": [t.value for t in learnt.left_out],
        }
    return PAPER_OBJECTS.plus(rows), checks


def run_new_objects(
    *,
    seed: int = 0,
    n_trials: int = 100,
    n_outside: int = 100,
    handlings: int = EXPLORE_HANDLINGS,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> NewObjectsResult:
    """Learn the four examples, then roll and recognise every object ``n_trials`` times.

    Parameters
    ----------
    seed : int
    n_trials : int
        Rolls per object (ten objects).
    n_outside : int
        Rolls of each object outside both tables.
    handlings : int
        Most rolls of one object in the exploration (1: none beyond the first).
    workers : int, optional
        Local worker processes (default: up to 4).
    progress : callable, optional
        ``progress(done, total)``.
    """
    table, checks = _learn(seed)
    names = [o for o in table.objects for _ in range(n_trials)]
    names += [o for o in OUTSIDE_OBJECTS for _ in range(n_outside)]
    seqs = np.random.SeedSequence(seed).spawn(len(names))
    n_handlings = max(1, int(handlings))
    jobs = [(n, s, table, n_handlings) for n, s in zip(names, seqs, strict=True)]
    n_workers = min(4, os.cpu_count() or 1) if workers is None else max(1, int(workers))
    results = map_in_order(_trial, jobs, workers=n_workers, chunksize=4, progress=progress)
    confusion: dict[str, dict[str, int]] = {}
    baseline: dict[str, dict[str, int]] = {}
    dec: dict[str, tuple[int, int]] = {name: (0, 0) for name in table.objects}
    explorations: dict[str, list[tuple[str, int]]] = {}
    for name, ten, six, seen, (explored, used, _) in results:
        explorations.setdefault(name, []).append((explored, used))
        if name in dec and decidable(table, name, seen):
            n, ok = dec[name]
            dec[name] = (n + 1, ok + int(ten == name))
        for store, outcome in ((confusion, ten), (baseline, six)):
            d = store.setdefault(name, {})
            d[outcome] = d.get(outcome, 0) + 1
    inside = set(table.objects)
    return NewObjectsResult(
        table,
        {k: v for k, v in confusion.items() if k in inside},
        {k: v for k, v in baseline.items() if k in inside},
        {k: v for k, v in confusion.items() if k not in inside},
        {k: v for k, v in baseline.items() if k not in inside},
        six_rows_agree(),
        dec,
        n_trials,
        n_outside,
        seed,
        checks,
        explorations,
        n_handlings,
    )
