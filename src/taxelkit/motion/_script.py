"""Building blocks of the motion scripts: a frame recorder, replayable draws, body geometry.

Private to :mod:`taxelkit.motion.scenarios`. A script drives a
:class:`Builder` through holds, indentation ramps and motions; every motion is
one of the pose operations of :mod:`taxelkit.motion.rolling`, sampled at the
frame rate. Angles for tipping come from the body's geometry in its current
pose (balance over an edge, landing on the next face), so the scripts never
hard-code a body's dihedral angles. Fitting a finished script on the array
is :mod:`taxelkit.motion.array_placement`.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from taxelkit import _fixed_order as fo
from taxelkit.motion.roll_paths import roll_cone, roll_straight, rotate_about_line
from taxelkit.motion.rolling import E_Z, Pose
from taxelkit.world.solids import AnalyticSolid
from taxelkit.world.solids_polyhedra import Cube, Tetrahedron
from taxelkit.world.solids_round import Cone, Cylinder, TruncatedCone

# Timing and extents of the scripts: (low, high) ranges each draw is uniform in
# (assumed; paper 001 gives no speeds). At 20 Hz the shortest still state,
# 0.4 s, is 8 frames, and a tip of 90 deg at the fastest 120 deg/s is 15.

#: Still states (on a face, an edge, a rim, ...), s.
HOLD_S = (0.4, 0.9)
#: Lifted before placing and after lifting off, s.
LIFTED_S = (0.4, 0.9)
#: Indentation ramps when placing and lifting, s.
PLACE_S = (0.3, 0.5)
#: Tipping about an edge, tilting about a rim point or the apex, deg/s.
TIP_DEG_S = (60.0, 120.0)
#: Rolling, mm/s: a sphere's centre, a cylinder's line, a (truncated) cone's
#: far rim (its contact generator then turns at this over the rim's distance
#: from the apex, 11-23 deg/s for the default cone).
ROLL_MM_S = (3.0, 6.0)
#: Dragging a face across the sensor, mm/s.
SLIDE_MM_S = (3.0, 6.0)
#: Spinning a face in place, deg/s.
SPIN_DEG_S = (45.0, 90.0)
#: Length of each straight run of the sphere, mm.
SPHERE_RUN_MM = (4.0, 9.0)
#: Distance a cylinder rolls on its side, mm.
CYLINDER_ROLL_MM = (5.0, 10.0)
#: Turn of a cone's contact generator about its apex, deg.
CONE_TURN_DEG = (45.0, 90.0)
#: Turn of a truncated cone's contact generator about its virtual apex, deg.
FRUSTUM_TURN_DEG = (25.0, 45.0)
#: Drag distance of the sliding script, mm.
SLIDE_MM = (3.0, 8.0)
#: Spin angle of the sliding script, deg.
SPIN_DEG = (30.0, 90.0)
#: Rim and apex holds, as a fraction of the tilt from the face (or side) to
#: the next surface.
HOLD_FRACTION = (0.3, 0.55)
#: Chance that a polyhedron tips over onto the next face instead of back.
P_OVER = 0.4


class Draws:
    """A fixed stream of uniform numbers, replayed identically on every attempt."""

    def __init__(self, values: NDArray[np.float64]) -> None:
        self._values = values
        self._i = 0

    def uniform(self, low: float, high: float) -> float:
        assert self._i < self._values.size, "script drew more random numbers than planned"
        v = float(self._values[self._i])
        self._i += 1
        return low + (high - low) * v

    def span(self, bounds: tuple[float, float]) -> float:
        return self.uniform(*bounds)

    def index(self, n: int) -> int:
        return min(n - 1, int(self.uniform(0.0, n)))

    def coin(self, p: float = 0.5) -> bool:
        return self.uniform(0.0, 1.0) < p

    def sign(self) -> float:
        return 1.0 if self.coin() else -1.0


def unit_h(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Horizontal part of ``v``, normalised."""
    h = np.array([v[0], v[1], 0.0])
    out: NDArray[np.float64] = h / math.hypot(float(v[0]), float(v[1]))
    return out


