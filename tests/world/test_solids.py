"""Checks of the analytic solids of paper 001 and of convex mesh solids.

References used here are independent of the library's formulas: closed forms,
point-in-body tests with bisection along each vertical line, and vertical ray
casting on the tessellated meshes (``to_trimesh``). trimesh's own ray module
needs ``rtree``, which is not a dependency, so the ray casting is written out
below (barycentric coordinates of the line in each triangle's projection).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from taxelkit.errors import (
    CorruptRecordingError,
    InputError,
    RecordingNotFoundError,
    UnsupportedFormatError,
)
from taxelkit.sensors.array_geometry import TaxelArray
from taxelkit.sensors.noise import NoiseModel
from taxelkit.sensors.presets import BONNEVILLE_16X16, Sensor
from taxelkit.sensors.press import displacement_from_solid
from taxelkit.sensors.skin import SkinModel
from taxelkit.world.base import Solid
from taxelkit.world.mesh_solid import MeshSolid, load_mesh_solid
from taxelkit.world.pose import matrix_from_axis_angle
from taxelkit.world.solids import (
    DEFAULT_CONE_HEIGHT_MM,
    DEFAULT_CONE_RADIUS_MM,
    DEFAULT_CUBE_EDGE_MM,
    DEFAULT_CYLINDER_HEIGHT_MM,
    DEFAULT_CYLINDER_RADIUS_MM,
    DEFAULT_SPHERE_RADIUS_MM,
    DEFAULT_TETRAHEDRON_EDGE_MM,
    DEFAULT_TRUNCATED_CONE_BOTTOM_RADIUS_MM,
    DEFAULT_TRUNCATED_CONE_HEIGHT_MM,
    DEFAULT_TRUNCATED_CONE_TOP_RADIUS_MM,
    SOLID_NAMES,
    AnalyticSolid,
    Cone,
    Cube,
    Cylinder,
    Sphere,
    Tetrahedron,
    TruncatedCone,
    make_solid,
    solid_size_names,
)
from taxelkit.world.solids_round import DEFAULT_SECTIONS

Arr = NDArray[np.float64]

#: Every analytic solid at its default size, plus a frustum that widens upwards.
ALL_SOLIDS: list[Any] = [
    Cube(),
    Sphere(),
    Cone(),
    TruncatedCone(),
    TruncatedCone(bottom_radius_mm=3.5, top_radius_mm=7.0, height_mm=12.0),
    Cylinder(),
    Tetrahedron(),
]
IDS = ["cube", "sphere", "cone", "frustum", "frustum-up", "cylinder", "tetrahedron"]


def _rot(axis: list[float], angle: float) -> Arr:
    return matrix_from_axis_angle(axis, angle)


def _random_rotations(rng: np.random.Generator, n: int) -> Arr:
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return matrix_from_axis_angle(q[:, :3], 2.0 * np.arccos(np.clip(q[:, 3], -1.0, 1.0)))


def _bottom(solid: Any, rot: Arr, x: Arr, y: Arr, dtype: Any = np.float64) -> Arr:
    """Bottom of one pose on the grid ``x`` (columns) by ``y`` (rows)."""
    out = solid.bottom_mm(rot[None], x[None].astype(dtype), y[None].astype(dtype))
    return np.asarray(out[0], dtype=np.float64)


# --- independent references -------------------------------------------------------


def _inside(solid: Any) -> Callable[[Arr], NDArray[np.bool_]]:
    """Point-in-body test in the body frame, written from the definitions."""
    if isinstance(solid, Cube):
        return lambda p: np.abs(p).max(axis=-1) <= solid.edge_mm / 2
    if isinstance(solid, Sphere):
        return lambda p: (p**2).sum(axis=-1) <= solid.radius_mm**2
    if isinstance(solid, Cylinder):
        r, h = solid.radius_mm, solid.height_mm
        return lambda p: (np.abs(p[..., 2]) <= h / 2) & (p[..., 0] ** 2 + p[..., 1] ** 2 <= r**2)
    if isinstance(solid, Tetrahedron):
        verts = solid.vertices_mm
        # Barycentric coordinates w.r.t. the four vertices must all be >= 0.
        t = np.linalg.inv(np.c_[verts[:3] - verts[3]].T)
        return lambda p: ((lam := (p - verts[3]) @ t.T) >= 0).all(axis=-1) & (lam.sum(axis=-1) <= 1)
    if isinstance(solid, Cone | TruncatedCone):
        r1 = solid.radius_mm if isinstance(solid, Cone) else solid.bottom_radius_mm
        r2 = 0.0 if isinstance(solid, Cone) else solid.top_radius_mm
        h = solid.height_mm
        z_c = h * (r1**2 + 2 * r1 * r2 + 3 * r2**2) / (4 * (r1**2 + r1 * r2 + r2**2))

        def inside(p: Arr) -> NDArray[np.bool_]:
            s = p[..., 2] + z_c  # height above the base
            radius = r1 + (r2 - r1) * s / h
            return (s >= 0) & (s <= h) & (np.hypot(p[..., 0], p[..., 1]) <= radius)

        return inside
    raise AssertionError(solid)


def _bottom_by_bisection(
    solid: Any, rot: Arr, x: Arr, y: Arr, *, n_z: int = 1501, z_range: float = 30.0
) -> Arr:
    """Lowest inside point on each vertical line: dense scan, then 60 bisections."""
    inside = _inside(solid)
    gx, gy = np.meshgrid(x, y)
    px, py = gx.ravel(), gy.ravel()
    zs = np.linspace(-z_range, z_range, n_z)
    pts = np.stack(np.broadcast_arrays(px[:, None], py[:, None], zs[None, :]), axis=-1)
    hits = inside(pts @ rot)  # body frame: R^T p
    first = hits.argmax(axis=1)
    lo = zs[np.maximum(first - 1, 0)]
    hi = zs[first]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        ok = inside(np.stack([px, py, mid], axis=-1) @ rot)
        hi = np.where(ok, mid, hi)
        lo = np.where(ok, lo, mid)
    return np.where(hits.any(axis=1), hi, np.inf).reshape(y.size, x.size)


def _ray_cast_bottom(mesh: trimesh.Trimesh, rot: Arr, x: Arr, y: Arr) -> tuple[Arr, Arr]:
    """First hit of upward vertical rays with the rotated mesh, and the face's n_z."""
    tri = np.asarray(mesh.triangles) @ rot.T
    nz = (np.asarray(mesh.face_normals) @ rot.T)[:, 2]
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    det = (b[:, 1] - c[:, 1]) * (a[:, 0] - c[:, 0]) + (c[:, 0] - b[:, 0]) * (a[:, 1] - c[:, 1])
    keep = (nz < 0) & (np.abs(det) > 1e-12)  # faces seen from below
    a, b, c, det, nz = a[keep], b[keep], c[keep], det[keep], nz[keep]
    gx, gy = np.meshgrid(x, y)
    px, py = gx.ravel()[:, None], gy.ravel()[:, None]
    l1 = ((b[:, 1] - c[:, 1]) * (px - c[:, 0]) + (c[:, 0] - b[:, 0]) * (py - c[:, 1])) / det
    l2 = ((c[:, 1] - a[:, 1]) * (px - c[:, 0]) + (a[:, 0] - c[:, 0]) * (py - c[:, 1])) / det
    l3 = 1.0 - l1 - l2
    z = np.where(
        (l1 >= 0) & (l2 >= 0) & (l3 >= 0), l1 * a[:, 2] + l2 * b[:, 2] + l3 * c[:, 2], np.inf
    )
    k = z.argmin(axis=1)
    rows = np.arange(z.shape[0])
    shape = (y.size, x.size)
    return z[rows, k].reshape(shape), nz[k].reshape(shape)


