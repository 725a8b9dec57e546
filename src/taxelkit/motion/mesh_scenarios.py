"""Randomised motion scripts for a convex mesh (a learnt object), kinematic engine.

The scripts of :mod:`~taxelkit.motion.scenarios` are written for the six
solids; these work for any :class:`~taxelkit.world.mesh_solid.MeshSolid`
from what :func:`~taxelkit.world.mesh_features.mesh_features` found:

=============== ==============================================================
polyhedron      (flat faces only) shows every kind of stable face in turn: it
                starts on a face of a random kind and, for each kind (in a
                random order), tips over polyhedral edges onto the nearest
                stable face of that kind, then tips up onto three different
                edges of that face (or all, if fewer), each time back onto it
                (LC -> AC -> LC with every pair of them)
round, ruled    (a capsule: ruled side and doubly curved caps) lies on its
                side, rolls across its line, rolls up onto a cap and rolls its
                point in two runs at right angles
round           (anything else) rests in its most stable pose found and rolls
                its contact in 2-3 runs joined by right-angle turns
=============== ==============================================================

Rolling a general convex body (:func:`~taxelkit.motion.mesh_roll.roll_path`): small turns about the
horizontal axis ``e_z x d`` through the lowest point farthest along the
direction of travel ``d``: rolling without slip and without spin for a
smooth body, tipping over the front edge for a face, so the same step rolls
a tessellated ellipsoid and tips a prism. Still states, speeds and the fit on
the array follow :mod:`~taxelkit.motion._script`; a body whose round patch
rolls on a point is pressed lightly, as the sphere is
(:data:`~taxelkit.motion.scenarios.SPHERE_MAX_CONTACT_RADIUS_MM`).
"""

from __future__ import annotations

import math
from collections import deque

import numpy as np
from numpy.typing import NDArray

from taxelkit import _fixed_order as fo
from taxelkit.errors import InputError, check_in_range, check_positive
from taxelkit.motion._script import (
    HOLD_FRACTION,
    HOLD_S,
    ROLL_MM_S,
    SPHERE_RUN_MM,
    TIP_DEG_S,
    Builder,
    Draws,
    balance_angle,
    begin_contact,
    bottom_polygon,
    end_contact,
    landing_angle,
    unit_h,
)
from taxelkit.motion.array_placement import EDGE_MARGIN_MM, fit_on_array, yawed
from taxelkit.motion.mesh_roll import roll_path
from taxelkit.motion.roll_paths import rotate_about_line
from taxelkit.motion.rolling import DEFAULT_DEPTH_MM, DEFAULT_RATE_HZ, E_Z, Pose, Scenario
from taxelkit.motion.scenarios import SPHERE_MAX_CONTACT_RADIUS_MM
from taxelkit.sensors.noise import RngLike
from taxelkit.sensors.presets import BONNEVILLE_16X16, Sensor
from taxelkit.world.mesh_features import MeshFeatures
from taxelkit.world.mesh_solid import MeshSolid
from taxelkit.world.pose import matrix_from_axis_angle

__all__ = ["make_mesh_scenario"]

#: Edges shown on each kind of face.
_EDGES_SHOWN = 3
_N_DRAWS = 1024
_ATTEMPTS = 6
_YAW_TRIES = 8


def _roll(b: Builder, d: NDArray[np.float64], speed: float, label: str, **stop: float) -> None:
    solid = b.solid
    assert isinstance(solid, MeshSolid)
    rots, cents = roll_path(solid, b.pose, d, **stop)
    travel = fo.scalar_norm(cents[-1, :2] - b.pose.centroid_mm[:2]) + 1e-9
    dist = stop.get("distance_mm", travel)
    n = rots.shape[0]
    b.move(
        lambda u: (
            rots[np.minimum(np.round(u * n).astype(int), n) - 1],
            cents[np.minimum(np.round(u * n).astype(int), n) - 1],
        ),
        dist / speed,
        "rolling",
        label,
    )


