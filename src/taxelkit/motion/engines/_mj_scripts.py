"""Scripts of the MuJoCo scenes: what a scene draws, and the hand segments it runs.

Private to :mod:`taxelkit.motion.engines.mujoco_scenes`. Every random choice is
drawn before simulating, from one seed, in a fixed order (a replayable stream
of :class:`~taxelkit.motion._script.Draws`), so that the attempts of fitting a
scene on the array replay the same choices. Timing and extent ranges are those
of the kinematic scripts (:mod:`taxelkit.motion._script`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit import _fixed_order as fo
from taxelkit.motion import _script as sc
from taxelkit.motion.engines import _mj_hand as mh
from taxelkit.motion.engines import _mj_tip as mt
from taxelkit.motion.engines._mjcf import DENSITY_KG_M3, ROLLING_FRICTION, SLIDING_FRICTION
from taxelkit.motion.rolling import E_Z
from taxelkit.motion.scenarios import _draw_body
from taxelkit.world.pose import matrix_from_axis_angle
from taxelkit.world.solids import AnalyticSolid
from taxelkit.world.solids_round import Cone, Cylinder, TruncatedCone

#: Each scene draws its random choices from this many uniform numbers.
N_DRAWS = 256
#: Pushes shrink by this factor per attempt after the second.
SHRINK = 0.8


@dataclass(frozen=True)
class Plan:
    """What a scene draws before simulating."""

    object_name: str
    solid: AnalyticSolid
    depth_mm: float
    yaw: float
    shift_fraction: NDArray[np.float64]
    draws: NDArray[np.float64]
    slides: bool
    flip: bool
    friction: float
    density_kg_m3: float


# --- scripts: lists of hand segments --------------------------------------------------------


def _begin(d: sc.Draws) -> list[mh.Segment]:
    return [mh.Hover(d.span(sc.LIFTED_S)), mh.Place(d.span(sc.PLACE_S)), mh.Rest(d.span(sc.HOLD_S))]


def _end(d: sc.Draws) -> list[mh.Segment]:
    return [mh.Unpress(d.span(sc.PLACE_S)), mh.Rise(), mh.Hover(d.span(sc.LIFTED_S))]


def _script_sphere(
    d: sc.Draws, solid: AnalyticSolid, yaw: float, shrink: float, lay: bool
) -> list[list[mh.Segment]]:
    out = [_begin(d)]
    runs = 2 + d.index(2)
    direction = np.array([math.cos(yaw), math.sin(yaw)])
    for _ in range(runs):
        dist = d.span(sc.SPHERE_RUN_MM) * shrink
        speed = d.span(sc.ROLL_MM_S)
        push = mh.Push(dist, speed, "vector", (float(direction[0]), float(direction[1])))
        out.append([push, mh.Brake(), mh.Rest(d.span(sc.HOLD_S))])
        direction = np.array([-direction[1], direction[0]]) * d.sign()
    out.append(_end(d))
    return out


def _script_round(
    d: sc.Draws, solid: AnalyticSolid, yaw: float, shrink: float, lay: bool
) -> list[list[mh.Segment]]:
    """Cylinder, cone, truncated cone: maybe laid from a face onto the side, then rolled."""
    out = [_begin(d)]
    u = (math.cos(yaw), math.sin(yaw))
    tip = mt.Tip(
        direction=u,
        hold_fraction=d.span(sc.HOLD_FRACTION),
        hold_s=d.span(sc.HOLD_S),
        over=True,
        speed_deg_s=d.span(sc.TIP_DEG_S),
    )
    rest = d.span(sc.HOLD_S)
    if lay:  # standing on a face: tilt onto the rim, hold, lay it on its side
        out.append([tip, mh.Brake(), mh.Rest(rest)])
    sign = d.sign()
    if isinstance(solid, Cone | TruncatedCone):  # the far rim's path about the apex
        prof = solid.profile
        reach = max(math.hypot(r, z - prof.vertex_z_mm) for z, r in prof.rims)
        turns = sc.FRUSTUM_TURN_DEG if isinstance(solid, TruncatedCone) else sc.CONE_TURN_DEG
        dist = math.radians(d.span(turns)) * reach * shrink
    else:
        dist = d.span(sc.CYLINDER_ROLL_MM) * shrink
    speed = d.span(sc.ROLL_MM_S)
    out.append([mh.Push(dist, speed, "across", sign=sign), mh.Brake(), mh.Rest(d.span(sc.HOLD_S))])
    if d.coin():
        back = d.uniform(0.3, 0.8) * dist
        out.append(
            [mh.Push(back, speed, "across", sign=-sign), mh.Brake(), mh.Rest(d.span(sc.HOLD_S))]
        )
    out.append(_end(d))
    return out


def _script_polyhedron(
    d: sc.Draws, solid: AnalyticSolid, yaw: float, shrink: float, lay: bool
) -> list[list[mh.Segment]]:
    out = [_begin(d)]
    previous: mt.Tip | None = None
    for _ in range(2 + d.index(2)):
        previous = mt.Tip(
            choice=d.uniform(0.0, 1.0),
            hold_fraction=d.span(sc.HOLD_FRACTION),
            hold_s=d.span(sc.HOLD_S),
            over=d.coin(sc.P_OVER) and lay,
            speed_deg_s=d.span(sc.TIP_DEG_S),
            previous=previous,
        )
        out.append([previous, mh.Rest(d.span(sc.HOLD_S))])
    out.append(_end(d))
    return out


def _script_sliding(
    d: sc.Draws, solid: AnalyticSolid, yaw: float, shrink: float, lay: bool
) -> list[list[mh.Segment]]:
    out = [_begin(d)]
    mode = d.index(3)  # 0 drag, 1 spin, 2 drag then spin
    heading = yaw + d.uniform(0.0, 2.0 * math.pi)
    dist = d.span(sc.SLIDE_MM) * shrink
    speed = d.span(sc.SLIDE_MM_S)
    spin = d.sign() * d.span(sc.SPIN_DEG)
    spin_speed = d.span(sc.SPIN_DEG_S)
    if mode in (0, 2):
        push = mh.Push(dist, speed, "vector", (math.cos(heading), math.sin(heading)))
        out.append([push, mh.Brake(), mh.Rest(d.span(sc.HOLD_S))])
    if mode in (1, 2):
        out.append([mh.Spin(spin, spin_speed), mh.Brake(), mh.Rest(d.span(sc.HOLD_S))])
    out.append(_end(d))
    return out


_Script = Callable[[sc.Draws, AnalyticSolid, float, float, bool], list[list[mh.Segment]]]
_SCRIPTS: dict[str, _Script] = {
    "sphere": _script_sphere,
    "cylinder": _script_round,
    "cone": _script_round,
    "truncated-cone": _script_round,
    "cube": _script_polyhedron,
    "tetrahedron": _script_polyhedron,
}


def start_rotation(plan: Plan, d: sc.Draws, allow_lay: bool) -> tuple[NDArray[np.float64], bool]:
    """Initial rotation (yaw included) and whether a round body starts on a face."""
    solid = plan.solid
    base = matrix_from_axis_angle([1.0, 0.0, 0.0], math.pi if plan.flip else 0.0)
    on_side = False
    if not plan.slides and isinstance(solid, Cylinder | Cone | TruncatedCone):
        first = d.index(3 if isinstance(solid, TruncatedCone) else 2)
        if first == 2:  # a frustum's top face
            base = matrix_from_axis_angle([1.0, 0.0, 0.0], math.pi)
        on_side = first == 1 or not allow_lay
        if on_side:
            b = sc.Builder(solid, sc.rest_pose(solid, base), rate_hz=1.0, depth_mm=1.0)
            sc.lay_silently(b, np.array([1.0, 0.0, 0.0]))
            base = b.pose.rotation
    out = fo.matmul(matrix_from_axis_angle(E_Z, plan.yaw), base)
    return out, not on_side


def draw_plan(
    name: str, gen: np.random.Generator, size_jitter: float, depth_mm: float, depth_jitter: float
) -> Plan:
    slides = name == "sliding"
    object_name, solid, depth, flip = _draw_body(name, gen, size_jitter, depth_mm, depth_jitter)
    return Plan(
        object_name=object_name,
        solid=solid,
        depth_mm=depth,
        yaw=float(gen.uniform(0.0, 2.0 * math.pi)),
        shift_fraction=gen.random(2),
        draws=gen.random(N_DRAWS),
        slides=slides,
        flip=flip,
        friction=float(gen.uniform(*(SLIDING_FRICTION if slides else ROLLING_FRICTION))),
        density_kg_m3=float(gen.uniform(*DENSITY_KG_M3)),
    )


def segments_for(
    plan: Plan, attempt: int, lift_gap_s: float
) -> tuple[list[mh.Segment], NDArray[np.float64]]:
    d = sc.Draws(plan.draws)
    rotation0, on_face = start_rotation(plan, d, allow_lay=attempt == 0)
    shrink = SHRINK ** max(0, attempt - 1)
    script = _script_sliding if plan.slides else _SCRIPTS[plan.object_name]
    # attempt 0 as drawn; later ones without tipping over or laying down
    parts = script(
        d, plan.solid, plan.yaw, shrink, on_face if _is_round(plan.solid) else attempt == 0
    )
    if lift_gap_s > 0.0:  # after the first motion's rest
        parts.insert(2, [mh.Gap(lift_gap_s), mh.Rest(sc.HOLD_S[0])])
    return [seg for part in parts for seg in part], rotation0


def _is_round(solid: AnalyticSolid) -> bool:
    return isinstance(solid, Cylinder | Cone | TruncatedCone)