def _sagitta_mm(solid: Any, mesh: trimesh.Trimesh) -> float:
    """Largest distance between the inscribed mesh and the true surface."""
    if isinstance(solid, Sphere):
        planes = np.einsum("fi,fi->f", mesh.face_normals, mesh.triangles[:, 0])
        return float(solid.radius_mm - planes.min())
    if isinstance(solid, Cube | Tetrahedron):
        return 0.0
    r_max = max(r for _, r in solid.profile.rims)
    return float(r_max * (1.0 - math.cos(math.pi / DEFAULT_SECTIONS)))


def _lowest_point_xy(solid: Any, rot: Arr) -> Arr:
    """Horizontal position of a lowest point, from the geometry (not the library)."""
    if isinstance(solid, Sphere):
        return np.zeros(2)
    if isinstance(solid, Cube | Tetrahedron):
        v = solid.vertices_mm @ rot.T
        return np.asarray(v[v[:, 2].argmin(), :2])
    axis = rot[:, 2]
    best, best_z = np.zeros(2), np.inf
    for z_rim, r_rim in solid.profile.rims:
        centre = z_rim * axis
        up = np.array([0.0, 0.0, 1.0]) - axis[2] * axis  # steepest ascent within the rim plane
        norm = np.linalg.norm(up)
        point = centre - r_rim * up / norm if norm > 1e-12 and r_rim > 0 else centre
        if point[2] < best_z:
            best, best_z = point[:2], point[2]
    return best


# --- registry ----------------------------------------------------------------------