def _rest_rotation(solid: MeshSolid, normal: NDArray[np.float64]) -> NDArray[np.float64]:
    """A rotation that turns the body-frame ``normal`` straight down."""
    n = normal / fo.scalar_norm(normal)
    axis = np.cross(n, -E_Z)
    s, c = fo.scalar_norm(axis), fo.scalar_dot(n, -E_Z)
    if s < 1e-9:
        return np.eye(3) if c > 0 else matrix_from_axis_angle([1.0, 0.0, 0.0], math.pi)
    out: NDArray[np.float64] = matrix_from_axis_angle(axis / s, math.atan2(s, c))
    return out


def _rest(solid: MeshSolid, rotation: NDArray[np.float64]) -> Pose:
    low = float(fo.rotate_points(solid.vertices_mm, rotation)[:, 2].min())
    return Pose(rotation, np.array([0.0, 0.0, -low]))


def _down_face(solid: MeshSolid, feats: MeshFeatures, pose: Pose) -> int:
    normals = fo.rotate_points(np.array([f.normal for f in feats.faces]), pose.rotation)
    return int(np.argmin(normals[:, 2]))


def _edge_pivot(
    b: Builder, edge: int
) -> tuple[MeshSolid, NDArray[np.float64], NDArray[np.float64]]:
    """The mesh, the middle of bottom edge ``edge``, mm, and the outward horizontal unit normal.

    Tipping about that edge turns the body about the horizontal line through
    the middle, perpendicular to the normal.
    """
    solid = b.solid
    assert isinstance(solid, MeshSolid)
    poly = bottom_polygon(solid, b.pose)  # type: ignore[arg-type]
    v1, v2 = poly[edge % len(poly)], poly[(edge + 1) % len(poly)]
    pivot = 0.5 * (v1 + v2)
    e = unit_h(v2 - v1)
    w = pivot - b.pose.centroid_mm
    return solid, pivot, unit_h(w - fo.scalar_dot(w, e) * e)


def _tip(b: Builder, feats: MeshFeatures, d: Draws, edge: int, over: bool) -> None:
    """Tip onto bottom edge ``edge``, hold, then back onto the face or over onto the next."""
    solid, pivot, u = _edge_pivot(b, edge)
    balance = balance_angle(b.pose, pivot, u)
    landing = landing_angle(b.pose.world_mm(solid.vertices_mm), pivot, u)
    k = np.cross(E_Z, u)
    speed = d.span(TIP_DEG_S)
    b.rotate(pivot, k, balance, speed, "tipping", "edge")
    b.hold(d.span(HOLD_S), "edge")
    b.rotate(pivot, k, landing - balance if over else -balance, speed, "tipping", "face")
    b.hold(d.span(HOLD_S), "face")


def _landing_face(b: Builder, feats: MeshFeatures, edge: int) -> int:
    """The face the body lands on when tipped over bottom edge ``edge``."""
    solid, pivot, u = _edge_pivot(b, edge)
    landing = landing_angle(b.pose.world_mm(solid.vertices_mm), pivot, u)
    rots, cents = rotate_about_line(b.pose, pivot, np.cross(E_Z, u), landing)
    return _down_face(solid, feats, Pose(rots[0], cents[0]))


def _kind(feats: MeshFeatures, i: int) -> tuple[float, float, float]:
    f = feats.faces[i]
    return (round(f.area_mm2, 1), round(f.elongation, 2), round(f.triangularity, 3))


