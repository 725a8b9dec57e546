"""Kinematic scripts for convex meshes: rolling without slip, determinism, on the array."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh

from taxelkit.learn.examples import example_mesh
from taxelkit.motion.mesh_roll import roll_path
from taxelkit.motion.mesh_scenarios import make_mesh_scenario
from taxelkit.motion.rolling import Pose
from taxelkit.world.mesh_features import mesh_features
from taxelkit.world.mesh_solid import MeshSolid


def _solid(mesh: trimesh.Trimesh) -> tuple[MeshSolid, object]:
    return MeshSolid.from_trimesh(mesh), mesh_features(mesh)


def test_a_ball_rolls_its_distance_without_slip() -> None:
    ball = MeshSolid.from_trimesh(trimesh.creation.icosphere(subdivisions=4, radius=6.0))
    start = Pose(np.eye(3), np.array([0.0, 0.0, -ball.vertices_mm[:, 2].min()]))
    rots, cents = roll_path(ball, start, np.array([1.0, 0.0, 0.0]), distance_mm=10.0)
    moved = cents[-1] - start.centroid_mm
    assert moved[0] == pytest.approx(10.0, abs=0.3) and abs(moved[1]) < 0.1
    turned = math.degrees(math.acos((np.trace(rots[-1]) - 1.0) / 2.0))
    assert turned == pytest.approx(math.degrees(10.0 / 6.0), rel=0.05)  # s = r phi
    assert np.ptp(cents[:, 2]) < 0.05  # the centre stays at the radius


def test_a_cube_tips_over_its_front_edge_by_a_quarter_turn() -> None:
    cube = MeshSolid.from_trimesh(trimesh.creation.box(extents=(10.0, 10.0, 10.0)))
    start = Pose(np.eye(3), np.array([0.0, 0.0, 5.0]))
    _, cents = roll_path(cube, start, np.array([1.0, 0.0, 0.0]), angle_rad=math.pi / 2)
    assert cents[-1] == pytest.approx([10.0, 0.0, 5.0], abs=0.05)  # onto the next face


@pytest.mark.parametrize("name", ["hex-prism", "square-pyramid", "ellipsoid", "capsule"])
def test_scripts_are_deterministic_and_stay_on_the_array(name: str) -> None:
    solid, feats = _solid(example_mesh(name))
    a = make_mesh_scenario(solid, feats, name=name, rng=5)  # type: ignore[arg-type]
    b = make_mesh_scenario(solid, feats, name=name, rng=5)  # type: ignore[arg-type]
    for field in ("rotations", "positions_mm", "rest_height_mm", "indent_mm", "t_s"):
        assert np.array_equal(getattr(a, field), getattr(b, field)), field
    assert a.phase == b.phase and a.object_name == name and not a.slides
    assert a.phase[0] == "lifted" and a.phase[-1] == "lifted"
    touch = a.in_contact
    world = a.centroids_mm[touch][:, None, :] + np.einsum(
        "vj,tij->tvi",
        a.solid.vertices_mm,
        a.rotations[touch],  # type: ignore[attr-defined]
    )
    pressed = world[..., :2][world[..., 2] <= 1e-6]
    assert np.all(np.abs(pressed) <= 14.1 - 1.0 + 1e-6)  # inside the array, 1 mm margin
    assert np.all(a.rest_height_mm > 0.0)
