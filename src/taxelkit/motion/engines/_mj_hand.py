"""The "hand" of the MuJoCo scenes: segments of a script that apply forces, never poses.

Private to :mod:`taxelkit.motion.engines.mujoco_scenes`. A script is a list of
segments run one after the other; each reads the body's state at every physics
step and returns the external wrench (force and torque at the centroid, world
frame, SI units) that MuJoCo applies through ``xfrc_applied`` for the next
step. The motion itself comes from the physics: gravity, contact and friction
decide whether a pushed body rolls, tips or slides.

Actuation (all numbers assumed; paper 001 describes no manipulator)
-------------------------------------------------------------------
* held in the air (:class:`Hover`, :class:`Rise`, :class:`Gap`): a vertical
  spring-damper on the centroid height plus gravity compensation, and damping
  of the horizontal and angular velocity (a hand holding the body still);
* placed (:class:`Place`): lowered at :data:`DESCENT_MM_S` and let go at the
  first contact; the skin's press then ramps up;
* pushed (:class:`Push`): a horizontal force at the centroid tracking a speed
  profile (ramps of :data:`PUSH_RAMP_S`), along a fixed direction (a ball, a
  dragged face) or across the body's axis (a cylinder or a cone on its side:
  only the component across the axis is driven, the constraint of rolling
  decides the rest); :class:`Brake` brings the centroid to rest;
* tipped (:class:`~taxelkit.motion.engines._mj_tip.Tip`): a couple about a
  horizontal line through a bottom edge or a rim point;
* spun (:class:`Spin`): a couple about the vertical tracking a yaw rate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from taxelkit import _fixed_order as fo
from taxelkit.motion.engines._mjcf import GRAVITY_M_S2, M_PER_MM
from taxelkit.world.solids import AnalyticSolid
from taxelkit.world.solids_round import Cone, TruncatedCone

#: Height of the lowest point above the plate while the body is held lifted, mm.
HOVER_CLEARANCE_MM = 3.0
#: Speed at which the hand lowers and raises the body, mm/s.
DESCENT_MM_S = 10.0
#: Bandwidth of the hand holding the body in the air, Hz (critically damped).
HOLD_BANDWIDTH_HZ = 4.0
#: Time constant of the push and spin speed controllers, s (20 physics
#: steps). Both are PI controllers (integral time constant the same): a face
#: dragged on the sliding skin needs ``mu m g`` before it moves and a meshed
#: cone must be pushed over the corners of its polygon (about ``m g tan(pi /
#: sections)``), forces a proportional push at a few mm/s never reaches; the
#: integral gets there after lagging ``mu g tau**2`` = 0.4 mm behind.
PUSH_TIMECONST_S = 0.02
#: Speed ramps at the start and end of a push or a spin, s.
PUSH_RAMP_S = 0.2
#: Duration of a brake (speed held at zero after a push), s.
BRAKE_S = 0.3
#: Height of the short mid-script lift-off (:class:`Gap`), mm: well above the
#: few micrometres a resting body sinks into the plate.
GAP_CLEARANCE_MM = 0.3
#: Smallest press while the body touches (end of the lifting ramp): keeps
#: ``indent_mm > 0`` for every frame in contact.
PRESS_MIN = 0.05


@dataclass(frozen=True)
class BodyState:
    """The body's state at one physics step (SI units, world frame)."""

    t_s: float
    pos_m: NDArray[np.float64]
    rot: NDArray[np.float64]
    vel_m_s: NDArray[np.float64]
    omega_rad_s: NDArray[np.float64]
    touching: bool


@dataclass
class Hand:
    """What every segment shares: the body's mass properties and the skin's press.

    ``press`` (0-1) scales the documented indentation while the body touches;
    ``ramp`` is ``"placing"``/``"lifting"`` while the press ramps, else ``""``.
    """

    solid: AnalyticSolid
    mass_kg: float
    inertia_body: NDArray[np.float64]
    press: float = 0.0
    ramp: str = ""

    def inertia_world(self, rot: NDArray[np.float64]) -> NDArray[np.float64]:
        return fo.matmul(fo.matmul(rot, self.inertia_body), rot.T)

    def rest_z_m(self, rot: NDArray[np.float64]) -> float:
        """Centroid height with the body resting on the plate in this orientation, m."""
        return -float(self.solid.lowest_z_mm(rot[None])[0]) * M_PER_MM

    def hold(self, s: BodyState, z_m: float, vz_m_s: float) -> NDArray[np.float64]:
        """Wrench holding the body at height ``z_m`` (rate ``vz_m_s``), still otherwise."""
        w = 2.0 * math.pi * HOLD_BANDWIDTH_HZ
        f = np.zeros(6)
        f[:2] = -self.mass_kg * 2.0 * w * s.vel_m_s[:2]
        acc = w * w * (z_m - s.pos_m[2]) + 2.0 * w * (vz_m_s - s.vel_m_s[2])
        f[2] = self.mass_kg * (GRAVITY_M_S2 + acc)
        f[3:] = -2.0 * w * fo.matvec(self.inertia_world(s.rot), s.omega_rad_s)
        return f


