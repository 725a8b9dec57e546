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
from collections.abc import Callable, Sequence
from functools import cache
from typing import Any

import numpy as np

from taxelkit.experiments.new_objects_result import (
    EXPLORE_HANDLINGS,
    UNDECIDED,
    NewObjectsResult,
    decidable,
)
from taxelkit.experiments.sensor_views import check_views
from taxelkit.experiments.work_units import map_in_order
from taxelkit.frames import TactileFrames
from taxelkit.learn.check import DEFAULT_CHECK_ROLLS, learn_solid
from taxelkit.learn.derive import derive_row
from taxelkit.learn.examples import EXAMPLE_OBJECTS, OUTSIDE_OBJECTS, example_mesh
from taxelkit.motion.mesh_scenarios import make_mesh_scenario
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import make_scenario
from taxelkit.sensors.faults import FaultModel, fault_model
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
    "IMPERFECTIONS",
    "NewObjectsResult",
    "decidable",
    "run_new_objects",
    "six_rows_agree",
]

#: The learning check runs on ``seed + CHECK_SEED_OFFSET``, a stream the trials do not use.
CHECK_SEED_OFFSET = 7919
#: Spawn-key element of the handlings after the first (the first is the trial's own roll).
_HANDLING_KEY = 104729
#: Spawn-key element of the imperfections' faults.
_FAULT_KEY = 130363
#: How each roll is seen: as the array gives it, then through these fault models
#: (:data:`~taxelkit.sensors.faults.FAULT_PRESETS`).
IMPERFECTIONS: tuple[str, ...] = ("none", "all")


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


def _fault_seed(seq: np.random.SeedSequence, j: int, k: int) -> np.random.Generator:
    """Generator of imperfection ``k``'s faults on handling ``j`` (apart from the motions)."""
    spawn = (*seq.spawn_key, _FAULT_KEY, j, k)
    return np.random.default_rng(np.random.SeedSequence(seq.entropy, spawn_key=spawn))


def _explore(
    handling: Callable[[int], TactileFrames], table: ObjectTable, handlings: int
) -> tuple[Any, tuple[str, int, tuple[str, ...]]]:
    """The first roll's ten-object recognition, then the exploration over ``handling(j)``."""
    config = TactemeConfig(face_shapes=True, objects=table)
    ten = recognise(handling(0), config=config)
    contacts: list[ContactEvidence] = list(contacts_of(ten.events))
    used = 1
    while used < handlings:
        if contacts and one_object_verdict(contacts, table=table).outcome is not None:
            break
        contacts += contacts_of(recognise(handling(used), config=config).events)
        used += 1
    outcome = one_object_verdict(contacts, table=table).outcome if contacts else None
    seen_all = tuple(sorted({t for c in contacts for t, _ in c.tactemes}))
    return ten, (outcome or UNDECIDED, used, seen_all)


def _trial(
    args: tuple[str, np.random.SeedSequence, ObjectTable, int, tuple[str, ...]],
) -> tuple[
    str,
    str,
    str,
    tuple[str, ...],
    tuple[str, int, tuple[str, ...]],
    dict[str, tuple[str, str, int]],
]:
    """One trial: object, outcomes of its first roll with the ten-object table and with
    the six, tactemes seen; then the exploration's outcome, handlings used and tactemes;
    last, per imperfection, the first roll's and the exploration's outcome and handlings
    with the same motions seen through that fault model."""
    name, seq, table, handlings, imperfections = args
    recordings: dict[int, TactileFrames] = {}

    def handling(j: int) -> TactileFrames:
        if j not in recordings:  # handling 0 is the trial's own roll
            rng = np.random.default_rng(seq) if j == 0 else _handling_rng(seq, j)
            recordings[j] = _recording(name, rng)
        return recordings[j]

    ten, explored = _explore(handling, table, handlings)
    six = recognise(handling(0))
    seen = tuple(sorted({t for t, _ in ten.tactemes}))
    imperfect: dict[str, tuple[str, str, int]] = {}
    for k, fault in enumerate(f for f in imperfections if f != "none"):
        model = fault_model(fault)

        def seen_through(j: int, k: int = k, model: FaultModel = model) -> TactileFrames:
            thr = BONNEVILLE_16X16.contact_threshold_mm
            return model.apply(handling(j), threshold=thr, rng=_fault_seed(seq, j, k))

        ten_f, (outcome, used, _) = _explore(seen_through, table, handlings)
        imperfect[fault] = (ten_f.identified or UNDECIDED, outcome, used)
    return name, ten.identified or UNDECIDED, six.identified or UNDECIDED, seen, explored, imperfect


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
    imperfections: Sequence[str] = IMPERFECTIONS,
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
    imperfections : sequence of str
        Fault models every roll is also seen through, the same motions
        (names of :data:`~taxelkit.sensors.faults.FAULT_PRESETS`; ``"none"``,
        the array's noise only, is the main result).
    workers : int, optional
        Local worker processes (default: up to 4).
    progress : callable, optional
        ``progress(done, total)``.
    """
    imps = check_views(imperfections)[0][1:]  # the views beside the clean rolls
    table, checks = _learn(seed)
    names = [o for o in table.objects for _ in range(n_trials)]
    names += [o for o in OUTSIDE_OBJECTS for _ in range(n_outside)]
    seqs = np.random.SeedSequence(seed).spawn(len(names))
    n_handlings = max(1, int(handlings))
    jobs = [(n, s, table, n_handlings, imps) for n, s in zip(names, seqs, strict=True)]
    n_workers = min(4, os.cpu_count() or 1) if workers is None else max(1, int(workers))
    results = map_in_order(_trial, jobs, workers=n_workers, chunksize=4, progress=progress)
    confusion: dict[str, dict[str, int]] = {}
    baseline: dict[str, dict[str, int]] = {}
    dec: dict[str, tuple[int, int]] = {name: (0, 0) for name in table.objects}
    explorations: dict[str, list[tuple[str, int]]] = {}
    imperfect: dict[str, dict[str, Any]] = {f: {"confusion": {}, "explorations": {}} for f in imps}
    for name, ten, six, seen, (explored, used, _), faulty in results:
        explorations.setdefault(name, []).append((explored, used))
        for fault, (first, outcome_f, used_f) in faulty.items():
            d = imperfect[fault]["confusion"].setdefault(name, {})
            d[first] = d.get(first, 0) + 1
            imperfect[fault]["explorations"].setdefault(name, []).append((outcome_f, used_f))
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
        imperfect,
    )
