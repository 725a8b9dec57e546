"""Ground truth of a posed solid's contact with the sensor plane: where, what kind, how it slips.

These functions read the world's geometry, so they belong to scenario
generation, tests and reports only; a recogniser must never call them (it sees
frames, nothing else).

Method
------
Each solid is represented by *candidate* material points that contain its
possible contacts with a plane: the vertices of a polyhedron; for a body of
revolution, :data:`RIM_SAMPLES` points on every rim circle, the exact lowest
point of every rim in the given pose, and the apex of a cone; for a sphere,
the point straight below its centre. The candidates within
:data:`CONTACT_TIE_MM` of the lowest one form the contact set. Its spread
gives the contact type (one point, a segment, a patch), and following the
same material points from one pose to the next gives the slip: zero for
rolling without slip up to the second order in the step, the step itself for
sliding.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit import _fixed_order as fo
from taxelkit.errors import InputError
from taxelkit.world.base import Solid
from taxelkit.world.pose import check_rotations
from taxelkit.world.solids_round import Sphere

__all__ = [
    "CONTACT_SPREAD_MM",
    "CONTACT_TIE_MM",
    "CONTACT_TYPES",
    "POSE_CHUNK",
    "RIM_SAMPLES",
    "ContactState",
    "contact_points_body_mm",
    "contact_state",
    "contact_types",
    "kind_indices",
    "slip_from_poses",
]

#: Candidate points within this height of the lowest one touch the plane, mm.
#: Far above the rounding of composed rotations (about 1e-14 mm) and far below
#: the drop of the rim samples next to a tilted rim's lowest point
#: (``r (1 - cos(pi / RIM_SAMPLES)) sin(tilt)``, 1e-4 mm at a 2 deg tilt).
CONTACT_TIE_MM = 1e-6

#: A contact set whose RMS spread along its widest (second widest) direction is
#: below this is a point (a line), mm. Above the sideways offset of a rim
#: sample that ties with the rim's exact lowest point (at most
#: ``sqrt(2 r CONTACT_TIE_MM)``, 4e-3 mm for r = 8 mm), far below a taxel.
CONTACT_SPREAD_MM = 0.01

#: Points per rim circle of a body of revolution: enough to outline a flat
#: face's contact disc (the exact lowest point of a tilted rim is added per pose).
RIM_SAMPLES = 256

#: Poses per batch of :func:`contact_types` and of the engines' geometric
#: contact (bounds the memory of the candidates of round bodies: 2 x 257
#: points per pose).
POSE_CHUNK = 2000

#: Contact types, from nothing to a patch (the classes of paper 001, Level 2,
#: without "indeterminate", which only a sensor can produce).
CONTACT_TYPES: tuple[str, ...] = ("none", "point", "line", "area")


def _revolution_candidates(solid: Any, rot: NDArray[np.float64]) -> NDArray[np.float64]:
    n_poses = rot.shape[0]
    # World "down" in body coordinates: R^T (0, 0, -1) = -(row 2 of R).
    down = -rot[:, 2, :]
    horiz = np.hypot(down[:, 0], down[:, 1])
    tilted = horiz > 1e-12
    safe = np.where(tilted, horiz, 1.0)
    dx = np.where(tilted, down[:, 0] / safe, 1.0)
    dy = np.where(tilted, down[:, 1] / safe, 0.0)
    ang = 2.0 * np.pi * np.arange(RIM_SAMPLES) / RIM_SAMPLES
    parts: list[NDArray[np.float64]] = []
    for z, r in solid.profile.rims:
        if r == 0.0:
            parts.append(np.broadcast_to(np.array([0.0, 0.0, z]), (n_poses, 1, 3)))
            continue
        ring = np.stack([r * np.cos(ang), r * np.sin(ang), np.full(ang.shape, z)], axis=1)
        parts.append(np.broadcast_to(ring, (n_poses, RIM_SAMPLES, 3)))
        low = np.stack([r * dx, r * dy, np.full(n_poses, z)], axis=1)
        parts.append(low[:, None, :])
    return np.concatenate(parts, axis=1)


def contact_points_body_mm(solid: Solid, rotations: ArrayLike) -> NDArray[np.float64]:
    """Candidate contact points of a solid, in its body frame, for each pose.

    Parameters
    ----------
    solid : Solid
        A :class:`~taxelkit.world.solids_round.Sphere`, a body of revolution
        (anything with a ``profile``: cylinder, cone, truncated cone) or a
        polyhedron (anything with ``vertices_mm``: cube, tetrahedron, mesh).
    rotations : (P, 3, 3) float
        Body-to-sensor rotations.

    Returns
    -------
    (P, K, 3) float, mm
        Material points relative to the reference point (body frame) that
        contain every possible contact with a horizontal plane below the body.

    Raises
    ------
    InputError
        For a solid of none of these kinds, or invalid rotations.
    """
    rot = check_rotations(rotations)
    if isinstance(solid, Sphere):
        return (-float(solid.radius_mm) * rot[:, 2, :])[:, None, :]
    if hasattr(solid, "profile"):
        return _revolution_candidates(solid, rot)
    vertices = getattr(solid, "vertices_mm", None)
    if vertices is not None:
        v = np.asarray(vertices, dtype=np.float64)
        return np.broadcast_to(v, (rot.shape[0], *v.shape)).copy()
    raise InputError(
        f"solid {getattr(solid, 'name', solid)!r} has no contact candidates: "
        "expected a Sphere, a body with a profile, or a body with vertices_mm"
    )


def _relative_world(rot: NDArray[np.float64], body: NDArray[np.float64]) -> NDArray[np.float64]:
    """Candidates rotated into the sensor frame, still relative to the reference point."""
    return fo.rotate_points(body, rot)


def kind_indices(
    pts: NDArray[np.float64], touching: NDArray[np.bool_], spread_mm: float = CONTACT_SPREAD_MM
) -> NDArray[np.intp]:
    """Contact type per pose, as an index of :data:`CONTACT_TYPES` (1 point, 2 line, 3 area).

    Parameters
    ----------
    pts : (P, K, 3) float, mm
        Candidate points (sensor orientation).
    touching : (P, K) bool
        Which of them touch the plane.
    spread_mm : float
        RMS spread of the touching points along their widest (second widest)
        direction below which the contact is a point (a line), mm.

    Returns
    -------
    (P,) intp
    """
    w = touching.astype(np.float64)
    w /= w.sum(axis=1, keepdims=True)
    mean = fo.matmul(w[:, None, :], pts)  # (P, 1, 3)
    d = pts - mean
    cov = fo.matmul(np.swapaxes(d * w[..., None], 1, 2), d)
    eig = np.linalg.eigvalsh(cov)  # ascending
    tol2 = spread_mm**2
    out: NDArray[np.intp] = np.where(eig[:, 2] <= tol2, 1, np.where(eig[:, 1] <= tol2, 2, 3))
    return out


def _types_from(
    pts: NDArray[np.float64], touching: NDArray[np.bool_], spread_mm: float = CONTACT_SPREAD_MM
) -> tuple[str, ...]:
    """Contact types from candidate points ``(P, K, 3)`` and which touch ``(P, K)``."""
    return tuple(CONTACT_TYPES[int(k)] for k in kind_indices(pts, touching, spread_mm))


@dataclass(frozen=True, eq=False)
class ContactState:
    """Candidate contact points of a posed solid and which of them touch the plane.

    Attributes
    ----------
    body_mm : (P, K, 3) float, mm
        Candidate material points, body frame (:func:`contact_points_body_mm`).
    relative_mm : (P, K, 3) float, mm
        The same points in the sensor frame's orientation, relative to the
        reference point (``R p``).
    touching : (P, K) bool
        Candidates within :data:`CONTACT_TIE_MM` of the lowest candidate.
    """

    body_mm: NDArray[np.float64]
    relative_mm: NDArray[np.float64]
    touching: NDArray[np.bool_]

    @property
    def kinds(self) -> tuple[str, ...]:
        """Contact type per pose, see :func:`contact_types`."""
        return _types_from(self.relative_mm, self.touching)


def contact_state(
    solid: Solid, rotations: ArrayLike, *, tie_mm: float = CONTACT_TIE_MM
) -> ContactState:
    """Candidate points of a solid under each pose and which of them touch the plane.

    Parameters
    ----------
    solid : Solid
    rotations : (P, 3, 3) float
    tie_mm : float
        Candidates within this height of the lowest one touch, mm (default
        :data:`CONTACT_TIE_MM`, for exact poses).

    Returns
    -------
    ContactState
    """
    rot = check_rotations(rotations)
    body = contact_points_body_mm(solid, rot)
    rel = _relative_world(rot, body)
    z = rel[..., 2]
    return ContactState(body, rel, z <= z.min(axis=1, keepdims=True) + tie_mm)


def contact_types(
    solid: Solid,
    rotations: ArrayLike,
    *,
    tie_mm: float = CONTACT_TIE_MM,
    spread_mm: float = CONTACT_SPREAD_MM,
) -> tuple[str, ...]:
    """Geometric contact type of a rigid solid resting on a plane, per pose.

    Parameters
    ----------
    solid : Solid
    rotations : (P, 3, 3) float
    tie_mm, spread_mm : float
        Candidates within ``tie_mm`` of the lowest one touch; their RMS spread
        is compared with ``spread_mm`` (mm). The defaults suit exact poses
        (kinematic scripts); a body resting on a physics engine's soft
        contacts is level only to micrometres and needs wider ones
        (:data:`~taxelkit.motion.engines._sampling.PHYSICS_TIE_MM`).

    Returns
    -------
    tuple of str, length P
        ``"point"``, ``"line"`` or ``"area"``: the contact set is one point, a
        segment, or spans a patch (RMS spreads against ``spread_mm``).

    Notes
    -----
    This is the contact of the rigid body with the undeformed plane. The sensor
    presses the body ``indent_mm`` into its skin, so near a transition (a face
    just lifting off, a rim just landing) its image can still look like the
    previous type: those are the spurious images paper 001 debounces.
    """
    rot = check_rotations(rotations)
    out: list[str] = []
    for start in range(0, rot.shape[0], POSE_CHUNK):  # bounds the candidates' memory
        state = contact_state(solid, rot[start : start + POSE_CHUNK], tie_mm=tie_mm)
        out.extend(_types_from(state.relative_mm, state.touching, spread_mm))
    return tuple(out)


def slip_from_poses(
    solid: Solid,
    rotations: ArrayLike,
    centroids_mm: ArrayLike,
    *,
    full: bool = False,
) -> NDArray[np.float64]:
    """Largest displacement of the material contact points between consecutive poses.

    Parameters
    ----------
    solid : Solid
    rotations : (T, 3, 3) float
        Body-to-sensor rotations.
    centroids_mm : (T, 3) float, mm
        Positions of the reference point in the sensor frame.
    full : bool
        False: horizontal displacement only (the slip along the plane). True:
        the full 3-D displacement.

    Returns
    -------
    (T - 1,) float, mm
        For each step ``t -> t + 1``: the points touching the plane at ``t``
        are followed as material points to pose ``t + 1``; the largest
        displacement among them. Rolling without slip gives ``O(step**2)``
        (full) and ``O(step**3)`` (horizontal, a cycloid's cusp); a body
        tipping off a face lifts the face's points by ``O(step)`` but moves them
        horizontally by ``O(step**2)``; sliding gives the step itself.

    Raises
    ------
    InputError
        On mismatched shapes.
    """
    rot = check_rotations(rotations)
    cen = np.asarray(centroids_mm, dtype=np.float64)
    if cen.shape != (rot.shape[0], 3):
        raise InputError(f"centroids_mm must have shape ({rot.shape[0]}, 3), got {cen.shape}")
    if rot.shape[0] < 2:
        return np.zeros(0)
    state = contact_state(solid, rot[:-1])
    touching = state.touching
    before = state.relative_mm + cen[:-1, None, :]
    after = _relative_world(rot[1:], state.body_mm) + cen[1:, None, :]
    step = after - before
    if not full:
        step = step[..., :2]
    dist = np.linalg.norm(step, axis=-1)
    out: NDArray[np.float64] = np.where(touching, dist, 0.0).max(axis=1)
    return out