def _profile(tau: float, duration: float, ramp: float) -> float:
    """Trapezoidal speed profile in [0, 1]: up over ``ramp``, down over the last ``ramp``."""
    return max(0.0, min(1.0, tau / ramp, (duration - tau) / ramp))


def smooth_step(u: float) -> float:
    """Cosine blend from 0 to 1 on ``u`` in [0, 1] (zero rate at both ends)."""
    u = min(1.0, max(0.0, u))
    return 0.5 - 0.5 * math.cos(math.pi * u)


@dataclass
class Segment:
    """Base of the script segments: ``start`` once, then ``wrench`` per step until None."""

    t0_s: float = field(default=0.0, init=False)

    def start(self, hand: Hand, s: BodyState) -> None:
        self.t0_s = s.t_s

    def wrench(self, hand: Hand, s: BodyState) -> NDArray[np.float64] | None:
        raise NotImplementedError


@dataclass
class Hover(Segment):
    """Hold the body lifted, lowest point :data:`HOVER_CLEARANCE_MM` above the plate."""

    duration_s: float = 0.5
    _z: float = field(default=0.0, init=False)

    def start(self, hand: Hand, s: BodyState) -> None:
        super().start(hand, s)
        self._z = hand.rest_z_m(s.rot) + HOVER_CLEARANCE_MM * M_PER_MM
        hand.ramp = ""

    def wrench(self, hand: Hand, s: BodyState) -> NDArray[np.float64] | None:
        if s.t_s - self.t0_s >= self.duration_s:
            return None
        return hand.hold(s, self._z, 0.0)


@dataclass
class Place(Segment):
    """Lower the body until it touches, let go, and ramp the press up over ``ramp_s``."""

    ramp_s: float = 0.4
    _touch_s: float | None = field(default=None, init=False)

    def wrench(self, hand: Hand, s: BodyState) -> NDArray[np.float64] | None:
        if self._touch_s is None and s.touching:
            self._touch_s = s.t_s
            hand.ramp = "placing"
        if self._touch_s is None:
            return hand.hold(s, float(s.pos_m[2]), -DESCENT_MM_S * M_PER_MM)
        hand.press = max(PRESS_MIN, min(1.0, (s.t_s - self._touch_s) / self.ramp_s))
        if s.t_s - self._touch_s >= self.ramp_s:
            hand.ramp = ""
            return None
        return np.zeros(6)


@dataclass
class Rest(Segment):
    """Leave the body alone (gravity and contact only)."""

    duration_s: float = 0.5

    def wrench(self, hand: Hand, s: BodyState) -> NDArray[np.float64] | None:
        return None if s.t_s - self.t0_s >= self.duration_s else np.zeros(6)


@dataclass
class Push(Segment):
    """Push the centroid horizontally, tracking a trapezoidal speed profile.

    ``mode``: ``"vector"`` drives the velocity along ``direction``; ``"across"``
    drives only the component across the body's axis (``sign`` picks the
    side), for a cylinder or a (truncated) cone on its side. For a cone the
    speed is that of its far rim (the centroid is driven at the matching
    fraction), ``distance_mm`` the far rim's path.
    """

    distance_mm: float = 5.0
    speed_mm_s: float = 4.0
    mode: str = "vector"
    direction: tuple[float, float] = (1.0, 0.0)
    sign: float = 1.0
    _duration: float = field(default=0.0, init=False)
    _centroid_speed: float = field(default=0.0, init=False)
    _integral: NDArray[np.float64] = field(default_factory=lambda: np.zeros(2), init=False)
    _last_s: float = field(default=0.0, init=False)

    def start(self, hand: Hand, s: BodyState) -> None:
        super().start(hand, s)
        self._integral = np.zeros(2)
        self._last_s = s.t_s
        self._duration = abs(self.distance_mm) / self.speed_mm_s + PUSH_RAMP_S
        ratio = 1.0
        if self.mode == "across" and isinstance(hand.solid, Cone | TruncatedCone):
            ratio = _centroid_over_far_rim(hand.solid, s)
        self._centroid_speed = self.speed_mm_s * ratio * M_PER_MM

    def wrench(self, hand: Hand, s: BodyState) -> NDArray[np.float64] | None:
        tau = s.t_s - self.t0_s
        if tau >= self._duration:
            return None
        speed = self._centroid_speed * _profile(tau, self._duration, PUSH_RAMP_S)
        if self.mode == "vector":
            err = speed * np.array(self.direction, dtype=np.float64) - s.vel_m_s[:2]
        else:
            a = s.rot[:, 2]  # e_z x a, horizontal: across the axis
            d = self.sign * np.array([-a[1], a[0]]) / max(math.hypot(a[0], a[1]), 1e-12)
            err = (speed - fo.scalar_dot(s.vel_m_s[:2], d)) * d
        self._integral += err * (s.t_s - self._last_s)
        self._last_s = s.t_s
        f = np.zeros(6)
        f[:2] = hand.mass_kg * (err / PUSH_TIMECONST_S + self._integral / PUSH_TIMECONST_S**2)
        return f


