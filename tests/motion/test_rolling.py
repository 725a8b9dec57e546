"""Kinematics of rolling without slip, the Scenario record, ground-truth contacts, frames.

Closed forms checked here: a sphere rolled a distance ``s`` turns by ``s / R``;
a rotation about a fixed line keeps that line fixed; a cone rolled on its side
keeps its apex fixed, and after its contact generator has turned by ``2 pi
sin(alpha)`` it has spun exactly once (the same material generator touches
again); a truncated cone's contact line points at its fixed virtual apex. The
no-slip condition is checked numerically: the material contact points move by
``O(step**2)`` per step (``O(step**3)`` horizontally for rolling), which the
tests show by halving the step; sliding moves them by the step itself.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.frames import TactileFrames
from taxelkit.motion.contact_truth import (
    CONTACT_TYPES,
    contact_points_body_mm,
    contact_state,
    contact_types,
    slip_from_poses,
)
from taxelkit.motion.roll_paths import roll_cone, roll_straight, rotate_about_line, translate
from taxelkit.motion.rolling import E_Z, PHASES, Pose, Scenario, frames_from_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.world.pose import matrix_from_axis_angle
from taxelkit.world.solids import Cone, Cube, Cylinder, Sphere, Tetrahedron, TruncatedCone

Arr = NDArray[np.float64]


def rest_pose(solid: object, rotation: Arr, xy: tuple[float, float] = (0.0, 0.0)) -> Pose:
    """The body resting on z = 0 with its centroid above ``xy``."""
    z = -float(solid.lowest_z_mm(rotation[None])[0])  # type: ignore[attr-defined]
    return Pose(rotation, np.array([xy[0], xy[1], z]))


def angle_between(r1: Arr, r2: Arr) -> Arr:
    """Rotation angles of ``r2 r1^T``, (n,) rad."""
    rel = r2 @ np.swapaxes(r1, -1, -2)
    skew = rel - np.swapaxes(rel, -1, -2)
    sin = 0.5 * np.linalg.norm(skew[..., [2, 0, 1], [1, 2, 0]], axis=-1)
    return np.arctan2(sin, (np.trace(rel, axis1=-2, axis2=-1) - 1.0) / 2.0)


def lying_cone(solid: Cone | TruncatedCone) -> Pose:
    """A (truncated) cone on its side: tipped over a base-rim point until a generator lands."""
    pose = rest_pose(solid, np.eye(3))
    (z0, r0), (z1, r1) = solid.profile.rims
    u = np.array([1.0, 0.0, 0.0])
    pivot = pose.centroid_mm + np.array([r0, 0.0, z0])
    q = pose.centroid_mm + np.array([r1, 0.0, z1]) - pivot
    landing = math.atan2(q[2], q[0])  # closed form: 90 deg + half-angle
    rots, cents = rotate_about_line(pose, pivot, np.cross(E_Z, u), landing)
    return Pose(rots[0], cents[0])


def rim_lowest(pose: Pose, z: float, r: float) -> Arr:
    """Lowest point of a tilted rim circle (body height ``z``, radius ``r``), sensor frame."""
    a = pose.rotation[:, 2]
    down = -(E_Z - a[2] * a)
    out: Arr = pose.centroid_mm + z * a + r * down / np.linalg.norm(down)
    return out


def apex_world(solid: Cone | TruncatedCone, pose: Pose) -> Arr:
    return pose.centroid_mm + solid.profile.vertex_z_mm * pose.rotation[:, 2]


# --- pose operations ---------------------------------------------------------------------------


def test_sphere_rolled_distance_s_turns_by_s_over_r() -> None:
    sphere = Sphere(radius_mm=5.0)
    pose = rest_pose(sphere, matrix_from_axis_angle([0.3, 0.2, 0.9], 0.7))
    d = np.array([0.6, 0.8, 0.0])
    s = np.array([0.5, 3.0, 7.5, 12.0])
    rots, cents = roll_straight(pose, sphere.radius_mm, d, s)
    np.testing.assert_allclose(angle_between(pose.rotation[None], rots), s / 5.0, atol=1e-12)
    np.testing.assert_allclose(cents - pose.centroid_mm, s[:, None] * d, atol=1e-12)
    # the rotation axis is horizontal and perpendicular to the travel: e_z x d
    rel = rots[-1] @ pose.rotation.T
    axis = np.array([rel[2, 1] - rel[1, 2], rel[0, 2] - rel[2, 0], rel[1, 0] - rel[0, 1]])
    np.testing.assert_allclose(axis / np.linalg.norm(axis), np.cross(E_Z, d), atol=1e-12)


def test_sphere_contact_point_has_zero_velocity() -> None:
    """Cycloid at the cusp: 3-D displacement ~ R dtheta^2 / 2, horizontal ~ R dtheta^3 / 6."""
    sphere = Sphere(radius_mm=6.0)
    pose = rest_pose(sphere, np.eye(3))
    d = np.array([1.0, 0.0, 0.0])
    slips = {}
    for step in (0.2, 0.1):
        s = np.arange(0.0, 10.0 + 1e-9, step)
        rots, cents = roll_straight(pose, sphere.radius_mm, d, s)
        dth = step / sphere.radius_mm
        full = slip_from_poses(sphere, rots, cents, full=True)
        horiz = slip_from_poses(sphere, rots, cents)
        np.testing.assert_allclose(
            full, 6.0 * (1.0 - math.cos(dth)) * np.ones_like(full), rtol=1e-3
        )
        np.testing.assert_allclose(horiz, 6.0 * (dth - math.sin(dth)), rtol=1e-3, atol=1e-12)
        slips[step] = (full.max(), horiz.max())
    assert slips[0.2][0] / slips[0.1][0] == pytest.approx(4.0, rel=0.01)  # O(step^2)
    assert slips[0.2][1] / slips[0.1][1] == pytest.approx(8.0, rel=0.02)  # O(step^3)


def test_cylinder_rolls_on_its_side_with_line_moving_parallel() -> None:
    cyl = Cylinder(radius_mm=4.0, height_mm=14.0)
    pose = rest_pose(cyl, matrix_from_axis_angle([1.0, 0.0, 0.0], math.pi / 2))  # axis along y
    assert contact_types(cyl, pose.rotation[None]) == ("line",)
    s = np.linspace(0.0, 9.0, 46)
    rots, cents = roll_straight(pose, cyl.radius_mm, [1.0, 0.0, 0.0], s)
    # rests on its side the whole time, never through the plane
    np.testing.assert_allclose(-cyl.lowest_z_mm(rots), cents[:, 2], atol=1e-12)
    assert set(contact_types(cyl, rots)) == {"line"}
    state = contact_state(cyl, rots)
    ends = [state.relative_mm[t][state.touching[t]] + cents[t] for t in range(s.size)]
    for t, pts in enumerate(ends):
        # the line moved by s along x (rim samples within CONTACT_TIE_MM sit ~1e-3 mm aside)
        np.testing.assert_allclose(pts[:, 0], s[t], atol=2e-3)
        np.testing.assert_allclose(pts[:, 2], 0.0, atol=1e-6)
    assert np.ptp(ends[-1][:, 1]) == pytest.approx(14.0, abs=1e-6)  # still along y
    assert slip_from_poses(cyl, rots, cents).max() < 1e-4
    assert slip_from_poses(cyl, rots, cents, full=True).max() < 4.0 * (0.2 / 4.0) ** 2


@settings(max_examples=40, deadline=None)
@given(
    axis=st.tuples(*[st.floats(-1, 1)] * 3).filter(lambda a: np.linalg.norm(a) > 0.1),
    point=st.tuples(*[st.floats(-10, 10)] * 3),
    angles=st.lists(st.floats(-6.3, 6.3), min_size=1, max_size=5),
    t=st.floats(-5, 5),
)
def test_rotation_about_a_line_keeps_the_line_fixed(
    axis: tuple[float, float, float],
    point: tuple[float, float, float],
    angles: list[float],
    t: float,
) -> None:
    pose = Pose(matrix_from_axis_angle([0.1, 0.5, 0.2], 1.1), np.array([1.0, -2.0, 6.0]))
    rots, cents = rotate_about_line(pose, point, axis, angles)
    a = np.asarray(axis) / np.linalg.norm(axis)
    on_line = np.asarray(point) + t * a
    body = pose.rotation.T @ (on_line - pose.centroid_mm)  # that material point
    world = cents + rots @ body
    np.testing.assert_allclose(world, np.broadcast_to(on_line, world.shape), atol=1e-9)


def test_cube_tipped_about_an_edge_keeps_the_edge_and_lands_on_the_next_face() -> None:
    cube = Cube(edge_mm=10.0)
    pose = rest_pose(cube, np.eye(3))
    edge = np.array([[5.0, -5.0, 0.0], [5.0, 5.0, 0.0]])
    u = np.array([1.0, 0.0, 0.0])
    angles = np.linspace(0.0, math.pi / 2, 31)
    rots, cents = rotate_about_line(pose, edge[0], np.cross(E_Z, u), angles)
    np.testing.assert_allclose(-cube.lowest_z_mm(rots), cents[:, 2], atol=1e-12)
    kinds = contact_types(cube, rots)
    assert kinds[0] == "area" and kinds[-1] == "area" and set(kinds[1:-1]) == {"line"}
    corner_body = np.array([[5.0, -5.0, -5.0], [5.0, 5.0, -5.0]])
    world = cents[:, None, :] + corner_body @ np.swapaxes(rots, 1, 2)
    np.testing.assert_allclose(world, np.broadcast_to(edge, world.shape), atol=1e-12)
    np.testing.assert_allclose(cents[15], [5.0, 0.0, 5.0 * math.sqrt(2.0)], atol=1e-12)  # balance
    # the face lifts about the edge: horizontal slip second order (a (1 - cos dtheta))
    dth = angles[1]
    assert slip_from_poses(cube, rots, cents).max() <= 10.0 * (1 - math.cos(dth)) + 1e-12


def test_tetrahedron_tips_109_47_deg_from_face_to_face() -> None:
    tet = Tetrahedron(edge_mm=12.0)
    pose = rest_pose(tet, np.eye(3))
    v = pose.world_mm(tet.vertices_mm)
    a, b = v[1], v[2]  # a bottom edge
    mid = 0.5 * (a + b)
    u = np.array([mid[0], mid[1], 0.0]) / math.hypot(mid[0], mid[1])
    full = math.pi - math.acos(1.0 / 3.0)
    assert math.degrees(full) == pytest.approx(109.47, abs=0.01)
    rots, cents = rotate_about_line(pose, mid, np.cross(E_Z, u), np.array([full / 2, full]))
    np.testing.assert_allclose(-tet.lowest_z_mm(rots), cents[:, 2], atol=1e-12)
    assert contact_types(tet, rots) == ("line", "area")
    np.testing.assert_allclose(cents[0, :2], mid[:2], atol=1e-12)  # balanced over the edge


def test_cone_rolls_about_its_fixed_apex_and_spins_once_per_2pi_sin_alpha() -> None:
    cone = Cone(radius_mm=5.0, height_mm=12.0)
    pose = lying_cone(cone)
    apex = apex_world(cone, pose)
    axis = -pose.rotation[:, 2]  # from the apex into the body
    sin_a = 5.0 / math.hypot(5.0, 12.0)
    assert axis[2] == pytest.approx(sin_a, abs=1e-12)
    assert apex[2] == pytest.approx(0.0, abs=1e-12)
    turns = np.linspace(0.0, 2.0 * math.pi * sin_a, 200)
    rots, cents = roll_cone(pose, apex, axis, turns)
    np.testing.assert_allclose(-cone.lowest_z_mm(rots), cents[:, 2], atol=1e-12)
    assert set(contact_types(cone, rots)) == {"line"}
    apexes = cents + cone.profile.vertex_z_mm * rots[:, :, 2]
    np.testing.assert_allclose(apexes, np.broadcast_to(apex, apexes.shape), atol=1e-12)
    # the generator turned by phi; after psi = 2 pi the same material generator touches
    z_turn = matrix_from_axis_angle(E_Z, turns[-1])
    np.testing.assert_allclose(rots[-1], z_turn @ pose.rotation, atol=1e-12)
    # no slip: contact points move by O(step^2), horizontally by O(step^3)
    full = slip_from_poses(cone, rots, cents, full=True)
    half = roll_cone(pose, apex, axis, turns[::2])
    full2 = slip_from_poses(cone, *half, full=True)
    assert full2.max() / full.max() == pytest.approx(4.0, rel=0.05)
    horiz, horiz2 = slip_from_poses(cone, rots, cents), slip_from_poses(cone, *half)
    assert horiz2.max() / horiz.max() == pytest.approx(8.0, rel=0.15)
    dth = angle_between(rots[:-1], rots[1:]).max()  # |omega| dt = dphi cot(alpha)
    assert dth == pytest.approx(turns[1] * 12.0 / 5.0, rel=1e-3)
    assert horiz.max() < 2.0 * cone.radius_mm * dth**3 / 6.0


def test_truncated_cone_rolls_in_an_arc_about_its_virtual_apex() -> None:
    frustum = TruncatedCone(bottom_radius_mm=6.0, top_radius_mm=3.0, height_mm=10.0)
    pose = lying_cone(frustum)
    apex = apex_world(frustum, pose)
    axis = frustum.profile.direction * pose.rotation[:, 2]
    assert apex[2] == pytest.approx(0.0, abs=1e-12)
    rots, cents = roll_cone(pose, apex, axis, np.linspace(0.0, math.radians(50), 40))
    np.testing.assert_allclose(-frustum.lowest_z_mm(rots), cents[:, 2], atol=1e-12)
    apexes = cents + frustum.profile.vertex_z_mm * rots[:, :, 2]
    np.testing.assert_allclose(apexes, np.broadcast_to(apex, apexes.shape), atol=1e-12)
    assert set(contact_types(frustum, rots)) == {"line"}
    for rot, cen in zip(rots, cents, strict=True):
        # the lowest points of the two rims: the ends of the contact line
        ends = [rim_lowest(Pose(rot, cen), z, r) for z, r in frustum.profile.rims]
        np.testing.assert_allclose([ends[0][2], ends[1][2]], 0.0, atol=1e-9)
        d1, d2 = ends[0] - apex, ends[1] - apex
        # extended, the contact line passes through the virtual apex, off the body
        assert np.linalg.norm(np.cross(d1, d2)) < 1e-9 * np.linalg.norm(d1) * np.linalg.norm(d2)
        assert np.dot(d1, d2) > 0.0 and min(np.linalg.norm(d1), np.linalg.norm(d2)) > 5.0
    dth = angle_between(rots[:-1], rots[1:]).max()
    assert slip_from_poses(frustum, rots, cents).max() < 2.0 * 6.0 * dth**3 / 6.0  # O(step^3)


def test_sliding_and_spinning_violate_no_slip() -> None:
    cube = Cube(edge_mm=10.0)
    pose = rest_pose(cube, np.eye(3))
    off = np.linspace(0.0, 5.0, 21)[:, None] * np.array([0.6, 0.8])
    rots, cents = translate(pose, off)
    np.testing.assert_allclose(slip_from_poses(cube, rots, cents), 0.25, rtol=1e-9)
    cyl = Cylinder()
    pose = rest_pose(cyl, np.eye(3))
    spin = np.linspace(0.0, math.radians(60), 21)
    rots, cents = rotate_about_line(pose, pose.centroid_mm, E_Z, spin)
    chord = 2 * cyl.radius_mm * math.sin(spin[1] / 2)
    np.testing.assert_allclose(slip_from_poses(cyl, rots, cents), chord, rtol=1e-9)


def test_pose_operations_validate_their_inputs() -> None:
    pose = Pose(np.eye(3), np.zeros(3))
    with pytest.raises(InputError, match="horizontal"):
        roll_straight(pose, 1.0, [1.0, 0.0, 1.0], [1.0])
    with pytest.raises(InputError, match="radius_mm"):
        roll_straight(pose, 0.0, [1.0, 0.0, 0.0], [1.0])
    with pytest.raises(InputError, match="rise"):
        roll_cone(pose, np.zeros(3), [1.0, 0.0, 0.0], [0.1])
    with pytest.raises(InputError, match="axis"):
        rotate_about_line(pose, np.zeros(3), np.zeros(3), [0.1])
    with pytest.raises(InputError, match="offsets_mm"):
        translate(pose, np.zeros(3))
    with pytest.raises(InputError, match="centroid_mm"):
        Pose(np.eye(3), np.zeros(2))
    with pytest.raises(InputError, match="rotation"):
        Pose(2 * np.eye(3), np.zeros(3))


# --- ground-truth contact ----------------------------------------------------------------------


@pytest.mark.parametrize(
    ("solid", "rotation", "kind"),
    [
        (Cube(), np.eye(3), "area"),
        (Cube(), matrix_from_axis_angle([0, 1, 0], math.pi / 4), "line"),
        (Cube(), matrix_from_axis_angle([1, -1, 0], math.atan(math.sqrt(2))), "point"),
        (Tetrahedron(), np.eye(3), "area"),
        (Tetrahedron(), matrix_from_axis_angle([1, 0, 0], math.pi), "point"),
        (Sphere(), matrix_from_axis_angle([1, 2, 3], 0.4), "point"),
        (Cylinder(), np.eye(3), "area"),
        (Cylinder(), matrix_from_axis_angle([1, 0, 0], math.pi / 2), "line"),
        (Cylinder(), matrix_from_axis_angle([1, 0, 0], 0.5), "point"),
        (Cone(), np.eye(3), "area"),
        (Cone(), matrix_from_axis_angle([1, 0, 0], math.pi), "point"),
        (TruncatedCone(), matrix_from_axis_angle([1, 0, 0], math.pi), "area"),
    ],
)
def test_contact_types_of_simple_poses(solid: object, rotation: Arr, kind: str) -> None:
    assert contact_types(solid, rotation[None]) == (kind,)  # type: ignore[arg-type]
    assert kind in CONTACT_TYPES


def test_contact_points_reject_unknown_solids() -> None:
    class Blob:
        name = "blob"

    with pytest.raises(InputError, match="blob"):
        contact_points_body_mm(Blob(), np.eye(3)[None])  # type: ignore[arg-type]
    with pytest.raises(InputError, match="centroids_mm"):
        slip_from_poses(Cube(), np.stack([np.eye(3)] * 2), np.zeros((3, 3)))


# --- Scenario and frames -----------------------------------------------------------------------


def small_scenario(**overrides: object) -> Scenario:
    sphere = Sphere()
    pose = rest_pose(sphere, np.eye(3))
    rots, cents = roll_straight(pose, sphere.radius_mm, [1.0, 0.0, 0.0], np.linspace(-3, 3, 7))
    fields: dict[str, object] = {
        "name": "sphere",
        "object_name": "sphere",
        "solid": sphere,
        "rotations": rots,
        "positions_mm": cents[:, :2],
        "rest_height_mm": cents[:, 2],
        "indent_mm": np.array([-0.3, 0.3, 0.3, 0.3, 0.3, 0.3, -0.3]),
        "t_s": np.arange(7) / 20.0,
        "phase": ("lifted", *["rolling"] * 5, "lifted"),
    }
    fields.update(overrides)
    return Scenario(**fields)  # type: ignore[arg-type]


def test_scenario_validates_and_freezes_its_arrays() -> None:
    sc = small_scenario()
    assert sc.n_frames == 7 and sc.rate_hz == pytest.approx(20.0)
    assert sc.contact == ("none", *["point"] * 5, "none")
    assert sc.phase_runs() == (("lifted", 0, 1), ("rolling", 1, 6), ("lifted", 6, 7))
    assert sc.centroids_mm.shape == (7, 3)
    np.testing.assert_array_equal(sc.in_contact, [False] + [True] * 5 + [False])
    slip = sc.slip_mm()
    assert np.isnan(slip[0]) and np.isnan(slip[-1])
    dth = 1.0 / 6.0  # 1 mm per frame on a 6 mm sphere: a cycloid's cusp
    np.testing.assert_allclose(slip[1:-1], 6.0 * (dth - math.sin(dth)), rtol=1e-6)
    with pytest.raises(ValueError):
        sc.indent_mm[0] = 1.0
    assert sc.equals(small_scenario()) and not sc.equals(small_scenario(slides=True))
    with pytest.raises(InputError, match="phase"):
        small_scenario(phase=("rolling",) * 6)
    with pytest.raises(InputError, match="unknown phase"):
        small_scenario(phase=("bouncing",) * 7)
    with pytest.raises(InputError, match="t_s"):
        small_scenario(t_s=np.zeros(7))
    with pytest.raises(InputError, match="positions_mm"):
        small_scenario(positions_mm=np.zeros((6, 2)))
    with pytest.raises(InputError, match="indent_mm"):
        small_scenario(indent_mm=np.full(7, np.nan))
    assert set(PHASES) >= {"lifted", "face", "edge", "vertex", "side", "rim", "apex"}


def test_frames_from_scenario_shape_units_and_seeding() -> None:
    sc = small_scenario()
    rec = frames_from_scenario(BONNEVILLE_16X16, sc, rng=3)
    assert isinstance(rec, TactileFrames)
    assert rec.shape == (7, 16, 16) and rec.units == "mm"
    assert rec.pitch_mm == pytest.approx(28.2 / 16) and rec.sensor == "bonneville-16x16"
    np.testing.assert_array_equal(rec.t_s, sc.t_s)
    assert rec.equals(frames_from_scenario(BONNEVILLE_16X16, sc, rng=3))
    clean = frames_from_scenario(BONNEVILLE_16X16, sc, add_noise=False).frames
    assert np.all(clean[[0, -1]] == 0.0)  # lifted: nothing
    # pressed 0.3 mm: the deepest taxel reads about the indentation
    assert 0.2 < clean[1:-1].max() <= 0.3 + 1e-6
    contact = BONNEVILLE_16X16.contact_from_displacement(clean)
    assert all(1 <= contact[t].sum() <= 9 for t in range(1, 6))
    # the blob moves with the sphere: 1 mm per frame along +x
    cols = [np.nonzero(contact[t])[1].mean() for t in range(1, 6)]
    assert np.all(np.diff(cols) >= 0) and cols[-1] - cols[0] > 1.0


def test_a_face_a_few_micrometres_out_of_level_is_a_face_with_physics_tolerances() -> None:
    """A physics engine's resting face is level only to micrometres (MuJoCo's soft contacts).

    The exact poses' tie (1e-6 mm) keeps only the lowest rim points of a disc
    tilted by 0.2 mrad (its rim 2.8 um out of level): a point or, here, the
    lowest point and its rim sample, a line. The physics tolerances that a
    MuJoCo scenario carries see the face.
    """
    tilt = matrix_from_axis_angle([1.0, 0.0, 0.0], 2e-4)
    rots = np.repeat(tilt[None], 3, axis=0)
    fields = {
        "name": "cylinder",
        "object_name": "cylinder",
        "solid": Cylinder(),
        "rotations": rots,
        "positions_mm": np.zeros((3, 2)),
        "rest_height_mm": np.full(3, 5.0),
        "indent_mm": np.full(3, 0.3),
        "t_s": np.arange(3) / 20.0,
        "phase": ("face",) * 3,
    }
    exact = Scenario(**fields)  # type: ignore[arg-type]
    assert exact.contact == ("line",) * 3
    physics = Scenario(**fields, contact_tie_mm=0.02, contact_spread_mm=1.0)  # type: ignore[arg-type]
    assert physics.contact == ("area",) * 3
    assert contact_types(Cylinder(), rots, tie_mm=0.02, spread_mm=1.0) == physics.contact
    with pytest.raises(InputError, match="contact_tie_mm"):
        Scenario(**fields, contact_tie_mm=0.0)  # type: ignore[arg-type]