def test_registry_names_classes_and_defaults() -> None:
    assert SOLID_NAMES == ("cube", "sphere", "cone", "truncated-cone", "cylinder", "tetrahedron")
    for name in SOLID_NAMES:
        solid = make_solid(name)
        assert solid.name == name
        assert isinstance(solid, Solid)
        assert isinstance(solid, AnalyticSolid)
    assert make_solid("cube") == Cube(DEFAULT_CUBE_EDGE_MM)
    assert make_solid("sphere") == Sphere(DEFAULT_SPHERE_RADIUS_MM)
    assert make_solid("cylinder") == Cylinder(
        DEFAULT_CYLINDER_RADIUS_MM, DEFAULT_CYLINDER_HEIGHT_MM
    )
    assert make_solid("cone") == Cone(DEFAULT_CONE_RADIUS_MM, DEFAULT_CONE_HEIGHT_MM)
    assert make_solid("tetrahedron") == Tetrahedron(DEFAULT_TETRAHEDRON_EDGE_MM)
    assert make_solid("truncated-cone") == TruncatedCone(
        DEFAULT_TRUNCATED_CONE_BOTTOM_RADIUS_MM,
        DEFAULT_TRUNCATED_CONE_TOP_RADIUS_MM,
        DEFAULT_TRUNCATED_CONE_HEIGHT_MM,
    )
    assert solid_size_names("truncated-cone") == (
        "bottom_radius_mm",
        "top_radius_mm",
        "height_mm",
    )


def test_make_solid_scale_and_overrides() -> None:
    assert make_solid("cylinder", scale=0.5, height_mm=10.0) == Cylinder(2.5, 5.0)
    assert make_solid("cube", edge_mm=3.0) == Cube(3.0)


def test_make_solid_rejects_bad_input() -> None:
    with pytest.raises(InputError, match="known solids: cube, sphere, cone"):
        make_solid("pyramid")
    with pytest.raises(InputError, match="valid sizes: radius_mm"):
        make_solid("sphere", edge_mm=3.0)
    with pytest.raises(InputError, match="scale"):
        make_solid("sphere", scale=0.0)
    with pytest.raises(InputError, match="radius_mm"):
        make_solid("sphere", radius_mm=-1.0)
    with pytest.raises(InputError, match="Cylinder"):
        TruncatedCone(4.0, 4.0, 3.0)
    with pytest.raises(InputError, match="edge_mm"):
        Cube(float("nan"))


def test_bottom_validates_shapes_and_values() -> None:
    cube = Cube()
    x = np.zeros((2, 5))
    with pytest.raises(InputError, match="rotations"):
        cube.bottom_mm(np.eye(2)[None], x, x)
    with pytest.raises(InputError, match=r"x_mm must have shape \(1, W\)"):
        cube.bottom_mm(np.eye(3), x, x[:1])
    with pytest.raises(InputError, match="y_mm"):
        cube.bottom_mm(np.eye(3)[None].repeat(2, 0), x, x[0])
    bad = x.copy()
    bad[1, 3] = np.nan
    with pytest.raises(InputError, match="x_mm must be finite"):
        Sphere().bottom_mm(np.eye(3)[None].repeat(2, 0), bad, x)
    with pytest.raises(InputError, match="rotations must be finite"):
        cube.lowest_z_mm(np.full((1, 3, 3), np.inf))


# --- closed forms ------------------------------------------------------------------


@pytest.mark.parametrize("depth_mm", [0.05, 0.3, 1.2])
def test_pressed_sphere_contact_radius(depth_mm: float) -> None:
    """Penetration sqrt(R^2 - r^2) - (R - d) inside r <= sqrt(2 R d - d^2), zero outside."""
    radius = 6.0
    fine = Sensor(
        name="fine",
        array=TaxelArray(rows=72, cols=72, pitch_mm=0.125, element_size_mm=0.125),
        skin=SkinModel(spread_mm=0.0),
        noise=NoiseModel(),
        contact_threshold_mm=1e-9,
        max_rate_hz=100.0,
    )
    u = displacement_from_solid(
        fine,
        Sphere(radius),
        np.eye(3),
        [0.03, -0.02],
        indent_mm=depth_mm,
        add_noise=False,
        dtype=np.float64,
    )[0]
    xc, yc = fine.array.centre_offsets_mm(margin=0)
    r = np.hypot(*np.meshgrid(xc - 0.03, yc + 0.02))
    expected = np.maximum(np.sqrt(np.maximum(radius**2 - r**2, 0.0)) - (radius - depth_mm), 0.0)
    np.testing.assert_allclose(u, expected, atol=1e-12)
    a = math.sqrt(2 * radius * depth_mm - depth_mm**2)
    contact = fine.contact_from_displacement(u)
    assert r[contact].max() < a <= r[~contact].min()


