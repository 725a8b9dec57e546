"""Bodies of revolution bounded by two caps and a cone or cylinder: batched bottoms.

The engine behind :class:`~taxelkit.world.solids_round.Cylinder`,
:class:`~taxelkit.world.solids_round.Cone` and
:class:`~taxelkit.world.solids_round.TruncatedCone`.

Cylinders and (truncated) cones are the intersection of a *slab* between the
two cap planes and a *lateral quadric*

    (d . w)**2 - k |w|**2 + kappa >= 0,    w = p - v,

with ``v`` a point on the axis and ``d`` the unit axis pointing into the body.
A cylinder of radius ``r`` has ``v`` at its centre, ``k = 1`` and ``kappa =
r**2``; a cone of half-angle ``alpha`` has ``v`` at the apex, ``k =
cos(alpha)**2`` and ``kappa = 0`` (the slab also removes the second nappe).
Along the vertical line ``p = (x, y, t)`` the quadric reads ``A t**2 + 2 B t
+ C >= 0`` with ``A = d_z**2 - k`` fixed per pose and ``B, C`` linear and
quadratic in ``(x, y)``; its discriminant simplifies to

    B**2 - A C = k ((1 - k) rho**2 - c**2) - A kappa,

``rho`` the horizontal distance from ``v`` and ``c = d_x (y - v_y) - d_y (x -
v_x)``, so no large terms cancel. Where ``|A| >= A_SIMPLE`` the roots are
``(-B +- sqrt(disc)) / A`` with ``B / A``, ``disc / A**2`` and ``c / |A|``
evaluated directly (fewest grid operations); where ``A`` is small (an axis
nearly vertical for a cylinder, a generator nearly vertical for a cone) they
are taken in the stable form ``m / A`` and ``C / m`` with ``m = -(B + sign(B)
sqrt(disc))``, in float64 whatever the grid's dtype. An upright cylinder is a
disc test under its bottom cap. Depending on the sign of ``A`` and ``d_z``
the line meets the lateral surface in an interval (``A < 0``), in the ray
above the larger root (``A > 0``, body opening upwards) or in the ray below
the smaller root (``A > 0``, opening downwards); poses are grouped by that
case and form.

References
----------
Paper 001 (the six objects); the geometry is standard (ray-quadric
intersection with the numerically stable quadratic formula).
"""

from __future__ import annotations

import math
from abc import abstractmethod
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.world.revolution_roots import (
    BOUNDED,
    OPENS_DOWN,
    OPENS_UP,
    SIMPLE_COMBINE,
    STABLE_COMBINE,
    upright_cylinder,
)
from taxelkit.world.solid_methods import SolidMethods
from taxelkit.world.solids_grid import (
    TILT_EPS,
    PoseGroup,
    as_rotation_batch,
    evaluate_bottom,
    line_grid,
)
from taxelkit.world.solids_polyhedra import LOWEST_TIE_MM

__all__ = [
    "A_MIN",
    "A_SIMPLE",
    "A_VERTICAL",
    "RevolutionProfile",
    "RevolutionSolidMethods",
    "revolution_bottom_mm",
    "revolution_lowest_point_mm",
    "revolution_lowest_segment_mm",
    "revolution_lowest_z_mm",
]

#: Poses with ``|A| >= A_SIMPLE`` take the roots as ``(-B +- sqrt(disc)) / A``
#: (fewest operations); the error of that form grows like ``|B| / |A|``, so
#: poses with a smaller ``|A|`` use the stable form ``m / A, C / m``. The
#: stable form needs ``C``, a difference of squares of up to ~600 mm**2, so
#: it runs in float64 even for float32 grids (about 5-15 % of random poses).
A_SIMPLE = 0.1

#: Smallest ``|A|`` used by the stable form: ``A = 0`` (a vertical cylinder
#: axis or cone generator) is replaced by this value, a change of the body far
#: below any float precision of the result.
A_MIN = 1e-30

#: A cylinder whose axis leans by less than ``sqrt(A_VERTICAL)`` rad (1e-10)
#: is evaluated as exactly upright: its lateral surface only restricts
#: ``(x, y)`` to a disc.
A_VERTICAL = 1e-20


@dataclass(frozen=True)
class RevolutionProfile:
    """A body of revolution bounded by two caps and a lateral quadric (body frame).

    Attributes
    ----------
    k : float
        ``cos(alpha)**2`` for a cone of half-angle ``alpha``; 1 for a cylinder.
    sin2 : float
        ``1 - k``, stored separately for precision.
    kappa_mm2 : float, mm^2
        ``radius**2`` for a cylinder, 0 for a cone.
    vertex_z_mm : float, mm
        Axis point ``v``: the apex of a cone, the centre of a cylinder.
    direction : float
        +1 if the body lies towards +z from ``v`` (cone apex down), -1 if
        towards -z; +1 for a cylinder.
    z_low_mm, z_high_mm : float, mm
        The cap planes.
    rims : tuple of (z_mm, radius_mm)
        Circles whose convex hull is the body (for the lowest point).
    """

    k: float
    sin2: float
    kappa_mm2: float
    vertex_z_mm: float
    direction: float
    z_low_mm: float
    z_high_mm: float
    rims: tuple[tuple[float, float], ...]


