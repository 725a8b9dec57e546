"""From a physics record (one state per time step) to frames at any rate, with phase labels.

Private to :mod:`taxelkit.motion.engines.mujoco_scenes`; pure NumPy, no MuJoCo.

Sampling
--------
Frame ``k`` is taken at ``t_k = k / rate_hz``, i.e. at the fractional step
``s_k = k * steps_per_s / rate_hz``. Positions are interpolated linearly and
rotations by spherical interpolation of the unit quaternions between steps
``floor(s_k)`` and ``floor(s_k) + 1``; with a zero fraction the step's own
values come out bit for bit, so a scene sampled at 100 Hz and at 20 Hz agree
exactly at the common times. Contact, press and the motion measures are read
at the nearest step.

Phase labels (from the engine's state, never from the script)
-------------------------------------------------------------
``lifted`` no contact with the plate; ``placing``/``lifting`` the press ramps;
moving (some material point faster than :data:`MOVING_MM_S`): ``sliding`` or
``spinning`` when a contact point slips faster than :data:`SLIP_MM_S`
(spinning when the turn about the vertical dominates), else ``rolling`` for a
ball or a round body on a line contact and ``tipping`` otherwise; still: the
geometric contact type (:func:`contact_kinds`) gives ``face`` (area), ``edge``
or ``side`` (line), ``vertex``, ``rim``, ``apex`` or ``side`` (a ball's point).

Contact types of physics poses
------------------------------
:func:`~taxelkit.motion.contact_truth.contact_types` ties candidate points
within 1e-6 mm, right for the exact poses of the kinematic scripts. A body
resting on MuJoCo's soft contacts is level only to a few micrometres (an edge
whose two ends sink 8 and 9 um), so :func:`contact_kinds` ties within
:data:`PHYSICS_TIE_MM` and measures spread against :data:`PHYSICS_SPREAD_MM`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit import _fixed_order as fo
from taxelkit.motion.array_placement import EDGE_MARGIN_MM, patch_halfwidth_mm
from taxelkit.motion.contact_truth import (
    POSE_CHUNK,
    contact_state,
    contact_types,
    kind_indices,
)
from taxelkit.world.solids import AnalyticSolid
from taxelkit.world.solids_polyhedra import Cube, Tetrahedron
from taxelkit.world.solids_round import Cone, Sphere

#: A body moves when the centroid's speed plus its turning rate times its
#: bounding radius exceeds this, mm/s: a tenth of the slowest push (3 mm/s);
#: a resting body creeps far slower. Speeds and slip are averaged over
#: :data:`WINDOW_S` (the contact points of a meshed body jitter at the
#: physics step).
MOVING_MM_S = 0.3

#: Window of the speed and slip averages, s (centred): 50 ms, a frame at 20 Hz.
WINDOW_S = 0.05

#: A contact point slips when the material point of the body at the contact
#: moves over the plate faster than this, mm/s: a third of the slowest drag
#: (3 mm/s); rolling and tipping bodies creep far slower on MuJoCo's soft
#: contacts.
SLIP_MM_S = 1.0

#: Candidate points within this height of the lowest one touch the plate, mm:
#: above the differences in sinking of MuJoCo's soft contacts (about 10 um
#: at most) and a third of the lightest press (0.21 mm x 0.05 at the end of a
#: ramp is 10 um, 0.21 mm in a hold), so what is tied here is pressed into
#: the skin alike.
PHYSICS_TIE_MM = 0.02

#: RMS spread of the tied points along their widest (second widest) direction
#: below which the contact is a point (a line), mm. A rim tied within
#: :data:`PHYSICS_TIE_MM` spans an arc ``sqrt(8 r tie / sin(tilt))`` long
#: (1.5 mm for r = 7 mm at 30 deg, RMS 0.45 mm); the shortest line, a
#: jittered cube's edge (8.4 mm), has an RMS of 2.4 mm, the smallest face
#: (a frustum's top, radius >= 2.45 mm) 1.2 mm.
PHYSICS_SPREAD_MM = 1.0


@dataclass(frozen=True, eq=False)
class StepRecord:
    """One state per physics step (arrays of length ``N``), sensor frame, mm.

    ``quats`` are unit quaternions ``(w, x, y, z)`` body to sensor;
    ``speed_mm_s`` the fastest material point's speed (centroid speed plus
    turning rate times the bounding radius); ``spin_share`` the turning rate
    about the vertical times the bounding radius over that speed;
    ``slip_mm_s`` the fastest horizontal speed of a material contact point (0
    without contact); ``ramp`` 0 none, 1 placing, 2 lifting.
    """

    quats: NDArray[np.float64]
    centroids_mm: NDArray[np.float64]
    touching: NDArray[np.bool_]
    press: NDArray[np.float64]
    ramp: NDArray[np.int8]
    speed_mm_s: NDArray[np.float64]
    spin_share: NDArray[np.float64]
    slip_mm_s: NDArray[np.float64]


def _quat_mul(a: NDArray[np.float64], b: NDArray[np.float64]) -> NDArray[np.float64]:
    aw, ax, ay, az = a.T
    bw, bx, by, bz = b.T
    return np.stack(
        [
            aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw,
        ],
        axis=1,
    )


def motion_measures(
    quats: NDArray[np.float64],
    centroids_mm: NDArray[np.float64],
    slip_mm_s: NDArray[np.float64],
    *,
    radius_mm: float,
    steps_per_s: int,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Speed, spin share and slip per step, averaged over :data:`WINDOW_S`.

    Parameters
    ----------
    quats : (N, 4) float
        Unit quaternions ``(w, x, y, z)`` per step.
    centroids_mm : (N, 3) float, mm
    slip_mm_s : (N,) float, mm/s
        Instantaneous slip of the contact points.
    radius_mm : float
        Bounding radius of the body about its centroid, mm.
    steps_per_s : int

    Returns
    -------
    speed_mm_s : (N,) float
        Centroid displacement plus turn angle times ``radius_mm`` across the
        window, over its duration.
    spin_share : (N,) float
        The turn about the vertical times ``radius_mm`` over that total.
    slip_mm_s : (N,) float
        Mean slip over the window.
    """
    n = quats.shape[0]
    h = max(1, round(0.5 * WINDOW_S * steps_per_s))
    hi = np.minimum(np.arange(n) + h, n - 1)
    lo = np.maximum(np.arange(n) - h, 0)
    dt = np.maximum(hi - lo, 1) / steps_per_s
    conj = quats[lo] * np.array([1.0, -1.0, -1.0, -1.0])
    rel = _quat_mul(quats[hi], conj)  # rotation from lo to hi, world frame
    vec_norm = np.linalg.norm(rel[:, 1:], axis=1)
    angle = 2.0 * fo.arctan2(vec_norm, np.abs(rel[:, 0]))
    axis_z = np.abs(rel[:, 3]) / np.maximum(vec_norm, 1e-300)
    move = np.linalg.norm(centroids_mm[hi] - centroids_mm[lo], axis=1)
    total = move + angle * radius_mm
    speed = total / dt
    spin = angle * axis_z * radius_mm / np.maximum(total, 1e-300)
    csum = np.concatenate([[0.0], np.cumsum(slip_mm_s)])
    slip = (csum[hi + 1] - csum[lo]) / (hi - lo + 1)
    return speed, spin, slip