def test_cube_face_down_is_flat_with_square_footprint() -> None:
    edge = 12.0
    x = np.linspace(-9.0, 9.0, 37) + 0.0123  # no point on a face plane
    b = _bottom(Cube(edge), np.eye(3), x, x)
    inside = (np.abs(x)[None, :] < edge / 2) & (np.abs(x)[:, None] < edge / 2)
    np.testing.assert_array_equal(b[inside], -edge / 2)
    assert np.all(np.isposinf(b[~inside]))
    assert Cube(edge).lowest_z_mm(np.eye(3)[None])[0] == pytest.approx(-edge / 2)


def test_cube_on_a_vertex() -> None:
    edge = 12.0
    # Rotate the body diagonal (1, 1, 1) onto -z.
    d = np.array([1.0, 1.0, 1.0]) / math.sqrt(3)
    axis = np.cross(d, [0.0, 0.0, -1.0])
    rot = _rot(list(axis), math.acos(-d[2]))
    np.testing.assert_allclose(rot @ d, [0, 0, -1], atol=1e-12)
    lowest = Cube(edge).lowest_z_mm(rot[None])[0]
    assert lowest == pytest.approx(-edge * math.sqrt(3) / 2, abs=1e-12)
    b = _bottom(Cube(edge), rot, np.array([0.0]), np.array([0.0]))
    assert b[0, 0] == pytest.approx(lowest, abs=1e-12)
    # Near the vertex the three faces rise at arctan(sqrt(2)) from horizontal.
    r = 0.5
    ring = _bottom(Cube(edge), rot, np.array([r]), np.array([0.0]))[0, 0]
    assert lowest < ring <= lowest + r * math.sqrt(2) + 1e-12


def test_cylinder_on_its_side_touches_along_a_generator() -> None:
    r, h = 5.0, 16.0
    rot = _rot([1.0, 0.0, 0.0], math.pi / 2)  # axis along -y
    x = np.linspace(-7.0, 7.0, 29) + 0.0123
    y = np.linspace(-10.0, 10.0, 41) + 0.0071
    b = _bottom(Cylinder(r, h), rot, x, y)
    inside = (np.abs(x)[None, :] < r) & (np.abs(y)[:, None] < h / 2)
    expected = np.where(inside, -np.sqrt(np.maximum(r**2 - x[None, :] ** 2, 0.0)), np.inf)
    np.testing.assert_allclose(b, expected, atol=1e-12)
    line = _bottom(Cylinder(r, h), rot, np.array([0.0]), y)[:, 0]
    np.testing.assert_allclose(line[np.abs(y) < h / 2], -r, atol=1e-12)
    assert Cylinder(r, h).lowest_z_mm(rot[None])[0] == pytest.approx(-r)


def test_cone_on_its_side_touches_along_a_generator() -> None:
    r, h = 6.0, 14.0
    cone = Cone(r, h)
    alpha = math.atan2(r, h)
    rot = _rot([0.0, 1.0, 0.0], math.pi / 2 + alpha)  # axis (base -> apex) dips by alpha
    lowest = cone.lowest_z_mm(rot[None])[0]
    apex = rot @ np.array([0.0, 0.0, 0.75 * h])
    rim = rot @ np.array([r, 0.0, -0.25 * h])
    assert apex[2] == pytest.approx(lowest, abs=1e-12)
    assert rim[2] == pytest.approx(lowest, abs=1e-12)
    # Along the generator (y = 0) the bottom is flat between apex and rim ...
    x = np.linspace(min(apex[0], rim[0]) + 0.01, max(apex[0], rim[0]) - 0.01, 50)
    np.testing.assert_allclose(_bottom(cone, rot, x, np.array([0.0]))[0], lowest, atol=1e-9)
    # ... and it rises on both sides of it and beyond its ends.
    side = _bottom(cone, rot, x, np.array([-0.2, 0.2]))
    assert np.all(side > lowest + 1e-6)
    beyond = _bottom(cone, rot, np.array([rim[0] - 0.05]), np.array([0.0]))
    assert beyond[0, 0] > lowest + 1e-6
    assert math.hypot(*(apex - rim)) == pytest.approx(math.hypot(r, h))