def _lowest_rim_points_mm(profile: RevolutionProfile, rotations: ArrayLike) -> NDArray[np.float64]:
    """Lowest point of every rim circle, ``(P, R, 3)`` mm.

    Along each rim's steepest descent, as :func:`revolution_lowest_point_mm` explains.
    """
    rot = as_rotation_batch(rotations)
    a = rot[:, :, 2]
    tilt = np.hypot(a[:, 0], a[:, 1])
    down = -(np.array([0.0, 0.0, 1.0]) - a[:, 2:3] * a)
    safe = np.where(tilt > 1e-12, tilt, 1.0)[:, None]
    down = np.where(tilt[:, None] > 1e-12, down / safe, 0.0)
    return np.stack([zr * a + rr * down for zr, rr in profile.rims], axis=1)


def revolution_lowest_point_mm(
    profile: RevolutionProfile, rotations: ArrayLike
) -> NDArray[np.float64]:
    """Lowest point of rotated bodies of revolution, relative to the reference point.

    The lowest point of a rim circle (centre ``z a``, radius ``r``, normal
    ``a``) lies ``r`` from its centre along the steepest descent in its plane,
    ``-(e_z - a_z a) / sqrt(1 - a_z**2)``; an upright rim is lowest everywhere
    and contributes its centre. Tied rims (a cylinder on its side) are averaged.

    Returns
    -------
    (P, 3) float64, mm
    """
    pts = _lowest_rim_points_mm(profile, rotations)
    z = pts[..., 2]
    tied = z <= z.min(axis=1, keepdims=True) + 1e-6
    low: NDArray[np.float64] = (pts * tied[..., None]).sum(axis=1) / tied.sum(axis=1)[:, None]
    return low


def revolution_lowest_segment_mm(
    profile: RevolutionProfile, rotations: ArrayLike
) -> NDArray[np.float64]:
    """Ends of the lowest part of rotated bodies of revolution.

    A body lying on its side (a cylinder's or cone's generator horizontal) has
    its two lowest rim points tied (within :data:`LOWEST_TIE_MM`): the segment
    between them is the contact line, its ends in the order of the rims.
    Otherwise both ends are the single lowest point.

    The ends were once the lowest tied point and the last tied one: when the
    last rim's point came out lower by a rounding error, both ends were that
    point, and the line's groove in the skin became a point's dimple at one
    end. On a lying cone or truncated cone that happened in about half the
    poses, as the last digit fell (seed 0, ten kinematic rolls each: 734 of
    1,828 lying poses of cones, 982 of 1,651 of truncated cones, 18 of 1,085
    of cylinders), so another BLAS kernel gave other frames.

    Returns
    -------
    (P, 2, 3) float64, mm
    """
    pts = _lowest_rim_points_mm(profile, rotations)
    z = pts[..., 2]
    tied = z <= z.min(axis=1, keepdims=True) + LOWEST_TIE_MM
    first = np.argmax(tied, axis=1)  # the first and the last tied rim, whichever is lower
    last = tied.shape[1] - 1 - np.argmax(tied[:, ::-1], axis=1)
    rows = np.arange(z.shape[0])
    out: NDArray[np.float64] = np.stack([pts[rows, first], pts[rows, last]], axis=1)
    return out


def revolution_lowest_z_mm(profile: RevolutionProfile, rotations: ArrayLike) -> NDArray[np.float64]:
    """Lowest z of rotated bodies of revolution: the lowest point of their rims.

    A circle of radius ``r`` at height ``z`` on the axis ``a`` reaches down to
    ``z a_z - r sqrt(1 - a_z**2)``.

    Returns
    -------
    (P,) float64, mm
    """
    rot = as_rotation_batch(rotations)
    a = rot[:, :, 2]
    tilt = np.hypot(a[:, 0], a[:, 1])
    z = [zr * a[:, 2] - rr * tilt for zr, rr in profile.rims]
    low: NDArray[np.float64] = np.min(z, axis=0)
    return low


def _linear(c0: NDArray[np.float64], cx: Any, cy: Any, cq: Any = 0.0) -> NDArray[np.float64]:
    """(P, 4) coefficients of ``c0 + cx x + cy y + cq (x**2 + y**2)``."""
    return np.stack(np.broadcast_arrays(c0, cx, cy, cq), axis=1).astype(np.float64)


