"""Flat faces, edges, rims and curved patches of convex meshes (closed-form checks)."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh

from taxelkit.world.mesh_features import mesh_features
from taxelkit.world.solids import make_solid


def test_a_cube_has_six_stable_square_faces_with_four_edges_each() -> None:
    f = mesh_features(make_solid("cube", edge_mm=10.0).to_trimesh())
    assert len(f.faces) == 6 and not f.curved
    for face in f.faces:
        assert face.stable and face.area_mm2 == pytest.approx(100.0)
        assert face.elongation == pytest.approx(1.0) and face.triangularity == pytest.approx(1.0)
        assert len(face.edge_dirs) == 4 and np.allclose(face.edge_lengths_mm, 10.0)
        assert face.rim_mm == 0.0


def test_a_tetrahedron_face_is_an_equilateral_triangle() -> None:
    f = mesh_features(make_solid("tetrahedron").to_trimesh())
    assert len(f.faces) == 4
    assert all(x.triangularity == pytest.approx(4.0 * math.sqrt(3.0) / 6.0) for x in f.faces)


@pytest.mark.parametrize("sections", [32, 64, 128])
def test_round_bodies_are_told_by_their_curved_surfaces(sections: int) -> None:
    cyl = mesh_features(trimesh.creation.cylinder(radius=6.0, height=14.0, sections=sections))
    assert len(cyl.faces) == 2 and len(cyl.ruled) == 1 and cyl.ruled[0].parallel
    assert cyl.faces[0].rim_mm == pytest.approx(2 * 6.0 * sections * math.sin(math.pi / sections))
    assert cyl.faces[0].triangularity == pytest.approx(3.0 / math.pi, abs=0.01)  # a disc
    cone = mesh_features(trimesh.creation.cone(radius=6.0, height=14.0, sections=sections))
    assert len(cone.faces) == 1 and not cone.ruled[0].parallel and cone.ruled[0].apex_on_body
    frustum = mesh_features(make_solid("truncated-cone").to_trimesh())
    assert len(frustum.faces) == 2 and not frustum.ruled[0].apex_on_body
    ball = mesh_features(trimesh.creation.icosphere(subdivisions=3, radius=6.0))
    assert not ball.faces and not ball.ruled
    assert ball.doubly_curved_mm2 == pytest.approx(4 * math.pi * 36, rel=0.02)


def test_a_capsule_has_a_ruled_side_and_doubly_curved_caps() -> None:
    f = mesh_features(trimesh.creation.capsule(height=12.0, radius=5.0, count=[32, 32]))
    assert not f.faces and len(f.ruled) == 1 and f.ruled[0].parallel
    assert f.doubly_curved_mm2 > 0.5 * 4 * math.pi * 25  # about the two caps