def _script_polyhedron(b: Builder, feats: MeshFeatures, d: Draws) -> None:
    stable = [i for i, f in enumerate(feats.faces) if f.stable]
    kinds = sorted({_kind(feats, i) for i in stable})
    order = [kinds.pop(d.index(len(kinds))) for _ in range(len(kinds))]
    first = [i for i in stable if _kind(feats, i) == order[0]]
    solid = b.solid
    assert isinstance(solid, MeshSolid)
    b.pose = _rest(solid, _rest_rotation(solid, feats.faces[first[d.index(len(first))]].normal))
    begin_contact(b, d, "face")
    for kind in order:
        for _ in range(len(feats.faces)):  # walk towards the nearest face of this kind
            here = _down_face(solid, feats, b.pose)
            if _kind(feats, here) == kind:
                break
            m = len(bottom_polygon(solid, b.pose))  # type: ignore[arg-type]
            lands = [_landing_face(b, feats, j) for j in range(m)]
            hop = _first_hop(feats, here, kind, lands, stable)
            if hop is None:
                break
            _tip(b, feats, d, hop, over=True)
        m = len(bottom_polygon(solid, b.pose))  # type: ignore[arg-type]
        start = d.index(m)
        shown = [(start + j * max(1, m // _EDGES_SHOWN)) % m for j in range(min(m, _EDGES_SHOWN))]
        for j in dict.fromkeys(shown):
            _tip(b, feats, d, j, over=False)
    end_contact(b, d)


def _first_hop(
    feats: MeshFeatures,
    here: int,
    kind: tuple[float, float, float],
    lands: list[int],
    stable: list[int],
) -> int | None:
    """Bottom edge to tip over first on the shortest path of stable faces to ``kind``."""
    graph = {i: set(int(n) for n in feats.faces[i].neighbours if int(n) in stable) for i in stable}
    seen, queue = {here: -1}, deque([here])
    while queue:
        f = queue.popleft()
        if _kind(feats, f) == kind:
            while seen[f] != here:
                f = seen[f]
            return lands.index(f) if f in lands else None
        for g in sorted(graph.get(f, ())):
            if g not in seen:
                seen[g] = f
                queue.append(g)
    return None


def _settled(solid: MeshSolid, d: Draws) -> Pose:
    """The most stable of 64 drawn orientations (lowest centroid), resting."""
    best: Pose | None = None
    for _ in range(64):
        axis = np.array([d.uniform(-1, 1), d.uniform(-1, 1), d.uniform(-1, 1)]) + 1e-9
        rot = matrix_from_axis_angle(axis / fo.scalar_norm(axis), d.uniform(0.0, math.pi))
        pose = _rest(solid, rot)
        if best is None or pose.centroid_mm[2] < best.centroid_mm[2]:
            best = pose
    assert best is not None
    return best


def _long_axis(solid: MeshSolid, pose: Pose) -> NDArray[np.float64]:
    """Horizontal direction of the body's longest extent in ``pose``.

    The principal axis of the vertices' horizontal spread, from sums that
    :func:`math.fsum` rounds exactly (the same bits on every CPU).
    """
    v = pose.world_mm(solid.vertices_mm)
    x, y = (
        v[:, 0] - math.fsum(v[:, 0].tolist()) / v.shape[0],
        v[:, 1] - math.fsum(v[:, 1].tolist()) / v.shape[0],
    )
    sxx, syy, sxy = (math.fsum((a * b).tolist()) for a, b in ((x, x), (y, y), (x, y)))
    theta = 0.5 * math.atan2(2.0 * sxy, sxx - syy)
    return np.array([math.cos(theta), math.sin(theta), 0.0])


def _script_round(b: Builder, feats: MeshFeatures, d: Draws) -> None:
    solid = b.solid
    assert isinstance(solid, MeshSolid)
    b.pose = _settled(solid, d)
    begin_contact(b, d, "side")
    direction = np.array([1.0, 0.0, 0.0])
    if feats.ruled:  # lying on a ruled side: roll across the line, then up onto a cap
        axis = _long_axis(solid, b.pose)
        across = np.cross(E_Z, axis)
        _roll(b, across * d.sign(), d.span(ROLL_MM_S), "side", distance_mm=d.span((5.0, 10.0)))
        b.hold(d.span(HOLD_S), "side")
        up = axis * d.sign()
        tilt = d.span(HOLD_FRACTION) * math.pi / 2.0
        _roll(b, up, d.span(ROLL_MM_S), "side", angle_rad=tilt)
        b.hold(d.span(HOLD_S), "side")
        direction = np.cross(E_Z, up)
        runs = [(direction * d.sign(), d.span((3.0, 5.0))), (up, d.span((2.0, 3.0)))]
    else:
        runs = []
        for _ in range(2 + d.index(2)):
            runs.append((direction, d.span(SPHERE_RUN_MM)))
            direction = np.array([-direction[1], direction[0], 0.0]) * d.sign()
    for i, (heading, dist) in enumerate(runs):
        _roll(b, heading, d.span(ROLL_MM_S), "side", distance_mm=dist)
        if d.coin() or i == len(runs) - 1:
            b.hold(d.span(HOLD_S), "side")
    end_contact(b, d)


def _fit(
    b: Builder, solid: MeshSolid, yaw: float, shift_fraction: NDArray[np.float64], sensor: Sensor
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]] | None:
    """Rotations, centroids (yawed, shifted) and indentation on the array, or None."""
    rots, cents, indent = b.arrays()
    touch = indent > 0.0
    world = cents[touch][:, None, :] + fo.rotate_points(solid.vertices_mm, rots[touch])
    pressed = world[..., 2] <= indent[touch][:, None] + 1e-9
    xy = world[..., :2][pressed]
    margin = np.full(xy.shape[0], EDGE_MARGIN_MM)
    half = 0.5 * np.array([sensor.array.width_mm, sensor.array.height_mm])
    fit = fit_on_array(xy, margin, half, shift_fraction, yaw=yaw, tries=_YAW_TRIES)
    if fit is None:
        return None
    r, c = yawed(rots, cents, fit[0])
    c[:, :2] += fit[1]
    return r, c, indent


def make_mesh_scenario(
    solid: MeshSolid,
    features: MeshFeatures,
    *,
    name: str = "mesh",
    rng: RngLike = None,
    size_jitter: float = 0.0,
    depth_mm: float = DEFAULT_DEPTH_MM,
    depth_jitter: float = 0.3,
    rate_hz: float = DEFAULT_RATE_HZ,
    sensor: Sensor = BONNEVILLE_16X16,
) -> Scenario:
    """A randomised motion script for a convex mesh, on the array.

    Parameters
    ----------
    solid : MeshSolid
    features : MeshFeatures
        Of the same mesh (:func:`~taxelkit.world.mesh_features.mesh_features`).
    name : str
        The object's name (the scenario's ``object_name``; ground truth).
    rng : int, Generator or None
        Seed: the same seed gives an identical scenario.
    size_jitter : float
        The mesh is scaled by one factor from ``1 +- size_jitter``, in [0, 0.5]
        (default 0: a learnt object is one object at one size).
    depth_mm, depth_jitter, rate_hz, sensor
        As :func:`~taxelkit.motion.scenarios.make_scenario`.

    Raises
    ------
    InputError
        If the script cannot be fitted on the array (the mesh is too large).
    """
    jitter = check_in_range("size_jitter", size_jitter, 0.0, 0.5)
    djit = check_in_range("depth_jitter", depth_jitter, 0.0, 0.9)
    depth0 = check_positive("depth_mm", depth_mm)
    rate = check_positive("rate_hz", rate_hz)
    gen = np.random.default_rng(rng)
    scale = gen.uniform(1.0 - jitter, 1.0 + jitter)
    body = MeshSolid(solid.vertices_mm * scale, solid.normals, solid.offsets_mm * scale, label=name)
    depth = depth0 * gen.uniform(1.0 - djit, 1.0 + djit)
    if features.doubly_curved_mm2 > 0.0 and not features.ruled and not features.faces:
        ext = np.sort(np.ptp(body.vertices_mm, axis=0)) / 2.0  # rolls on a point: press lightly
        depth = min(depth, SPHERE_MAX_CONTACT_RADIUS_MM**2 / (2.0 * ext[2] ** 2 / ext[0]))
    draws = gen.random(_N_DRAWS)
    yaw = float(gen.uniform(0.0, 2.0 * math.pi))
    shift = gen.random(2)
    polyhedron = bool(features.faces) and not features.curved
    for _ in range(_ATTEMPTS):
        b = Builder(body, _rest(body, np.eye(3)), rate_hz=rate, depth_mm=depth)  # type: ignore[arg-type]
        (_script_polyhedron if polyhedron else _script_round)(b, features, Draws(draws))
        fitted = _fit(b, body, yaw, shift, sensor)
        if fitted is not None:
            rots, cents, indent = fitted
            return Scenario(
                name=name,
                object_name=name,
                solid=body,
                rotations=rots,
                positions_mm=cents[:, :2],
                rest_height_mm=cents[:, 2],
                indent_mm=indent,
                t_s=np.arange(indent.size) / rate,
                phase=b.phases,
                slides=False,
            )
        draws = np.random.default_rng(gen.integers(2**32)).random(_N_DRAWS)
    raise InputError(
        f"cannot fit a {name!r} script on the {sensor.name} array; the mesh is too large"
    )
