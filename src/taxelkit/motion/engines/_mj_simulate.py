"""One MuJoCo simulation of a scene script: the body driven by the hand, step by step.

Private to :mod:`taxelkit.motion.engines.mujoco_scenes`: the scene is built
from its plan (:mod:`~taxelkit.motion.engines._mjcf`), the hand's segments
(:mod:`~taxelkit.motion.engines._mj_hand`) apply their wrenches between
MuJoCo's two step stages, and every physics step's pose, contact and press is
recorded (:class:`~taxelkit.motion.engines._sampling.StepRecord`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit import _fixed_order as fo
from taxelkit.errors import InputError
from taxelkit.motion import _script as sc
from taxelkit.motion.engines import _mj_hand as mh
from taxelkit.motion.engines import _mj_scripts as ms_scripts
from taxelkit.motion.engines._mjcf import BODY_NAME, M_PER_MM, PHYSICS_HZ, scene_xml
from taxelkit.motion.engines._sampling import StepRecord, matrices_from_quats, motion_measures
from taxelkit.motion.engines.registry import MUJOCO_INSTALL_HINT
from taxelkit.motion.rolling import E_Z
from taxelkit.sensors.presets import Sensor
from taxelkit.world.solids import AnalyticSolid
from taxelkit.world.solids_round import Cone, Cylinder, Sphere, TruncatedCone

__all__ = ["TOUCH_GAP_MM", "bounding_radius_mm", "import_mujoco", "simulate"]

#: A body whose lowest point is less than this above the plate still touches
#: it, mm, even in a step where MuJoCo lists no contact: a dragged face
#: chatters by a fraction of a micrometre, far below the skin's 30 um
#: threshold, and the press does not vanish in a millisecond.
TOUCH_GAP_MM = 0.005
#: Hard cap on a scene's length, s (a script lasts 5-15 s).
_MAX_DURATION_S = 60.0


#: The hand's press ramp per step, as stored in the step record.
_RAMP_CODES = {"": 0, "placing": 1, "lifting": 2}


def import_mujoco() -> Any:
    try:
        import mujoco
    except ImportError:
        raise InputError(f"the mujoco engine needs MuJoCo: {MUJOCO_INSTALL_HINT}") from None
    return mujoco


def simulate(
    mujoco: Any,
    sensor: Sensor,
    plan: ms_scripts.Plan,
    segments: list[mh.Segment],
    rotation0: NDArray[np.float64],
) -> StepRecord:
    xml = scene_xml(plan.solid, sensor, friction=plan.friction, density_kg_m3=plan.density_kg_m3)
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    bid = model.body(BODY_NAME).id
    ri = np.zeros(9)
    mujoco.mju_quat2Mat(ri, model.body_iquat[bid])
    ri3 = ri.reshape(3, 3)
    hand = mh.Hand(
        plan.solid,
        float(model.body_mass[bid]),
        fo.matmul(fo.matmul(ri3, np.diag(model.body_inertia[bid])), ri3.T),
    )
    rest = sc.rest_pose(plan.solid, rotation0)
    quat = np.zeros(4)
    mujoco.mju_mat2Quat(quat, rotation0.ravel())
    data.qpos[:3] = (rest.centroid_mm + mh.HOVER_CLEARANCE_MM * E_Z) * M_PER_MM
    data.qpos[3:7] = quat
    radius_mm = bounding_radius_mm(plan.solid)
    rows: list[tuple[float, ...]] = []
    # the contact points of the steps in contact and the body's motion then, for the
    # slip of its material contact points (computed after the loop, all at once)
    contact_pos: list[NDArray[np.float64]] = []
    contact_steps: list[int] = []
    contact_motion: list[tuple[float, ...]] = []
    seg_i = 0
    mujoco.mj_forward(model, data)
    segments[0].start(hand, _state(data, bid, 0.0, False))
    max_steps = int(_MAX_DURATION_S * PHYSICS_HZ)
    for step in range(max_steps):
        mujoco.mj_step1(model, data)
        t = step / PHYSICS_HZ
        ncon = int(data.ncon)
        s = _state(data, bid, t, ncon > 0)
        if ncon:
            contact_pos.append(data.contact.pos[:ncon].copy())
            contact_steps.append(len(rows))
            contact_motion.append(
                (*s.pos_m.tolist(), *s.vel_m_s[:2].tolist(), *s.omega_rad_s.tolist())
            )
        wrench = segments[seg_i].wrench(hand, s)
        while wrench is None and seg_i + 1 < len(segments):
            seg_i += 1
            segments[seg_i].start(hand, s)
            wrench = segments[seg_i].wrench(hand, s)
        ramp = _RAMP_CODES[hand.ramp]
        rows.append((*data.qpos[:7].tolist(), ncon > 0, hand.press, ramp))
        if wrench is None:
            break
        data.xfrc_applied[bid] = wrench
        mujoco.mj_step2(model, data)
    arr = np.array(rows, dtype=np.float64)
    quats = arr[:, 3:7] / np.linalg.norm(arr[:, 3:7], axis=1, keepdims=True)
    centroids = arr[:, :3] / M_PER_MM
    gap = centroids[:, 2] + plan.solid.lowest_z_mm(matrices_from_quats(quats))
    touching = (arr[:, 7] > 0.5) | (gap < TOUCH_GAP_MM)
    slip_now = _contact_slip_mm_s(arr.shape[0], contact_pos, contact_steps, contact_motion)
    speed, spin, slip = motion_measures(  # the script ends after at most _MAX_DURATION_S
        quats, centroids, slip_now, radius_mm=radius_mm, steps_per_s=PHYSICS_HZ
    )
    return StepRecord(
        quats=quats,
        centroids_mm=centroids,
        touching=touching,
        press=arr[:, 8],
        ramp=arr[:, 9].astype(np.int8),
        speed_mm_s=speed,
        spin_share=spin,
        slip_mm_s=slip,
    )


def _contact_slip_mm_s(
    n_steps: int,
    contact_pos: list[NDArray[np.float64]],
    contact_steps: list[int],
    contact_motion: list[tuple[float, ...]],
) -> NDArray[np.float64]:
    """Fastest horizontal speed of the body's material contact points per step, mm/s.

    ``contact_pos[i]`` holds the contact points (m) of step ``contact_steps[i]``
    and ``contact_motion[i]`` the centroid (m), its horizontal velocity (m/s)
    and the angular velocity (rad/s) then; steps without contact get 0. The
    material velocity is ``v + w x (p - c)``, elementwise as per step.
    """
    out = np.zeros(n_steps)
    if not contact_steps:
        return out
    counts = np.array([p.shape[0] for p in contact_pos])
    pts = np.concatenate(contact_pos)
    m = np.repeat(np.array(contact_motion), counts, axis=0)  # (points, 8)
    rel = pts - m[:, :3]
    w0, w1, w2 = m[:, 5], m[:, 6], m[:, 7]
    vx = m[:, 3] + (w1 * rel[:, 2] - w2 * rel[:, 1])  # v + w x rel
    vy = m[:, 4] + (w2 * rel[:, 0] - w0 * rel[:, 2])
    starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
    out[np.array(contact_steps)] = np.maximum.reduceat(np.hypot(vx, vy), starts) / M_PER_MM
    return out


def _state(data: Any, bid: int, t: float, touching: bool) -> mh.BodyState:
    """The body's state after MuJoCo's position stage (``xmat`` matches ``qpos``)."""
    rot = np.array(data.xmat[bid]).reshape(3, 3)
    return mh.BodyState(
        t_s=t,
        pos_m=np.array(data.qpos[:3]),
        rot=rot,
        vel_m_s=np.array(data.qvel[:3]),
        omega_rad_s=fo.matvec(rot, np.array(data.qvel[3:6])),
        touching=touching,
    )


def bounding_radius_mm(solid: AnalyticSolid) -> float:
    if isinstance(solid, Sphere):
        return float(solid.radius_mm)
    if isinstance(solid, Cylinder | Cone | TruncatedCone):
        return max(math.hypot(r, z) for z, r in solid.profile.rims)
    return float(np.max(np.linalg.norm(solid.vertices_mm, axis=1)))