def matrices_from_quats(q: NDArray[np.float64]) -> NDArray[np.float64]:
    """Rotation matrices ``(n, 3, 3)`` from unit quaternions ``(n, 4)`` ``(w, x, y, z)``."""
    w, x, y, z = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    out = np.empty((q.shape[0], 3, 3))
    out[:, 0, 0] = 1 - 2 * (y * y + z * z)
    out[:, 0, 1] = 2 * (x * y - w * z)
    out[:, 0, 2] = 2 * (x * z + w * y)
    out[:, 1, 0] = 2 * (x * y + w * z)
    out[:, 1, 1] = 1 - 2 * (x * x + z * z)
    out[:, 1, 2] = 2 * (y * z - w * x)
    out[:, 2, 0] = 2 * (x * z - w * y)
    out[:, 2, 1] = 2 * (y * z + w * x)
    out[:, 2, 2] = 1 - 2 * (x * x + y * y)
    return out


def slerp(
    q0: NDArray[np.float64], q1: NDArray[np.float64], f: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Spherical interpolation of unit quaternions ``(n, 4)`` at fractions ``f`` ``(n,)``.

    ``f == 0`` returns ``q0`` exactly; nearly equal quaternions are blended
    linearly and normalised.
    """
    dot = np.sum(q0 * q1, axis=1)
    q1 = np.where(dot[:, None] < 0.0, -q1, q1)
    dot = np.abs(dot)
    omega = fo.arccos(np.clip(dot, -1.0, 1.0))
    small = omega < 1e-9
    sin_o = np.where(small, 1.0, np.sin(omega))
    a = np.where(small, 1.0 - f, np.sin((1.0 - f) * omega) / sin_o)
    b = np.where(small, f, np.sin(f * omega) / sin_o)
    out = a[:, None] * q0 + b[:, None] * q1
    out /= np.linalg.norm(out, axis=1, keepdims=True)
    exact = f == 0.0
    out[exact] = q0[exact]
    return out


def sample_times(
    n_steps: int, steps_per_s: int, rate_hz: float
) -> tuple[NDArray[np.float64], NDArray[np.intp], NDArray[np.float64]]:
    """Frame times, the step before each and the fraction past it.

    Returns
    -------
    t_s : (T,) float, s
        ``k / rate_hz`` for every ``k`` with ``t_k`` within the record.
    i0 : (T,) int
        Step at or before ``t_k`` (at most ``n_steps - 2``).
    frac : (T,) float
        ``s_k - i0`` in [0, 1].
    """
    last = n_steps - 1
    n_frames = math.floor(last * rate_hz / steps_per_s) + 1
    k = np.arange(n_frames, dtype=np.float64)
    s = k * steps_per_s / rate_hz
    keep = s <= last
    k, s = k[keep], s[keep]
    i0 = np.minimum(np.floor(s).astype(np.intp), last - 1)
    return k / rate_hz, i0, s - i0


def sample_record(
    rec: StepRecord, steps_per_s: int, rate_hz: float
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.intp]]:
    """Rotations ``(T, 3, 3)``, centroids ``(T, 3)`` mm, times ``(T,)`` s and nearest steps."""
    n = rec.quats.shape[0]
    t_s, i0, frac = sample_times(n, steps_per_s, rate_hz)
    q = slerp(rec.quats[i0], rec.quats[i0 + 1], frac)
    c0, c1 = rec.centroids_mm[i0], rec.centroids_mm[i0 + 1]
    cent = c0 + frac[:, None] * (c1 - c0)
    cent[frac == 0.0] = c0[frac == 0.0]
    nearest = np.minimum(np.floor(i0 + frac + 0.5).astype(np.intp), n - 1)
    return matrices_from_quats(q), cent, t_s, nearest


def _touching(
    solid: AnalyticSolid, rot: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.bool_], NDArray[np.intp]]:
    """Candidate points ``(P, K, 3)`` (sensor orientation, relative to the centroid),
    which of them touch ``(P, K)``, and the contact type index ``(P,)`` (1 point,
    2 line, 3 area)."""
    state = contact_state(solid, rot, tie_mm=PHYSICS_TIE_MM)
    pts, touch = state.relative_mm, state.touching
    return pts, touch, kind_indices(pts, touch, PHYSICS_SPREAD_MM)


def contact_kinds(solid: AnalyticSolid, rotations: NDArray[np.float64]) -> tuple[str, ...]:
    """Contact type (point, line, area) of a solid resting on the plate, per pose.

    Parameters
    ----------
    solid : AnalyticSolid
    rotations : (P, 3, 3) float
        Body-to-sensor rotations.

    Returns
    -------
    tuple of str, length P
        As :func:`~taxelkit.motion.contact_truth.contact_types`, with the
        tolerances of physics poses (:data:`PHYSICS_TIE_MM`,
        :data:`PHYSICS_SPREAD_MM`).
    """
    return contact_types(solid, rotations, tie_mm=PHYSICS_TIE_MM, spread_mm=PHYSICS_SPREAD_MM)


def contact_footprint_mm(
    solid: AnalyticSolid,
    rotations: NDArray[np.float64],
    positions_mm: NDArray[np.float64],
    depth_mm: float,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """xy of every contact point of resting poses, and the margin each needs on the array, mm.

    Parameters
    ----------
    solid : AnalyticSolid
    rotations : (P, 3, 3) float
    positions_mm : (P, 2) float, mm
        Centroid xy.
    depth_mm : float
        Press depth, mm.

    Returns
    -------
    xy : (M, 2) float, mm
        The touching candidate points (:data:`PHYSICS_TIE_MM`): a lying cone's
        apex and far rim, a face's outline, ...
    margin : (M,) float, mm
        :data:`~taxelkit.motion.array_placement.EDGE_MARGIN_MM`, plus the patch
        half-width ``sqrt(2 rho d)`` for the points and lines of round bodies
        (as the kinematic scripts' fitting).
    """
    xy_parts: list[NDArray[np.float64]] = []
    margin_parts: list[NDArray[np.float64]] = []
    patch = patch_halfwidth_mm(solid, depth_mm)
    for start in range(0, rotations.shape[0], POSE_CHUNK):
        stop = start + POSE_CHUNK
        pts, touch, kind = _touching(solid, rotations[start:stop])
        xy = pts[..., :2] + positions_mm[start:stop, None, :]
        margin = EDGE_MARGIN_MM + np.where(kind == 3, 0.0, patch)
        xy_parts.append(xy[touch])
        margin_parts.append(np.broadcast_to(margin[:, None], touch.shape)[touch])
    return np.concatenate(xy_parts), np.concatenate(margin_parts)


def _still_label(solid: AnalyticSolid, kind: str, rot: NDArray[np.float64]) -> str:
    if kind == "area":
        return "face"
    polyhedron = isinstance(solid, Cube | Tetrahedron)
    if kind == "line":
        return "edge" if polyhedron else "side"
    if polyhedron:
        return "vertex"
    if isinstance(solid, Sphere):
        return "side"
    if isinstance(solid, Cone):
        apex_z = solid.profile.rims[1][0]
        return (
            "apex"
            if float(rot[2, 2] * apex_z) <= float(solid.lowest_z_mm(rot[None])[0]) + 1e-6
            else "rim"
        )
    return "rim"


def phase_labels(
    solid: AnalyticSolid,
    rec: StepRecord,
    rotations: NDArray[np.float64],
    nearest: NDArray[np.intp],
) -> tuple[str, ...]:
    """Phase label per frame from the engine's state (see the module notes)."""
    kinds = contact_kinds(solid, rotations)
    round_line = not isinstance(solid, Cube | Tetrahedron)
    labels: list[str] = []
    for j, (step, kind) in enumerate(zip(nearest, kinds, strict=True)):
        if not rec.touching[step]:
            labels.append("lifted")
        elif rec.ramp[step] == 1:
            labels.append("placing")
        elif rec.ramp[step] == 2:
            labels.append("lifting")
        elif rec.speed_mm_s[step] > MOVING_MM_S:
            if rec.slip_mm_s[step] > SLIP_MM_S:
                labels.append("spinning" if rec.spin_share[step] > 0.5 else "sliding")
            elif isinstance(solid, Sphere) or (round_line and kind == "line"):
                labels.append("rolling")
            else:
                labels.append("tipping")
        else:
            labels.append(_still_label(solid, kind, rotations[j]))
    return tuple(labels)