def _revolution_groups(profile: RevolutionProfile, rot: NDArray[np.float64]) -> list[PoseGroup]:
    """Per-pose function tables (on ``1, x, y, q``), grouped by case and form."""
    n_poses = rot.shape[0]
    k, kappa = profile.k, profile.kappa_mm2
    axis = rot[:, :, 2]
    d = profile.direction * axis
    v = profile.vertex_z_mm * axis
    dx, dy, dz = d[:, 0], d[:, 1], d[:, 2]
    vx, vy, vz = v[:, 0], v[:, 1], v[:, 2]
    tilt2 = dx * dx + dy * dy
    a_quad = profile.sin2 - tilt2
    case = np.where(a_quad <= 0.0, BOUNDED, np.where(dz > 0.0, OPENS_UP, OPENS_DOWN))
    upright = (tilt2 <= A_VERTICAL) if k == 1.0 else np.zeros(n_poses, dtype=bool)
    simple = ~upright & (np.abs(a_quad) >= A_SIMPLE)
    a_eff = np.where(a_quad <= 0.0, np.minimum(a_quad, -A_MIN), np.maximum(a_quad, A_MIN))

    g = _linear(-(dx * vx + dy * vy + dz * vz), dx, dy)
    bn = -dz[:, None] * g
    bn[:, 0] -= k * vz
    rho2 = _linear(vx * vx + vy * vy, -2.0 * vx, -2.0 * vy, 1.0)
    disc = (k * profile.sin2) * rho2
    disc[:, 0] -= a_eff * kappa
    cs = math.sqrt(k) * _linear(dy * vx - dx * vy, -dy, dx)
    crow = k * rho2
    crow[:, 0] += k * vz * vz - kappa
    az = axis[:, 2]
    sign = np.where(az < 0.0, -1.0, 1.0)
    inv_az = 1.0 / (sign * np.maximum(np.abs(az), TILT_EPS))
    z_first = np.where(sign > 0.0, profile.z_low_mm, profile.z_high_mm)
    z_second = np.where(sign > 0.0, profile.z_high_mm, profile.z_low_mm)
    cap_lo = _linear(z_first * inv_az, -axis[:, 0] * inv_az, -axis[:, 1] * inv_az)
    cap_hi = _linear(z_second * inv_az, -axis[:, 0] * inv_az, -axis[:, 1] * inv_az)

    groups: list[PoseGroup] = []

    def add(
        mask: NDArray[np.bool_],
        table: NDArray[np.float64],
        combine: Any,
        n_work: int,
        pose_values: NDArray[np.float64] | None = None,
        float64: bool = False,
    ) -> None:
        idx = np.flatnonzero(mask)
        if idx.size == 0:
            return
        if idx.size == n_poses:
            groups.append(PoseGroup(None, table, combine, n_work, pose_values, float64))
            return
        values = None if pose_values is None else pose_values[idx]
        groups.append(PoseGroup(idx, table[idx], combine, n_work, values, float64))

    if upright.any():
        rim = rho2.copy()
        rim[:, 0] -= kappa
        add(upright, np.stack([rim, cap_lo], axis=1), upright_cylinder, 1)
    if simple.any():
        inv_a = 1.0 / np.where(simple, a_quad, 1.0)
        s_disc = disc * (inv_a * inv_a)[:, None]
        s_cs = cs * np.abs(inv_a)[:, None]
        # rows as revolution_roots reads them: B/A, disc/A**2, c/|A|, caps
        table = np.stack([bn * inv_a[:, None], s_disc, s_cs, cap_lo, cap_hi], axis=1)
        for c, combine in SIMPLE_COMBINE.items():
            add(simple & (case == c), table, combine, 2)
    stable = ~upright & ~simple
    if stable.any():
        table = np.stack([bn, disc, cs, g, crow, cap_lo, cap_hi], axis=1)  # revolution_roots' rows
        inv_a_eff = (1.0 / a_eff)[:, None]
        for c, combine in STABLE_COMBINE.items():
            add(stable & (case == c), table, combine, 3, inv_a_eff, float64=True)
    return groups


def revolution_bottom_mm(
    profile: RevolutionProfile, rotations: ArrayLike, x_mm: ArrayLike, y_mm: ArrayLike
) -> NDArray[Any]:
    """Bottom of rotated bodies of revolution on a batch of vertical-line grids.

    Parameters
    ----------
    profile : RevolutionProfile
    rotations : (P, 3, 3) float
    x_mm : (P, W) float, mm
    y_mm : (P, H) float, mm

    Returns
    -------
    (P, H, W) float, mm
        In the dtype of ``x_mm``; ``+inf`` off the body.
    """
    rot = as_rotation_batch(rotations)
    grid = line_grid(x_mm, y_mm, rot.shape[0])
    return evaluate_bottom(grid, _revolution_groups(profile, rot))


class RevolutionSolidMethods(SolidMethods):
    """The :class:`~taxelkit.world.base.Solid` methods of a body of revolution.

    A subclass provides ``profile``, its :class:`RevolutionProfile`.
    """

    @property
    @abstractmethod
    def profile(self) -> RevolutionProfile:
        """The body's profile."""

    def _lowest_z(self, rotations: ArrayLike) -> NDArray[np.float64]:
        return revolution_lowest_z_mm(self.profile, rotations)

    def _lowest_point(self, rotations: ArrayLike) -> NDArray[np.float64]:
        return revolution_lowest_point_mm(self.profile, rotations)

    def _lowest_segment(self, rotations: ArrayLike) -> NDArray[np.float64]:
        return revolution_lowest_segment_mm(self.profile, rotations)

    def _bottom(self, rotations: ArrayLike, x_mm: ArrayLike, y_mm: ArrayLike) -> NDArray[Any]:
        return revolution_bottom_mm(self.profile, rotations, x_mm, y_mm)
