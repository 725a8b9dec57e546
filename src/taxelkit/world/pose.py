"""Rotations for placing bodies: small, vectorised, named ``target_from_source``.

Euler angles go through :class:`scipy.spatial.transform.Rotation`; this
module fixes taxelkit's convention (extrinsic x-y-z, degrees), validates the
input and keeps any batch shape ``(...)``.

Axis-angle stays written out (Rodrigues' formula), on purpose: scipy's
``Rotation.from_rotvec`` passes through a quaternion and differs from it by
up to about 3e-15, and the rolling-object experiments are that sensitive. A
few of their 600 randomised trials sit on a decision threshold, so with
scipy's matrices ``reproduce smart-sensor`` reports 0.988 instead of the
published 0.985 (two more decided trials), and ``tacteme-table`` and
``contact-classes`` change too. ``tests/world/test_pose.py`` checks that
the two agree to 1e-12 on random poses.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial.transform import Rotation

from taxelkit.errors import InputError

__all__ = [
    "check_rotations",
    "matrix_from_axis_angle",
    "matrix_from_euler_xyz_deg",
]


def matrix_from_axis_angle(axis: ArrayLike, angle_rad: ArrayLike) -> NDArray[np.float64]:
    """Rotation matrices from axes and angles (Rodrigues' formula).

    Parameters
    ----------
    axis : (..., 3) float
        Rotation axes; normalised here, must be non-zero.
    angle_rad : (...) float, rad
        Right-handed rotation angles.

    Returns
    -------
    (..., 3, 3) float

    Raises
    ------
    InputError
        If an axis has zero length.
    """
    a = np.asarray(axis, dtype=np.float64)
    th = np.asarray(angle_rad, dtype=np.float64)
    if a.shape[-1:] != (3,):
        raise InputError(f"axis must have shape (..., 3), got {a.shape}")
    n = np.linalg.norm(a, axis=-1, keepdims=True)
    if np.any(n == 0):
        raise InputError("axis must be non-zero")
    a = a / n
    a, th = np.broadcast_arrays(a, th[..., None])
    th = th[..., 0]
    x, y, z = a[..., 0], a[..., 1], a[..., 2]
    c, s = np.cos(th), np.sin(th)
    t = 1.0 - c
    r = np.empty((*th.shape, 3, 3))
    r[..., 0, 0] = c + x * x * t
    r[..., 0, 1] = x * y * t - z * s
    r[..., 0, 2] = x * z * t + y * s
    r[..., 1, 0] = y * x * t + z * s
    r[..., 1, 1] = c + y * y * t
    r[..., 1, 2] = y * z * t - x * s
    r[..., 2, 0] = z * x * t - y * s
    r[..., 2, 1] = z * y * t + x * s
    r[..., 2, 2] = c + z * z * t
    return r


def matrix_from_euler_xyz_deg(angles_deg: ArrayLike) -> NDArray[np.float64]:
    """Rotation matrices from extrinsic x-y-z Euler angles.

    Parameters
    ----------
    angles_deg : (..., 3) float, deg
        Rotations about the fixed x, then y, then z axes.

    Returns
    -------
    (..., 3, 3) float
        ``Rz @ Ry @ Rx``: scipy's ``Rotation.from_euler("xyz", angles_deg,
        degrees=True)`` (lower-case axes: extrinsic).

    Raises
    ------
    InputError
        If ``angles_deg`` does not end in 3.

    Examples
    --------
    >>> r = matrix_from_euler_xyz_deg([90.0, 90.0, 0.0])  # x first: +y -> +z -> +x
    >>> np.round(r @ [0.0, 1.0, 0.0], 12).tolist()
    [1.0, 0.0, 0.0]
    """
    ang = np.asarray(angles_deg, dtype=np.float64)
    if ang.shape[-1:] != (3,):
        raise InputError(f"angles_deg must have shape (..., 3), got {ang.shape}")
    rotation = Rotation.from_euler("xyz", ang.reshape(-1, 3), degrees=True)
    out: NDArray[np.float64] = rotation.as_matrix().reshape(*ang.shape[:-1], 3, 3)
    return out


def check_rotations(rotations: ArrayLike, *, atol: float = 1e-6) -> NDArray[np.float64]:
    """Return ``rotations`` as a ``(P, 3, 3)`` float array of proper rotations.

    A single ``(3, 3)`` matrix is promoted to ``(1, 3, 3)``.

    Raises
    ------
    InputError
        If the shape is wrong, values are not finite, or a matrix is not
        orthonormal with determinant +1 (within ``atol``).
    """
    r = np.asarray(rotations, dtype=np.float64)
    if r.shape == (3, 3):
        r = r[None]
    if r.ndim != 3 or r.shape[1:] != (3, 3):
        raise InputError(f"rotations must have shape (P, 3, 3), got {r.shape}")
    if not np.all(np.isfinite(r)):
        raise InputError("rotations must be finite")
    gram = np.einsum("pij,pkj->pik", r, r)  # R R^T, one pass for the whole batch
    eye_err: Any = np.abs(gram - np.eye(3)).max(initial=0.0)
    det = np.einsum("pi,pi->p", r[:, 0], np.cross(r[:, 1], r[:, 2]))  # triple product
    if eye_err > atol or np.any(det < 0):
        raise InputError("rotations must be proper rotation matrices (R R^T = I, det R = +1)")
    return r
