"""Rigid motions of a body on the sensor plane: rolling along a line, rolling a cone, translating.

Each function turns a :class:`~taxelkit.motion.rolling.Pose` and a path
parameter into the poses of the body over the frames; the scripts of
:mod:`taxelkit.motion._script` chain them into scenarios.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit import _fixed_order as fo
from taxelkit.errors import InputError, check_finite_array, check_positive
from taxelkit.motion.rolling import E_Z, Pose
from taxelkit.world.pose import matrix_from_axis_angle

__all__ = ["roll_cone", "roll_straight", "rotate_about_line", "translate"]


def _samples(name: str, values: ArrayLike) -> NDArray[np.float64]:
    v = np.atleast_1d(np.asarray(values, dtype=np.float64))
    if v.ndim != 1:
        raise InputError(f"{name} must be a scalar or have shape (n,), got {v.shape}")
    check_finite_array(name, v)
    return v


def _vector3(name: str, value: ArrayLike) -> NDArray[np.float64]:
    v = np.asarray(value, dtype=np.float64)
    if v.shape != (3,):
        raise InputError(f"{name} must have shape (3,), got {v.shape}")
    check_finite_array(name, v)
    return v


def _unit(name: str, value: ArrayLike) -> NDArray[np.float64]:
    v = _vector3(name, value)
    n = float(np.linalg.norm(v))
    if n < 1e-12:
        raise InputError(f"{name} must be non-zero, got {v.tolist()}")
    return v / n


def rotate_about_line(
    pose: Pose, point_mm: ArrayLike, axis: ArrayLike, angles_rad: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Turn a posed body about a fixed line (tipping over an edge, tilting on a rim, spinning).

    Parameters
    ----------
    pose : Pose
        Start pose.
    point_mm : (3,) float, mm
        A point of the line, sensor frame.
    axis : (3,) float
        Direction of the line (normalised here); angles are right-handed about it.
    angles_rad : (n,) float, rad
        Angles of the samples.

    Returns
    -------
    rotations : (n, 3, 3) float
        ``Q_k R`` with ``Q_k`` the rotation by ``angles_rad[k]`` about ``axis``.
    centroids_mm : (n, 3) float, mm
        ``p + Q_k (c - p)``: every point of the line stays where it is.

    Notes
    -----
    Rolling without slip when the line is horizontal and passes through the
    contact (a bottom edge, the tangent of a rim at its lowest point). With a
    horizontal axis ``e_z x u`` a positive angle tips the body's top towards
    ``u``. About a vertical axis the body spins in place: sliding, except at
    a single point contact on the axis.
    """
    p = _vector3("point_mm", point_mm)
    q = matrix_from_axis_angle(_unit("axis", axis), _samples("angles_rad", angles_rad))
    rots = fo.matmul(q, pose.rotation)
    cents = p + fo.matvec(q, pose.centroid_mm - p)
    return rots, cents


def roll_straight(
    pose: Pose, radius_mm: float, direction: ArrayLike, distances_mm: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Roll a sphere, or a cylinder on its side, along a straight line without slip.

    Parameters
    ----------
    pose : Pose
        Start pose; the body's reference point must lie ``radius_mm`` above the
        contact (a sphere's centre, a lying cylinder's axis).
    radius_mm : float
        Rolling radius, mm.
    direction : (3,) float
        Horizontal direction of travel (a cylinder: perpendicular to its axis).
    distances_mm : (n,) float, mm
        Distances rolled at the samples (negative rolls backwards).

    Returns
    -------
    rotations : (n, 3, 3) float
        Turned by ``s / radius_mm`` about ``e_z x d``.
    centroids_mm : (n, 3) float, mm
        Moved by ``s d``.

    Raises
    ------
    InputError
        If the direction is not horizontal or the radius not positive.
    """
    r = check_positive("radius_mm", radius_mm)
    d = _unit("direction", direction)
    if abs(d[2]) > 1e-9:
        raise InputError(f"direction must be horizontal (z = 0), got {d.tolist()}")
    s = _samples("distances_mm", distances_mm)
    q = matrix_from_axis_angle(np.cross(E_Z, d), s / r)
    rots = fo.matmul(q, pose.rotation)
    cents: NDArray[np.float64] = pose.centroid_mm + s[:, None] * d
    return rots, cents


def roll_cone(
    pose: Pose, apex_mm: ArrayLike, axis: ArrayLike, turns_rad: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Roll a cone, or a truncated cone, on its side about its (virtual) apex without slip.

    Parameters
    ----------
    pose : Pose
        Start pose, lying on a generator.
    apex_mm : (3,) float, mm
        The apex in the sensor frame (for a truncated cone the virtual apex,
        where the extended generators meet); on the plane ``z = 0``.
    axis : (3,) float
        Direction of the cone's axis from the apex into the body, sensor frame
        (normalised here). Lying on its side, the axis rises by the half-angle
        ``alpha`` above the contact generator: its z-component is ``sin(alpha) > 0``.
    turns_rad : (n,) float, rad
        Angle ``phi`` the contact generator has turned about the vertical
        through the apex at each sample (positive counter-clockwise from above).

    Returns
    -------
    rotations : (n, 3, 3) float
        ``Z(phi) S(-phi / sin(alpha)) R``, ``Z`` about ``e_z``, ``S`` about the
        start axis.
    centroids_mm : (n, 3) float, mm
        The apex stays fixed.

    Raises
    ------
    InputError
        If the axis does not rise from the apex.

    Notes
    -----
    A rim of radius ``rho`` at distance ``L`` from the apex along the contact
    generator (``rho = L sin(alpha)``) travels ``L phi`` over the plane, and
    turns ``rho |psi|`` under itself: no slip needs ``|psi| = phi / sin(alpha)``.
    """
    apex = _vector3("apex_mm", apex_mm)
    a = _unit("axis", axis)
    if a[2] <= 1e-9:
        raise InputError(f"axis must rise from the apex (z > 0), got {a.tolist()}")
    phi = _samples("turns_rad", turns_rad)
    q = fo.matmul(matrix_from_axis_angle(E_Z, phi), matrix_from_axis_angle(a, -phi / a[2]))
    rots = fo.matmul(q, pose.rotation)
    cents = apex + fo.matvec(q, pose.centroid_mm - apex)
    return rots, cents


def translate(pose: Pose, offsets_mm: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Slide a posed body without turning it (violates rolling without slip).

    Parameters
    ----------
    pose : Pose
    offsets_mm : (n, 2) float, mm
        Horizontal displacement of the body at each sample.

    Returns
    -------
    rotations : (n, 3, 3) float
        The start rotation, repeated.
    centroids_mm : (n, 3) float, mm
    """
    off = np.asarray(offsets_mm, dtype=np.float64)
    if off.ndim != 2 or off.shape[1] != 2:
        raise InputError(f"offsets_mm must have shape (n, 2), got {off.shape}")
    check_finite_array("offsets_mm", off)
    n = off.shape[0]
    rots = np.repeat(pose.rotation[None], n, axis=0)
    cents = np.repeat(pose.centroid_mm[None], n, axis=0)
    cents[:, :2] += off
    return rots, cents
