"""Learning an object: derive its row from the mesh, check it by simulation, report overlaps.

:func:`learn_solid` derives the row (:func:`~taxelkit.learn.derive.derive_row`),
then rolls the mesh on the simulated sensor ``n_check`` times with the
kinematic scripts of :mod:`taxelkit.motion.mesh_scenarios` and runs the
recogniser (face tactemes on) on the frames. Every tacteme the recogniser
reports in a roll is one the object produces on this sensor. One the
derivation missed (the skin and the taxel grid can make a thin face tipping
over look like a line that turns, or a face that moves) is named in the
result with the number of rolls it came from, and:

* added to the row if another object of the table can produce it: otherwise
  seeing it could rule the learnt object out and leave that other one, a
  wrong name. Seen in only a few rolls (at most :data:`RARE_SHARE` of them,
  at least one), it is added as *rare* (:attr:`ObjectRow.rare
  <taxelkit.smart.object_table.ObjectRow.rare>`): it does not rule the
  object out, but the object is not named on its strength either, since the
  same reading from another object (a truncated cone's stray "LCMP", say)
  would otherwise leave the learnt object alone and name it;
* left out if no object of the table can produce it (the tactemes of
  sliding: AC moves, AC rotates, LC slides, LC spins): seeing it then rules
  every object out and the roll ends "unknown", never a wrong name; adding
  it would make the learnt object the answer to every sliding object.

Tactemes of the row never seen in the check are listed too (the scripts do
not try every motion).
Finally the row is compared with the table it joins: objects whose rows hold
all of another's cannot always be told apart (:meth:`ObjectTable.overlaps
<taxelkit.smart.object_table.ObjectTable.overlaps>`).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from taxelkit.learn.derive import derive_row
from taxelkit.motion.mesh_scenarios import make_mesh_scenario
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16, Sensor
from taxelkit.smart.object_table import PAPER_OBJECTS, ObjectRow, ObjectTable, Overlap
from taxelkit.smart.recogniser import recognise
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.tactemes import TactemeConfig
from taxelkit.world.mesh_features import MeshFeatures, mesh_features
from taxelkit.world.mesh_solid import MeshSolid

__all__ = ["DEFAULT_CHECK_ROLLS", "RARE_SHARE", "Learnt", "learn_solid"]

#: Rolls of the simulation check.
DEFAULT_CHECK_ROLLS = 24
#: A tacteme the check added from at most this share of its rolls (at least one) is rare.
#: Every tacteme the checks of the four shipped examples added, on seeds 0, 3 and 11,
#: came from a single roll of 24 (a capsule's "LCMT" and "LCMT in an arc", a hexagonal
#: prism's "LCMT about one end"): with them as ordinary members, a truncated cone whose
#: roll read "LCMP" once was named capsule, and cones were never named beside the prism.
RARE_SHARE = 0.05


@dataclass(frozen=True)
class Learnt:
    """A learnt object.

    Attributes
    ----------
    row : ObjectRow
        The row to store: derived, plus what the check saw beyond it.
    derived : ObjectRow
        The row from the geometry alone.
    seen : dict of Tacteme to int
        Rolls of the check in which each tacteme was reported.
    rolls : int
        Rolls of the check.
    outside : tuple of Tacteme
        Seen in the check but not derived (added to :attr:`row`).
    rare : tuple of Tacteme
        Those of ``outside`` seen in few rolls (:data:`RARE_SHARE`): the
        row's :attr:`~taxelkit.smart.object_table.ObjectRow.rare`.
    overlaps : tuple of Overlap
        Pairs of the table it joins (the six and ``beside``) that involve it.
    features : MeshFeatures
    """

    row: ObjectRow
    derived: ObjectRow
    seen: dict[Tacteme, int]
    rolls: int
    outside: tuple[Tacteme, ...]
    overlaps: tuple[Overlap, ...]
    features: MeshFeatures
    left_out: tuple[Tacteme, ...] = ()
    rare: tuple[Tacteme, ...] = ()


def check_rolls(
    solid: MeshSolid,
    features: MeshFeatures,
    name: str,
    *,
    n_rolls: int,
    rng: int,
    sensor: Sensor = BONNEVILLE_16X16,
) -> Counter[Tacteme]:
    """Rolls in which each tacteme was reported, over ``n_rolls`` seeded kinematic rolls."""
    config = TactemeConfig(face_shapes=True)
    seeds = np.random.SeedSequence(rng).spawn(n_rolls)
    seen: Counter[Tacteme] = Counter()
    for seed in seeds:
        sc = make_mesh_scenario(solid, features, name=name, rng=np.random.default_rng(seed))
        rec = frames_from_scenario(sensor, sc, rng=np.random.default_rng(seed.spawn(1)[0]))
        seen.update({Tacteme(n) for n, _ in recognise(rec, config=config).tactemes})
    return seen


def learn_solid(
    solid: MeshSolid,
    name: str,
    *,
    source: str = "",
    n_check: int = DEFAULT_CHECK_ROLLS,
    rng: int = 0,
    beside: ObjectTable | None = None,
    sensor: Sensor = BONNEVILLE_16X16,
) -> Learnt:
    """Derive, check and compare the row of a convex body.

    Parameters
    ----------
    solid : MeshSolid
    name : str
    source : str
        Recorded in the row.
    n_check : int
        Rolls of the simulation check (0: none).
    rng : int
        Seed of the check.
    beside : ObjectTable, optional
        User objects already in the table (the six are always there).
    sensor : Sensor

    Returns
    -------
    Learnt
        ``outside``: seen, not derived, added; ``left_out``: seen, not
        derived, produced by no object of the table (not added).
    """
    import trimesh

    hull = trimesh.Trimesh(solid.vertices_mm).convex_hull
    features = mesh_features(hull)
    derived = derive_row(solid, features, name, source=source, sensor=sensor)
    seen = (
        check_rolls(solid, features, name, n_rolls=n_check, rng=rng, sensor=sensor)
        if n_check
        else Counter()
    )
    others = [r for r in (beside.rows if beside is not None else ()) if r.name != name]
    produced = set().union(*(r.tactemes for r in (*PAPER_OBJECTS.rows, *others)))
    missed = [t for t in Tacteme if t in seen and t not in derived.tactemes]
    outside = tuple(t for t in missed if t in produced)
    left_out = tuple(t for t in missed if t not in produced)
    rare = tuple(t for t in outside if seen[t] <= max(1.0, RARE_SHARE * n_check))
    reasons = dict(derived.reasons)
    for t in outside:
        reasons[t] = (
            f"seen in {seen[t]} of {n_check} simulated rolls (not derived from the geometry"
            + ("; rare: never names the object alone)" if t in rare else ")")
        )
    order = [t for t in Tacteme if t in reasons]
    checked = {
        "rolls": n_check,
        "seen": {t.value: seen[t] for t in Tacteme if t in seen},
        "outside_row": [t.value for t in outside],
        "left_out": [t.value for t in left_out],
    }
    row = ObjectRow(
        name, frozenset(order), tuple((t, reasons[t]) for t in order), source, checked,
        frozenset(rare),
    )  # fmt: skip
    table = PAPER_OBJECTS.plus([*others, row])
    overlaps = tuple(o for o in table.overlaps() if name in (o.first, o.second))
    return Learnt(row, derived, dict(seen), n_check, outside, overlaps, features, left_out, rare)