def test_tetrahedron_resting_on_a_face() -> None:
    tet = Tetrahedron(16.0)
    h = tet.height_mm
    assert h == pytest.approx(16.0 * math.sqrt(2 / 3))
    x = np.linspace(-10.0, 10.0, 41) + 0.0123
    b = _bottom(tet, np.eye(3), x, x)
    base = tet.vertices_mm[:3, :2]
    gx, gy = np.meshgrid(x, x)
    pts = np.stack([gx, gy], axis=-1)
    lam = np.linalg.solve((base[:2] - base[2]).T, (pts - base[2]).reshape(-1, 2).T).T
    inside = ((lam >= 0).all(axis=1) & (lam.sum(axis=1) <= 1)).reshape(gx.shape)
    np.testing.assert_allclose(b[inside], -h / 4, atol=1e-12)
    assert np.all(np.isposinf(b[~inside]))
    assert tet.lowest_z_mm(np.eye(3)[None])[0] == pytest.approx(-h / 4)
    np.testing.assert_allclose(tet.planes[1], h / 4)


def test_upside_down_cone_is_a_point_contact() -> None:
    cone = Cone(6.0, 14.0)
    rot = _rot([1.0, 0.0, 0.0], math.pi)
    b = _bottom(cone, rot, np.array([0.0, 0.5, 1.0]), np.array([0.0]))[0]
    apex_z = -0.75 * 14.0
    np.testing.assert_allclose(b, apex_z + np.array([0.0, 0.5, 1.0]) * 14.0 / 6.0, atol=1e-12)
    assert cone.lowest_z_mm(rot[None])[0] == pytest.approx(apex_z)


# --- consistency and invariances ---------------------------------------------------


rotation_strategy = st.tuples(
    st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1), st.floats(-1, 1)
).filter(lambda q: sum(c * c for c in q) > 1e-3)


def _rotation_from(q: tuple[float, float, float, float]) -> Arr:
    v = np.array(q) / np.linalg.norm(q)
    axis = v[:3] if np.linalg.norm(v[:3]) > 1e-9 else np.array([0.0, 0.0, 1.0])
    return matrix_from_axis_angle(axis, 2.0 * math.acos(min(1.0, abs(v[3]))))


@pytest.mark.parametrize("solid", ALL_SOLIDS, ids=IDS)
@settings(max_examples=25, deadline=None)
@given(q=rotation_strategy)
def test_lowest_z_is_the_minimum_of_the_bottom(solid: Any, q: Any) -> None:
    rot = _rotation_from(q)
    lowest = solid.lowest_z_mm(rot[None])[0]
    x = np.linspace(-16.0, 16.0, 65)
    b = _bottom(solid, rot, x, x)
    assert np.isfinite(b).any()
    assert lowest <= b.min() + 1e-9  # nothing lies below the lowest point
    # The segment from the lowest point p to the centroid (the origin) lies in
    # the body, so the line through (1 - t) p_xy meets the body at or below
    # (1 - t) p_z, and never below the lowest point.
    t = 1e-6
    p = (1.0 - t) * _lowest_point_xy(solid, rot)
    at = _bottom(solid, rot, p[:1], p[1:])[0, 0]
    assert lowest - 1e-9 <= at <= (1.0 - t) * lowest + 1e-9
    assert b.min() - lowest < 1.5  # the grid (0.5 mm pitch) passes near it


@pytest.mark.parametrize("solid", ALL_SOLIDS, ids=IDS)
def test_agrees_with_ray_casting_on_the_tessellated_mesh(solid: Any) -> None:
    rng = np.random.default_rng(7)
    mesh = solid.to_trimesh()
    sag = _sagitta_mm(solid, mesh)
    x = np.linspace(-14.0, 14.0, 43) + 0.0123
    for rot in [np.eye(3), *_random_rotations(rng, 5)]:
        ref, nz = _ray_cast_bottom(mesh, rot, x, x)
        got = _bottom(solid, rot, x, x)
        hit = np.isfinite(ref)
        # The inscribed mesh lies inside the body: every ray that hits the mesh
        # hits the body at or below it.
        assert np.all(got[hit] <= ref[hit] + 1e-9)
        # Where the surface is not steep, the gap is at most the sagitta over |n_z|.
        flat = hit & (nz < -0.3)
        assert np.all(ref[flat] - got[flat] <= sag / np.abs(nz[flat]) + 1e-9)
        # Hit/miss differs only in the thin band between mesh and surface.
        assert np.mean(np.isfinite(got) != hit) < 0.01


SPECIAL_ROTATIONS: list[Arr] = [
    _rot([1.0, 0.3, 0.0], a)
    for a in (0.0, 1e-12, 1e-6, 0.1, math.pi / 2, math.pi / 2 - 1e-9, math.pi - 1e-8, math.pi)
]