class Builder:
    """Appends frames of a script; motions sample their end but not their start."""

    def __init__(self, solid: AnalyticSolid, pose: Pose, *, rate_hz: float, depth_mm: float):
        self.solid = solid
        self.pose = pose
        self.rate_hz = rate_hz
        self.depth_mm = depth_mm
        self._rots: list[NDArray[np.float64]] = []
        self._cents: list[NDArray[np.float64]] = []
        self._indent: list[NDArray[np.float64]] = []
        self._phase: list[str] = []

    def frames(self, duration_s: float) -> int:
        return max(1, round(duration_s * self.rate_hz))

    def _still(self, n: int, indent: NDArray[np.float64], labels: list[str]) -> None:
        self._rots.append(np.repeat(self.pose.rotation[None], n, axis=0))
        self._cents.append(np.repeat(self.pose.centroid_mm[None], n, axis=0))
        self._indent.append(indent)
        self._phase.extend(labels)

    def hold(self, duration_s: float, label: str) -> None:
        n = self.frames(duration_s)
        self._still(n, np.full(n, self.depth_mm), [label] * n)

    def lifted(self, duration_s: float) -> None:
        n = self.frames(duration_s)
        self._still(n, np.full(n, -self.depth_mm), ["lifted"] * n)

    def place(self, duration_s: float) -> None:
        n = self.frames(duration_s)
        self._still(n, self.depth_mm * np.arange(1, n + 1) / (n + 1), ["placing"] * n)

    def lift(self, duration_s: float) -> None:
        n = self.frames(duration_s)
        self._still(n, self.depth_mm * np.arange(n, 0, -1) / (n + 1), ["lifting"] * n)

    def move(
        self,
        op: Callable[[NDArray[np.float64]], tuple[NDArray[np.float64], NDArray[np.float64]]],
        duration_s: float,
        label: str,
        end_label: str,
    ) -> None:
        """Sample ``op`` at fractions ``1/n .. 1`` of the motion."""
        n = self.frames(duration_s)
        rots, cents = op(np.arange(1, n + 1) / n)
        self._rots.append(rots)
        self._cents.append(cents)
        self._indent.append(np.full(n, self.depth_mm))
        self._phase.extend([label] * (n - 1) + [end_label])
        self.pose = Pose(rots[-1], cents[-1])

    def rotate(
        self,
        point: NDArray[np.float64],
        axis: NDArray[np.float64],
        angle_rad: float,
        speed_deg_s: float,
        label: str,
        end_label: str,
    ) -> None:
        pose = self.pose
        self.move(
            lambda u: rotate_about_line(pose, point, axis, u * angle_rad),
            abs(math.degrees(angle_rad)) / speed_deg_s,
            label,
            end_label,
        )

    @property
    def phases(self) -> tuple[str, ...]:
        return tuple(self._phase)

    def arrays(self) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        return (
            np.concatenate(self._rots),
            np.concatenate(self._cents),
            np.concatenate(self._indent),
        )


# --- geometry of the bodies in a pose -------------------------------------------------------


def bottom_polygon(solid: Cube | Tetrahedron, pose: Pose) -> NDArray[np.float64]:
    """World vertices touching the plane, counter-clockwise around their mean."""
    v = pose.world_mm(solid.vertices_mm)
    low = v[v[:, 2] <= v[:, 2].min() + 1e-6]
    mid = low.mean(axis=0)
    order = np.argsort(fo.arctan2(low[:, 1] - mid[1], low[:, 0] - mid[0]))
    out: NDArray[np.float64] = low[order]
    return out


def balance_angle(pose: Pose, pivot: NDArray[np.float64], u: NDArray[np.float64]) -> float:
    """Tip towards ``u`` about a horizontal line through ``pivot`` until the centroid is above it.

    With the axis ``e_z x u`` a positive angle tips the top towards ``u``; the
    centroid ``w = c - pivot`` is above the line at ``atan2(-(w . u), w_z)``.
    """
    w = pose.centroid_mm - pivot
    return math.atan2(-fo.scalar_dot(w, u), float(w[2]))


def landing_angle(
    points: NDArray[np.float64], pivot: NDArray[np.float64], u: NDArray[np.float64]
) -> float:
    """Tip towards ``u`` about a horizontal line through ``pivot`` until a point lands.

    A point ``q`` (relative to the pivot) reaches the plane at ``atan2(q_z, q . u)``
    taken in ``[0, 2 pi)`` (a point of the resting face, ``q_z = 0`` behind the
    line, only after half a turn); points on the line itself are ignored.
    """
    k = np.cross(E_Z, u)
    q = points - pivot
    off_line = fo.norm(q - np.outer(fo.dot(q, k), k)) > 1e-6
    angles = np.mod(fo.arctan2(q[off_line, 2], fo.dot(q[off_line], u)), 2.0 * math.pi)
    return float(np.min(angles))


def rims(solid: Cylinder | Cone | TruncatedCone) -> list[tuple[float, float]]:
    """``(z, radius)`` of the bottom then the top rim, body frame (radius 0: an apex)."""
    return list(solid.profile.rims)


def rim_lowest(pose: Pose, z: float, r: float) -> NDArray[np.float64]:
    """Lowest point of a rim circle (body height ``z``, radius ``r``) of a tilted body."""
    a = pose.rotation[:, 2]
    centre = pose.centroid_mm + z * a
    if r == 0.0:
        return centre
    down = -(E_Z - a[2] * a)
    out: NDArray[np.float64] = centre + r * down / fo.scalar_norm(down)
    return out


def face_down_rim(solid: Cylinder | Cone | TruncatedCone, pose: Pose) -> int:
    """Index (into ``profile.rims``) of the flat face resting on the plane."""
    return 0 if pose.rotation[2, 2] > 0 else 1


