"""The random scripts of the paper-001 scenarios: how each solid is rolled, tipped or slid.

One script per solid (and ``"sliding"``), drawn by
:func:`~taxelkit.motion.scenarios.make_scenario`; each calls the builder of
:mod:`taxelkit.motion._script` with draws from its random stream, within the
limits of the attempt (rolls shrink on later attempts until the motion fits
on the array).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit import _fixed_order as fo
from taxelkit.motion._script import (
    CONE_TURN_DEG,
    CYLINDER_ROLL_MM,
    FRUSTUM_TURN_DEG,
    HOLD_FRACTION,
    HOLD_S,
    P_OVER,
    ROLL_MM_S,
    SLIDE_MM,
    SLIDE_MM_S,
    SPHERE_RUN_MM,
    SPIN_DEG,
    SPIN_DEG_S,
    TIP_DEG_S,
    Builder,
    Draws,
    apex_and_axis,
    balance_angle,
    begin_contact,
    bottom_polygon,
    end_contact,
    landing_angle,
    lay_silently,
    rest_pose,
    roll_about_apex,
    roll_line,
    stand_up,
    tilt_from_face,
    unit_h,
)
from taxelkit.motion.roll_paths import translate
from taxelkit.motion.rolling import E_Z
from taxelkit.world.pose import matrix_from_axis_angle
from taxelkit.world.solids_polyhedra import Cube, Tetrahedron
from taxelkit.world.solids_round import Cone, Cylinder, Sphere, TruncatedCone

__all__ = ["SCRIPTS", "Limits", "limits_for_attempt", "polyhedron_tips", "script_sliding"]

#: Rolls are scaled by this factor per attempt after the second.
SHRINK = 0.8


@dataclass(frozen=True)
class Limits:
    shrink: float = 1.0
    allow_over: bool = True
    allow_lay: bool = True


def limits_for_attempt(attempt: int) -> Limits:
    """Attempt 0 as drawn; 1 without tipping over or laying down; 2-9 rolls x 0.8 each."""
    if attempt == 0:
        return Limits()
    return Limits(SHRINK ** max(0, attempt - 1), allow_over=False, allow_lay=False)


# --- scripts -----------------------------------------------------------------------------------


def _script_sphere(b: Builder, d: Draws, lim: Limits) -> None:
    solid = b.solid
    assert isinstance(solid, Sphere)
    begin_contact(b, d, "side")
    direction = np.array([1.0, 0.0, 0.0])
    runs = 2 + d.index(2)
    for i in range(runs):
        dist = d.span(SPHERE_RUN_MM) * lim.shrink
        speed = d.span(ROLL_MM_S)
        pause = d.coin() or i == runs - 1
        roll_line(b, solid.radius_mm, direction, dist, speed, "side" if pause else "rolling")
        hold = d.span(HOLD_S)
        if pause:
            b.hold(hold, "side")
        direction = np.array([-direction[1], direction[0], 0.0]) * d.sign()
    end_contact(b, d)


def _script_polyhedron(b: Builder, d: Draws, lim: Limits) -> None:
    begin_contact(b, d, "face")
    polyhedron_tips(b, d, lim)


def polyhedron_tips(b: Builder, d: Draws, lim: Limits) -> None:
    """From a face: tipped about 2-3 bottom edges in turn, maybe onto a vertex; lifted off."""
    solid = b.solid
    assert isinstance(solid, Cube | Tetrahedron)
    visits = 2 + d.index(2)
    vertex_visit = d.index(visits + 1)  # == visits: no vertex
    previous: NDArray[np.float64] | None = None
    for i in range(visits):
        poly = bottom_polygon(solid, b.pose)
        m = len(poly)
        mids = 0.5 * (poly + np.roll(poly, -1, axis=0))
        j = d.index(m)
        other = (j + 1 + d.index(m - 1)) % m
        if previous is not None and np.linalg.norm(mids[j] - previous) < 1e-6:
            j = other  # never the edge just tipped over: the two lines differ
        v1, v2 = poly[j], poly[(j + 1) % m]
        pivot = 0.5 * (v1 + v2)
        e = unit_h(v2 - v1)
        w = pivot - b.pose.centroid_mm
        u = unit_h(w - fo.scalar_dot(w, e) * e)
        balance = balance_angle(b.pose, pivot, u)
        landing = landing_angle(b.pose.world_mm(solid.vertices_mm), pivot, u)
        k = np.cross(E_Z, u)
        speed = d.span(TIP_DEG_S)
        b.rotate(pivot, k, balance, speed, "tipping", "edge")
        b.hold(d.span(HOLD_S), "edge")
        end = d.index(2)
        if i == vertex_visit:
            corner, far = (v1, v2) if end == 0 else (v2, v1)
            uv = unit_h(corner - far)
            tilt = balance_angle(b.pose, corner, uv)
            kv = np.cross(E_Z, uv)
            b.rotate(corner, kv, tilt, speed, "tipping", "vertex")
            b.hold(d.span(HOLD_S), "vertex")
            b.rotate(corner, kv, -tilt, speed, "tipping", "edge")
            b.hold(d.span(HOLD_S), "edge")
        over = d.coin(P_OVER) and lim.allow_over
        b.rotate(pivot, k, landing - balance if over else -balance, speed, "tipping", "face")
        b.hold(d.span(HOLD_S), "face")
        previous = pivot  # back on this face or over onto the next, the edge is shared
    end_contact(b, d)


def _script_cylinder(b: Builder, d: Draws, lim: Limits) -> None:
    solid = b.solid
    assert isinstance(solid, Cylinder)
    u = unit_h(np.array([1.0, 0.0, 0.0]))
    on_side = d.coin(0.4) or not lim.allow_lay
    if on_side:
        lay_silently(b, u)
        begin_contact(b, d, "side")
    else:
        begin_contact(b, d, "face")
        tilt_from_face(b, u, d, lay=True)
    direction = np.cross(E_Z, u)
    dist = d.sign() * d.span(CYLINDER_ROLL_MM) * lim.shrink
    speed = d.span(ROLL_MM_S)
    roll_line(b, solid.radius_mm, direction, dist, speed, "side")
    b.hold(d.span(HOLD_S), "side")
    back = d.uniform(0.3, 0.8)
    if d.coin():
        roll_line(b, solid.radius_mm, direction, -back * dist, speed, "side")
        b.hold(d.span(HOLD_S), "side")
    end = d.index(2)
    if d.coin() and lim.allow_lay:
        stand_up(b, end, d)
    end_contact(b, d)


def _script_cone(b: Builder, d: Draws, lim: Limits) -> None:
    solid = b.solid
    assert isinstance(solid, Cone | TruncatedCone)
    frustum = isinstance(solid, TruncatedCone)
    u = np.array([1.0, 0.0, 0.0])
    first = d.index(3 if frustum else 2)  # 0 bottom face, 1 side, 2 top face (frustum)
    if first == 2:
        b.pose = rest_pose(solid, matrix_from_axis_angle([1.0, 0.0, 0.0], math.pi))
    if first == 1 or not lim.allow_lay:
        lay_silently(b, u)
        begin_contact(b, d, "side")
    else:
        begin_contact(b, d, "face")
        tilt_from_face(b, u, d, lay=True)
    turn = math.radians(d.span(FRUSTUM_TURN_DEG if frustum else CONE_TURN_DEG))
    turn *= d.sign() * lim.shrink
    speed = d.span(ROLL_MM_S)
    roll_about_apex(b, turn, speed, "side")
    b.hold(d.span(HOLD_S), "side")
    apex_hold = d.span(HOLD_FRACTION)
    if not frustum and d.coin():
        apex, axis = apex_and_axis(solid, b.pose)
        ua = -unit_h(axis)
        k = np.cross(E_Z, ua)
        tilt = apex_hold * (math.pi / 2.0 - math.asin(float(axis[2])))
        tip = d.span(TIP_DEG_S)
        b.rotate(apex, k, tilt, tip, "tipping", "apex")
        b.hold(d.span(HOLD_S), "apex")
        b.rotate(apex, k, -tilt, tip, "tipping", "side")
        b.hold(d.span(HOLD_S), "side")
    if d.coin():
        roll_about_apex(b, -turn * d.uniform(0.3, 0.8), speed, "side")
        b.hold(d.span(HOLD_S), "side")
    end = d.index(2)
    if frustum and d.coin() and lim.allow_lay:
        stand_up(b, end, d)
    end_contact(b, d)


def script_sliding(b: Builder, d: Draws, lim: Limits) -> None:
    begin_contact(b, d, "face")
    mode = d.index(3)  # 0 drag, 1 spin, 2 drag then spin
    heading = d.uniform(0.0, 2.0 * math.pi)
    dist = d.span(SLIDE_MM) * lim.shrink
    speed = d.span(SLIDE_MM_S)
    spin = math.radians(d.sign() * d.span(SPIN_DEG))
    spin_speed = d.span(SPIN_DEG_S)
    if mode in (0, 2):
        pose = b.pose
        step = dist * np.array([math.cos(heading), math.sin(heading)])
        b.move(lambda u: translate(pose, u[:, None] * step), dist / speed, "sliding", "face")
        b.hold(d.span(HOLD_S), "face")
    if mode in (1, 2):
        centre = b.pose.centroid_mm * np.array([1.0, 1.0, 0.0])
        b.rotate(centre, E_Z, spin, spin_speed, "spinning", "face")
        b.hold(d.span(HOLD_S), "face")
    end_contact(b, d)


SCRIPTS: dict[str, Callable[[Builder, Draws, Limits], None]] = {
    "sphere": _script_sphere,
    "cube": _script_polyhedron,
    "tetrahedron": _script_polyhedron,
    "cylinder": _script_cylinder,
    "cone": _script_cone,
    "truncated-cone": _script_cone,
}