@pytest.mark.parametrize("solid", ALL_SOLIDS, ids=IDS)
def test_degenerate_poses_match_bisection(solid: Any) -> None:
    """Upright, lying and tilted-by-a-hair poses (and a vertical cone generator)."""
    rotations = list(SPECIAL_ROTATIONS)
    if isinstance(solid, Cone | TruncatedCone):
        alpha = math.asin(math.sqrt(solid.profile.sin2))  # vertical generator at these tilts
        rotations += [_rot([0.0, 1.0, 0.0], alpha + e) for e in (0.0, 1e-9, 1e-3)]
        rotations += [_rot([0.0, 1.0, 0.0], math.pi - alpha)]
    x = np.linspace(-14.0, 14.0, 21) + 0.0123
    for rot in rotations:
        ref = _bottom_by_bisection(solid, rot, x, x)
        lowest = solid.lowest_z_mm(rot[None])[0]
        for dtype, tol in ((np.float64, 1e-9), (np.float32, 1e-4)):
            got = _bottom(solid, rot, x, x, dtype)
            near = np.isfinite(ref) & (ref < lowest + 1.0)  # where contact happens
            np.testing.assert_allclose(got[near], ref[near], atol=tol)
            assert np.mean(np.isfinite(got) != np.isfinite(ref)) < 0.01


@pytest.mark.parametrize("tilt", [1e-9, 1e-6, 1e-3, 0.05, 0.3])
def test_cylinder_wall_near_upright(tilt: float) -> None:
    """Lines just inside and just outside the wall of a slightly tilted cylinder."""
    cyl = Cylinder(5.0, 16.0)
    rot = _rot([1.0, 0.0, 0.0], tilt)
    # Where the wall meets the bottom cap on the y axis (body frame -> sensor frame).
    foot = rot @ np.array([0.0, 5.0, -8.0])
    y = foot[1] + np.array([-1e-3, -2e-4, 2e-4, 1e-3])
    x = np.array([0.0])
    ref = _bottom_by_bisection(cyl, rot, x, y, n_z=200_001, z_range=10.0)  # 1e-4 mm steps
    assert np.isfinite(ref[:2]).all() and np.isinf(ref[2:]).all()
    got = _bottom(cyl, rot, x, y)
    np.testing.assert_array_equal(np.isfinite(got), np.isfinite(ref))
    np.testing.assert_allclose(got[np.isfinite(ref)], ref[np.isfinite(ref)], atol=1e-9)


@pytest.mark.parametrize("solid", ALL_SOLIDS, ids=IDS)
def test_rotation_about_the_vertical_axis(solid: Any) -> None:
    rng = np.random.default_rng(3)
    rot = _random_rotations(rng, 1)[0]
    phi = 0.7
    rz = _rot([0.0, 0.0, 1.0], phi)
    pts = rng.uniform(-9.0, 9.0, size=(400, 2))
    rotated = pts @ rz[:2, :2].T
    many = np.repeat(rot[None], 400, axis=0)
    b = solid.bottom_mm(many, pts[:, :1], pts[:, 1:])
    b_rot = solid.bottom_mm(rz @ many, rotated[:, :1], rotated[:, 1:])
    assert np.isfinite(b).sum() > 20
    np.testing.assert_allclose(b_rot, b, atol=1e-9)
    assert solid.lowest_z_mm((rz @ rot)[None])[0] == pytest.approx(solid.lowest_z_mm(rot[None])[0])


@pytest.mark.parametrize("solid", ALL_SOLIDS, ids=IDS)
def test_batch_equals_pose_by_pose(solid: Any) -> None:
    """Mixed pose cases in one batch (grouped internally) and per-pose grids."""
    rng = np.random.default_rng(5)
    rots = np.concatenate([_random_rotations(rng, 30), np.stack(SPECIAL_ROTATIONS)])
    n = rots.shape[0]
    x = np.linspace(-12.0, 12.0, 13)[None] + rng.uniform(-3, 3, size=(n, 1))
    y = np.linspace(-11.0, 11.0, 11)[None] + rng.uniform(-3, 3, size=(n, 1))
    batch = solid.bottom_mm(rots, x, y)
    single = np.concatenate(
        [solid.bottom_mm(rots[i : i + 1], x[i : i + 1], y[i : i + 1]) for i in range(n)]
    )
    np.testing.assert_allclose(batch, single, atol=1e-9)
    # Grids that are not translates of one another take the general path.
    x_warped = x * rng.uniform(0.8, 1.2, size=(n, 1))
    general = solid.bottom_mm(rots, x_warped, y)
    single = np.concatenate(
        [solid.bottom_mm(rots[i : i + 1], x_warped[i : i + 1], y[i : i + 1]) for i in range(n)]
    )
    np.testing.assert_allclose(general, single, atol=1e-9)
    assert solid.lowest_z_mm(rots).shape == (n,)


