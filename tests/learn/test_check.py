"""Learning checks the derived row by simulation and names what it cannot tell apart."""

from __future__ import annotations

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
