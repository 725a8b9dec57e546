"""Learning checks the derived row by simulation and names what it cannot tell apart."""

from __future__ import annotations

import pytest

from taxelkit.learn.check import learn_solid
from taxelkit.learn.examples import example_mesh
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.world.mesh_solid import MeshSolid


def test_learning_the_pyramid_checks_its_row_and_names_its_overlaps() -> None:
    solid = MeshSolid.from_trimesh(example_mesh("square-pyramid"))
    a = learn_solid(solid, "pyramid", n_check=4, rng=3)
    b = learn_solid(solid, "pyramid", n_check=4, rng=3)
    assert a.row == b.row and a.seen == b.seen  # seeded
    assert a.derived.tactemes <= a.row.tactemes
    assert set(a.outside) == a.row.tactemes - a.derived.tactemes
    assert not set(a.left_out) & a.row.tactemes
    assert {Tacteme.AC, Tacteme.LC} <= set(a.seen)  # it was rolled and seen
    assert a.row.checked["rolls"] == 4
    sentences = " ".join(o.sentence for o in a.overlaps)
    assert "tetrahedron is never identified beside pyramid" in sentences
    assert "cube is never identified beside pyramid" in sentences


def test_the_ellipsoid_is_the_sphere_to_the_tactemes() -> None:
    solid = MeshSolid.from_trimesh(example_mesh("ellipsoid"))
    learnt = learn_solid(solid, "egg", n_check=0)
    assert any(o.identical and {o.first, o.second} == {"sphere", "egg"} for o in learnt.overlaps)


def test_a_tacteme_the_check_saw_once_is_added_as_rare(monkeypatch: pytest.MonkeyPatch) -> None:
    from collections import Counter

    import taxelkit.learn.check as check

    seen = Counter({Tacteme.LC: 24, Tacteme.LCMP: 20, Tacteme.LCMT: 1, Tacteme.LCMT_ARC: 3})
    monkeypatch.setattr(check, "check_rolls", lambda *a, **k: seen)
    solid = MeshSolid.from_trimesh(example_mesh("capsule"))
    learnt = learn_solid(solid, "pill", n_check=24, rng=0)
    assert {Tacteme.LCMT, Tacteme.LCMT_ARC} <= set(learnt.outside)
    assert learnt.rare == (Tacteme.LCMT,) and learnt.row.rare == frozenset({Tacteme.LCMT})
    assert "rare: never names the object alone" in learnt.row.reason(Tacteme.LCMT)
    assert "rare" not in learnt.row.reason(Tacteme.LCMT_ARC)  # 3 of 24: an ordinary member
    assert learnt.row.to_json()["rare"] == ["LCMT"]