@pytest.mark.parametrize("solid", ALL_SOLIDS, ids=IDS)
def test_shifting_the_pose_by_one_pitch_shifts_the_frame(solid: Any) -> None:
    rng = np.random.default_rng(9)
    rots = _random_rotations(rng, 8)
    pos = rng.uniform(-3.0, 3.0, size=(8, 2))
    pitch = BONNEVILLE_16X16.array.pitch_mm
    kw: dict[str, Any] = {"indent_mm": 0.4, "add_noise": False}
    u = displacement_from_solid(BONNEVILLE_16X16, solid, rots, pos, **kw)
    u_x = displacement_from_solid(BONNEVILLE_16X16, solid, rots, pos + np.array([pitch, 0.0]), **kw)
    u_y = displacement_from_solid(BONNEVILLE_16X16, solid, rots, pos + np.array([0.0, pitch]), **kw)
    assert u.max() > 0.1
    np.testing.assert_allclose(u_x[:, :, 1:], u[:, :, :-1], atol=1e-5)
    np.testing.assert_allclose(u_y[:, 1:, :], u[:, :-1, :], atol=1e-5)


@pytest.mark.parametrize("solid", ALL_SOLIDS, ids=IDS)
def test_float32_and_float64_agree(solid: Any) -> None:
    rng = np.random.default_rng(11)
    n = 300
    rots = _random_rotations(rng, n)
    pos = rng.uniform(-5.0, 5.0, size=(n, 2))
    kw: dict[str, Any] = {"indent_mm": rng.uniform(0.05, 0.5, n), "add_noise": False}
    u32 = displacement_from_solid(BONNEVILLE_16X16, solid, rots, pos, **kw)
    u64 = displacement_from_solid(BONNEVILLE_16X16, solid, rots, pos, dtype=np.float64, **kw)
    assert u32.dtype == np.float32 and u64.dtype == np.float64
    assert (u64 > BONNEVILLE_16X16.contact_threshold_mm).sum() > 50
    np.testing.assert_allclose(u32, u64, atol=1e-4)
    x = np.zeros((1, 4), dtype=np.float32)
    assert solid.bottom_mm(np.eye(3)[None], x, x).dtype == np.float32
    assert solid.bottom_mm(np.eye(3)[None], x.astype(int), x).dtype == np.float64


@pytest.mark.parametrize("solid", ALL_SOLIDS, ids=IDS)
def test_tessellation_is_a_closed_convex_body_about_the_centroid(solid: Any) -> None:
    mesh = solid.to_trimesh()
    assert mesh.is_watertight and mesh.is_convex
    np.testing.assert_allclose(mesh.center_mass, 0.0, atol=0.02)


def test_empty_batches() -> None:
    for solid in ALL_SOLIDS:
        assert solid.bottom_mm(np.zeros((0, 3, 3)), np.zeros((0, 5)), np.zeros((0, 4))).shape == (
            0,
            4,
            5,
        )
        assert solid.lowest_z_mm(np.zeros((0, 3, 3))).shape == (0,)


# --- meshes --------------------------------------------------------------------------


@pytest.mark.parametrize("suffix", ["stl", "obj"])
def test_mesh_file_cube_matches_the_analytic_cube(tmp_path: Path, suffix: str) -> None:
    edge = 10.0
    box = trimesh.creation.box(extents=(edge, edge, edge))
    box.apply_translation([3.0, -2.0, 5.0])  # the reference point is the centroid
    path = tmp_path / f"cube.{suffix}"
    box.export(path)
    solid = load_mesh_solid(path)
    assert solid.label == f"cube.{suffix}" and solid.name == "mesh"
    assert solid.normals.shape == (6, 3)  # 12 triangles merged into 6 planes
    assert isinstance(solid, Solid)
    rng = np.random.default_rng(2)
    rots = np.concatenate([np.eye(3)[None], _random_rotations(rng, 6)])
    x = np.tile(np.linspace(-9.0, 9.0, 25) + 0.0123, (7, 1))
    np.testing.assert_allclose(
        solid.bottom_mm(rots, x, x), Cube(edge).bottom_mm(rots, x, x), atol=1e-9
    )
    np.testing.assert_allclose(solid.lowest_z_mm(rots), Cube(edge).lowest_z_mm(rots), atol=1e-12)


def test_mesh_scale_and_general_convex_mesh(tmp_path: Path) -> None:
    ico = trimesh.creation.icosphere(subdivisions=1, radius=0.5)
    solid = MeshSolid.from_trimesh(ico, scale=10.0)
    rng = np.random.default_rng(4)
    x = np.linspace(-6.0, 6.0, 31) + 0.0123
    ref_mesh = solid.to_trimesh()
    for rot in _random_rotations(rng, 3):
        ref, _ = _ray_cast_bottom(ref_mesh, rot, x, x)
        got = _bottom(solid, rot, x, x)
        both = np.isfinite(ref) & np.isfinite(got)
        np.testing.assert_allclose(got[both], ref[both], atol=1e-9)
        assert np.mean(np.isfinite(got) != np.isfinite(ref)) < 0.005


