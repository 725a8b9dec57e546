"""Tipping by a couple: a polyhedron over a bottom edge, a round body over its rim.

Private to :mod:`taxelkit.motion.engines.mujoco_scenes`. The hand applies a
couple about a horizontal line through the pivot (a bottom edge's midpoint, or
the point of the resting face's rim towards the tilt), from a PD controller on
the tilt angle with the moment of gravity about that line fed forward: tilt
up, hold, then back or over towards the next face (or the side), and let go
:data:`RELEASE_MARGIN_DEG` before landing, so the last degrees are a fall under
gravity. Whether the body pivots about the edge without sliding is up to
friction.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from taxelkit import _fixed_order as fo
from taxelkit.motion._script import balance_angle, landing_angle, unit_h
from taxelkit.motion.engines._mj_hand import BodyState, Hand, Segment, smooth_step
from taxelkit.motion.engines._mjcf import GRAVITY_M_S2, M_PER_MM
from taxelkit.motion.rolling import E_Z, Pose
from taxelkit.world.solids_polyhedra import Cube, Tetrahedron
from taxelkit.world.solids_round import Cone, Cylinder, TruncatedCone

#: Bandwidth of the tilt controller, Hz (critically damped): fast next to a
#: tilt that lasts 0.2-1.5 s, slow next to the 1 kHz physics step. The moment
#: of gravity about the pivot line is fed forward, so the PD part only
#: corrects what is not modelled (the reaction forces at the pivot pass
#: through the line and exert none).
TILT_BANDWIDTH_HZ = 6.0

#: The tilt controller lets go this far before a face or a side lands, deg:
#: the last few degrees are a fall under gravity.
RELEASE_MARGIN_DEG = 3.0

#: Vertices within this height of the lowest one form the bottom face, mm: a
#: face resting on the plate after a landing is level to well within this.
FACE_TIE_MM = 0.05

#: An edge whose midpoint lies within this distance of the edge just tipped
#: over is that edge (the next tip must use another one), mm.
SAME_EDGE_MM = 1.0


@dataclass
class Tip(Segment):
    """Tilt about a bottom edge (polyhedron) or a rim point (round body on a face), hold, finish.

    ``choice`` in [0, 1) picks the bottom edge (polyhedra; never the edge the
    ``previous`` tip turned about); for a round body ``direction`` (horizontal, world) is
    where the top tilts to. The tilt goes to ``hold_fraction`` of the balance
    angle (polyhedra) or of the landing angle (a round body's rim), holds for
    ``hold_s``, then goes back (``over=False``) or on towards the next face
    or the side, and lets go :data:`RELEASE_MARGIN_DEG` before landing.
    """

    choice: float = 0.0
    direction: tuple[float, float] = (1.0, 0.0)
    hold_fraction: float = 0.4
    hold_s: float = 0.5
    over: bool = False
    speed_deg_s: float = 90.0
    previous: Tip | None = None
    pivot_xy_mm: tuple[float, float] = field(default=(0.0, 0.0), init=False)
    _plan: tuple[float, ...] = field(default=(), init=False)
    _pivot: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3), init=False)
    _u: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3), init=False)
    _a0: NDArray[np.float64] = field(default_factory=lambda: np.zeros(3), init=False)
    _ik: float = field(default=0.0, init=False)

    def start(self, hand: Hand, s: BodyState) -> None:
        super().start(hand, s)
        solid = hand.solid
        pose = Pose(s.rot, s.pos_m / M_PER_MM)
        if isinstance(solid, Cube | Tetrahedron):
            avoid = None if self.previous is None else self.previous.pivot_xy_mm
            pivot, u = _pick_edge(solid, pose, self.choice, avoid)
            end_angle = landing_angle(pose.world_mm(solid.vertices_mm), pivot, u)
            hold = self.hold_fraction * balance_angle(pose, pivot, u)
        else:
            assert isinstance(solid, Cylinder | Cone | TruncatedCone)
            u = unit_h(np.array([*self.direction, 0.0]))
            pivot, other = _rim_points(solid, pose, u)
            end_angle = landing_angle(other[None], pivot, u)
            hold = self.hold_fraction * end_angle
        margin = math.radians(RELEASE_MARGIN_DEG)
        final = end_angle - margin if self.over else margin
        speed = math.radians(self.speed_deg_s)
        t1 = hold / speed
        t2 = t1 + self.hold_s
        t3 = t2 + abs(final - hold) / speed
        self._plan = (hold, final, t1, t2, t3)
        self._pivot, self._u, self._a0 = pivot, u, s.rot[2, :].copy()
        self.pivot_xy_mm = (float(pivot[0]), float(pivot[1]))
        k = np.cross(E_Z, u)
        lever = pose.centroid_mm - pivot
        lever_perp = (lever - fo.scalar_dot(lever, k) * k) * M_PER_MM
        self._ik = fo.scalar_dot(
            k, fo.matvec(hand.inertia_world(s.rot), k)
        ) + hand.mass_kg * fo.scalar_dot(lever_perp, lever_perp)

    def _target(self, tau: float) -> tuple[float, float]:
        hold, final, t1, t2, t3 = self._plan
        if tau < t1:
            return hold * smooth_step(tau / t1), hold / t1 if t1 > 0 else 0.0
        if tau < t2:
            return hold, 0.0
        u = (tau - t2) / max(t3 - t2, 1e-9)
        rate = (final - hold) / max(t3 - t2, 1e-9)
        return hold + (final - hold) * smooth_step(u), rate

    def wrench(self, hand: Hand, s: BodyState) -> NDArray[np.float64] | None:
        tau = s.t_s - self.t0_s
        if tau >= self._plan[4]:
            return None
        k = np.array([-self._u[1], self._u[0], 0.0])  # e_z x u
        a = fo.matvec(s.rot, self._a0)
        angle = math.atan2(fo.scalar_dot(a, self._u), float(a[2]))
        rate = fo.scalar_dot(s.omega_rad_s, k)
        target, target_rate = self._target(tau)
        w = 2.0 * math.pi * TILT_BANDWIDTH_HZ
        lever = s.pos_m - self._pivot * M_PER_MM
        # moment of gravity about k: (lever x (0, 0, -m g)) . k
        weight = hand.mass_kg * GRAVITY_M_S2
        gravity_moment = -weight * float(lever[1] * k[0] - lever[0] * k[1])
        torque_k = self._ik * (w * w * (target - angle) + 2.0 * w * (target_rate - rate))
        torque_k -= gravity_moment
        f = np.zeros(6)
        omega_off = s.omega_rad_s - rate * k
        f[3:] = torque_k * k - 2.0 * w * fo.matvec(hand.inertia_world(s.rot), omega_off)
        return f


def _pick_edge(
    solid: Cube | Tetrahedron,
    pose: Pose,
    choice: float,
    avoid_xy_mm: tuple[float, float] | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Pivot (edge midpoint on the plane, mm) and outward horizontal unit of a bottom edge."""
    v = pose.world_mm(solid.vertices_mm)
    low = v[v[:, 2] <= v[:, 2].min() + FACE_TIE_MM]
    mid = low.mean(axis=0)
    poly = low[np.argsort(fo.arctan2(low[:, 1] - mid[1], low[:, 0] - mid[0]))]
    mids = 0.5 * (poly + np.roll(poly, -1, axis=0))
    options = list(range(len(poly)))
    if avoid_xy_mm is not None:
        far = [j for j in options if np.hypot(*(mids[j, :2] - avoid_xy_mm)) > SAME_EDGE_MM]
        options = far or options
    j = options[min(len(options) - 1, int(choice * len(options)))]
    e = unit_h(poly[(j + 1) % len(poly)] - poly[j])
    pivot = mids[j].copy()
    pivot[2] = 0.0
    w = pivot - pose.centroid_mm
    u = unit_h(w - fo.scalar_dot(w, e) * e)
    return pivot, u


def _rim_points(
    solid: Cylinder | Cone | TruncatedCone, pose: Pose, u: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Pivot on the resting face's rim towards ``u`` and the other rim's point, mm."""
    rims = list(solid.profile.rims)
    a = pose.rotation[:, 2]
    i = 0 if a[2] > 0 else 1
    pivot = pose.centroid_mm + rims[i][0] * a + rims[i][1] * u
    pivot[2] = 0.0
    other = pose.centroid_mm + rims[1 - i][0] * a + rims[1 - i][1] * u
    return pivot, other