def _tip_off_face(b: Builder, u: NDArray[np.float64]) -> tuple[NDArray[np.float64], float]:
    """Pivot (the face's rim point towards ``u``) and the turn that lays the body on its side."""
    solid = b.solid
    assert isinstance(solid, Cylinder | Cone | TruncatedCone)
    rim_list = rims(solid)
    i = face_down_rim(solid, b.pose)
    a = b.pose.rotation[:, 2]
    pivot = b.pose.centroid_mm + rim_list[i][0] * a + rim_list[i][1] * u
    other = b.pose.centroid_mm + rim_list[1 - i][0] * a + rim_list[1 - i][1] * u
    return pivot, landing_angle(other[None], pivot, u)


def tilt_from_face(b: Builder, u: NDArray[np.float64], d: Draws, *, lay: bool) -> None:
    """Tilt a round body from its face onto the rim towards ``u``, hold, then lay it down or not."""
    pivot, landing = _tip_off_face(b, u)
    k = np.cross(E_Z, u)
    speed = d.span(TIP_DEG_S)
    held = d.span(HOLD_FRACTION) * landing
    b.rotate(pivot, k, held, speed, "tipping", "rim")
    b.hold(d.span(HOLD_S), "rim")
    if lay:
        b.rotate(pivot, k, landing - held, speed, "tipping", "side")
        b.hold(d.span(HOLD_S), "side")
    else:
        b.rotate(pivot, k, -held, speed, "tipping", "face")
        b.hold(d.span(HOLD_S), "face")


def stand_up(b: Builder, end: int, d: Draws) -> None:
    """From lying on the side, tilt up about the lowest point of rim ``end`` onto that face."""
    solid = b.solid
    assert isinstance(solid, Cylinder | Cone | TruncatedCone)
    rim_list = rims(solid)
    if rim_list[end][1] == 0.0:
        end = 1 - end  # a cone's apex has no face
    pivot = rim_lowest(b.pose, *rim_list[end])
    u = unit_h(pivot - rim_lowest(b.pose, *rim_list[1 - end]))
    a = b.pose.rotation[:, 2]
    normal = a if end == 1 else -a
    angle = math.atan2(float(normal[2]), fo.scalar_dot(normal, u)) + math.pi / 2.0
    k = np.cross(E_Z, u)
    speed = d.span(TIP_DEG_S)
    held = (1.0 - d.span(HOLD_FRACTION)) * angle
    b.rotate(pivot, k, held, speed, "tipping", "rim")
    b.hold(d.span(HOLD_S), "rim")
    b.rotate(pivot, k, angle - held, speed, "tipping", "face")
    b.hold(d.span(HOLD_S), "face")


def lay_silently(b: Builder, u: NDArray[np.float64]) -> None:
    """Put a standing round body on its side (towards ``u``) without recording frames."""
    pivot, landing = _tip_off_face(b, u)
    rots, cents = rotate_about_line(b.pose, pivot, np.cross(E_Z, u), landing)
    b.pose = Pose(rots[0], cents[0])


def apex_and_axis(
    solid: Cone | TruncatedCone, pose: Pose
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The (virtual) apex in the sensor frame and the axis from it into the body."""
    prof = solid.profile
    a = pose.rotation[:, 2]
    return pose.centroid_mm + prof.vertex_z_mm * a, prof.direction * a


def roll_about_apex(b: Builder, turn_rad: float, speed_mm_s: float, end_label: str) -> None:
    """Roll a lying (truncated) cone about its (virtual) apex by ``turn_rad``.

    The far rim's contact point travels at ``speed_mm_s``.
    """
    solid = b.solid
    assert isinstance(solid, Cone | TruncatedCone)
    apex, axis = apex_and_axis(solid, b.pose)
    reach = max(fo.scalar_norm(rim_lowest(b.pose, z, r) - apex) for z, r in rims(solid))
    pose = b.pose
    b.move(
        lambda u: roll_cone(pose, apex, axis, u * turn_rad),
        abs(turn_rad) * reach / speed_mm_s,
        "rolling",
        end_label,
    )


def roll_line(
    b: Builder,
    radius: float,
    direction: NDArray[np.float64],
    dist: float,
    speed: float,
    end_label: str,
) -> None:
    """Roll a sphere or a lying cylinder ``dist`` mm along ``direction``."""
    pose = b.pose
    b.move(
        lambda u: roll_straight(pose, radius, direction, u * dist),
        abs(dist) / speed,
        "rolling",
        end_label,
    )


def rest_pose(solid: AnalyticSolid, rotation: NDArray[np.float64]) -> Pose:
    """The body resting on the plane with its centroid above the origin."""
    return Pose(rotation, np.array([0.0, 0.0, -float(solid.lowest_z_mm(rotation[None])[0])]))


def begin_contact(b: Builder, d: Draws, label: str) -> None:
    """Lifted, placed with an indentation ramp, then held still as ``label``."""
    b.lifted(d.span(LIFTED_S))
    b.place(d.span(PLACE_S))
    b.hold(d.span(HOLD_S), label)


def end_contact(b: Builder, d: Draws) -> None:
    """Lifted off with an indentation ramp, then left lifted."""
    b.lift(d.span(PLACE_S))
    b.lifted(d.span(LIFTED_S))