def test_non_convex_and_open_meshes_are_rejected_unless_hull_requested(tmp_path: Path) -> None:
    ring = trimesh.creation.annulus(r_min=2.0, r_max=5.0, height=3.0)
    with pytest.raises(InputError, match="not convex; pass convex_hull=True"):
        MeshSolid.from_trimesh(ring)
    hull = MeshSolid.from_trimesh(ring, convex_hull=True)
    assert hull.lowest_z_mm(np.eye(3)[None])[0] == pytest.approx(-1.5)
    box = trimesh.creation.box(extents=(2.0, 2.0, 2.0))
    opened = trimesh.Trimesh(box.vertices, box.faces[:-2])
    path = tmp_path / "open.stl"
    opened.export(path)
    with pytest.raises(InputError, match="not watertight"):
        load_mesh_solid(path)
    assert load_mesh_solid(path, convex_hull=True).normals.shape == (6, 3)


@pytest.mark.parametrize(
    ("content", "suffix"),
    [(b"", "stl"), (b"", "obj"), (b"garbage " * 20, "stl"), (b"solid x\nfacet", "stl")],
)
def test_unreadable_mesh_files_raise_typed_errors(
    tmp_path: Path, content: bytes, suffix: str
) -> None:
    path = tmp_path / f"bad.{suffix}"
    path.write_bytes(content)
    with pytest.raises(CorruptRecordingError, match="bad"):
        load_mesh_solid(path)


def test_truncated_and_missing_and_unsupported_mesh_files(tmp_path: Path) -> None:
    path = tmp_path / "cube.stl"
    trimesh.creation.box(extents=(1.0, 1.0, 1.0)).export(path)
    truncated = tmp_path / "truncated.stl"
    truncated.write_bytes(path.read_bytes()[:300])
    with pytest.raises(CorruptRecordingError) as info:
        load_mesh_solid(truncated)
    assert "\n" not in str(info.value)
    with pytest.raises(RecordingNotFoundError, match="no such mesh file"):
        load_mesh_solid(tmp_path / "nothing.stl")
    other = tmp_path / "cube.txt"
    other.write_text("hello")
    with pytest.raises(UnsupportedFormatError, match="stl, obj"):
        load_mesh_solid(other)


def test_mesh_solid_validates_its_arrays() -> None:
    cube = Cube(2.0)
    n, b = cube.planes
    with pytest.raises(InputError, match="offsets_mm must be > 0"):
        MeshSolid(cube.vertices_mm, n, b - 5.0)
    with pytest.raises(InputError, match="unit length"):
        MeshSolid(cube.vertices_mm, 2 * n, b)
    with pytest.raises(InputError, match="offsets_mm must have shape"):
        MeshSolid(cube.vertices_mm, n, b[:3])


@pytest.mark.parametrize("name", SOLID_NAMES)
def test_lowest_point_has_the_lowest_z_and_lies_on_the_body(name: str) -> None:
    from taxelkit.world.pose import matrix_from_euler_xyz_deg

    body = make_solid(name)
    rot = matrix_from_euler_xyz_deg(np.random.default_rng(5).uniform(-180, 180, (50, 3)))
    low = body.lowest_point_mm(rot)
    np.testing.assert_allclose(low[:, 2], body.lowest_z_mm(rot), atol=1e-9)
    # vertical lines close to the lowest point meet the body at or above it, and
    # the closer the line, the closer the hit (sharp vertices climb steeply; a
    # narrow vertex is met only in some directions, so probe a ring of them)
    ring = np.exp(2j * np.pi * np.arange(16) / 16)
    for eps, tol in ((1e-3, 0.5), (1e-6, 1e-3)):
        xs = low[:, 0:1] + eps * ring.real[None, :]
        ys = low[:, 1:2] + eps * ring.imag[None, :]
        zb = np.stack(
            [body.bottom_mm(rot, xs[:, d : d + 1], ys[:, d : d + 1])[:, 0, 0] for d in range(16)],
            axis=1,
        )  # fmt: skip
        best = zb.min(axis=1)
        assert np.all(np.isfinite(best))
        assert np.all(zb[np.isfinite(zb)] >= np.repeat(low[:, 2:3], 16, 1)[np.isfinite(zb)] - 1e-9)
        np.testing.assert_allclose(best, low[:, 2], atol=tol)