def _centroid_over_far_rim(solid: Cone | TruncatedCone, s: BodyState) -> float:
    """Horizontal distance apex-centroid over the far rim's distance from the apex."""
    prof = solid.profile
    a = s.rot[:, 2]
    apex = s.pos_m / M_PER_MM + prof.vertex_z_mm * a
    reach = max(math.hypot(r, z - prof.vertex_z_mm) for z, r in prof.rims)
    h = s.pos_m / M_PER_MM - apex
    centroid_h = math.hypot(float(h[0]), float(h[1]))
    return centroid_h / reach


@dataclass
class Brake(Segment):
    """Bring the centroid to rest and stop any spin about the vertical."""

    duration_s: float = BRAKE_S

    def wrench(self, hand: Hand, s: BodyState) -> NDArray[np.float64] | None:
        if s.t_s - self.t0_s >= self.duration_s:
            return None
        f = np.zeros(6)
        f[:2] = -hand.mass_kg * s.vel_m_s[:2] / PUSH_TIMECONST_S
        iz = float(hand.inertia_world(s.rot)[2, 2])
        f[5] = -iz * s.omega_rad_s[2] / PUSH_TIMECONST_S
        return f


@dataclass
class Spin(Segment):
    """Turn the body about the vertical through its centroid by ``angle_deg``."""

    angle_deg: float = 45.0
    speed_deg_s: float = 60.0
    _duration: float = field(default=0.0, init=False)
    _integral: float = field(default=0.0, init=False)
    _last_s: float = field(default=0.0, init=False)

    def start(self, hand: Hand, s: BodyState) -> None:
        super().start(hand, s)
        self._integral = 0.0
        self._last_s = s.t_s
        self._duration = abs(self.angle_deg) / self.speed_deg_s + PUSH_RAMP_S

    def wrench(self, hand: Hand, s: BodyState) -> NDArray[np.float64] | None:
        tau = s.t_s - self.t0_s
        if tau >= self._duration:
            return None
        rate = math.copysign(math.radians(self.speed_deg_s), self.angle_deg)
        rate *= _profile(tau, self._duration, PUSH_RAMP_S)
        err = rate - float(s.omega_rad_s[2])
        self._integral += err * (s.t_s - self._last_s)
        self._last_s = s.t_s
        f = np.zeros(6)
        f[:2] = -hand.mass_kg * s.vel_m_s[:2] / PUSH_TIMECONST_S
        iz = float(hand.inertia_world(s.rot)[2, 2])
        f[5] = iz * (err / PUSH_TIMECONST_S + self._integral / PUSH_TIMECONST_S**2)
        return f


@dataclass
class Unpress(Segment):
    """Ramp the press down over ``ramp_s`` with the body still resting."""

    ramp_s: float = 0.4

    def wrench(self, hand: Hand, s: BodyState) -> NDArray[np.float64] | None:
        tau = s.t_s - self.t0_s
        hand.ramp = "lifting"
        hand.press = max(PRESS_MIN, 1.0 - tau / self.ramp_s)
        return None if tau >= self.ramp_s else np.zeros(6)


@dataclass
class Rise(Segment):
    """Raise the body until its lowest point is :data:`HOVER_CLEARANCE_MM` above the plate."""

    _z0: float = field(default=0.0, init=False)
    _duration: float = field(default=0.0, init=False)

    def start(self, hand: Hand, s: BodyState) -> None:
        super().start(hand, s)
        self._z0 = float(s.pos_m[2])
        self._duration = HOVER_CLEARANCE_MM / DESCENT_MM_S

    def wrench(self, hand: Hand, s: BodyState) -> NDArray[np.float64] | None:
        tau = s.t_s - self.t0_s
        if tau >= self._duration:
            hand.ramp = ""
            return None
        u = tau / self._duration
        z = self._z0 + HOVER_CLEARANCE_MM * M_PER_MM * smooth_step(u)
        vz = HOVER_CLEARANCE_MM * M_PER_MM * 0.5 * math.pi * math.sin(math.pi * u) / self._duration
        return hand.hold(s, z, vz)


@dataclass
class Gap(Segment):
    """Lift the body clear by :data:`GAP_CLEARANCE_MM` and set it down, within ``duration_s``.

    The height follows half a sine wave; the body leaves the plate shortly
    after the start and lands shortly before the end, so contact is lost for
    about ``duration_s``. The press does not ramp: the loss is abrupt.
    """

    duration_s: float = 0.07
    _z0: float = field(default=0.0, init=False)

    def start(self, hand: Hand, s: BodyState) -> None:
        super().start(hand, s)
        self._z0 = float(s.pos_m[2])

    def wrench(self, hand: Hand, s: BodyState) -> NDArray[np.float64] | None:
        tau = s.t_s - self.t0_s
        if tau >= self.duration_s:
            return None
        w = math.pi / self.duration_s
        amp = GAP_CLEARANCE_MM * M_PER_MM
        z = self._z0 + amp * math.sin(w * tau)
        f = hand.hold(s, z, amp * w * math.cos(w * tau))
        f[2] -= hand.mass_kg * amp * w * w * math.sin(w * tau)  # feed-forward acceleration
        return f
