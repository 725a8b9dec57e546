"""Rotations of world/pose.py against closed forms and scipy.

``matrix_from_euler_xyz_deg`` now calls :class:`scipy.spatial.transform.Rotation`
and must agree to 1e-12 with the product of elementary rotations it replaced;
``matrix_from_axis_angle`` keeps Rodrigues' formula (see the module notes)
and must agree to 1e-12 with scipy's ``from_rotvec``.
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.typing import NDArray
from scipy.spatial.transform import Rotation

from taxelkit.errors import InputError
from taxelkit.world.pose import check_rotations, matrix_from_axis_angle, matrix_from_euler_xyz_deg

#: Agreement demanded between scipy's matrices and the closed forms: both are
#: a few float64 roundings from the exact value (measured: below 2e-15).
TOL = 1e-12


def rodrigues(axis: NDArray[np.float64], angle_rad: NDArray[np.float64]) -> NDArray[np.float64]:
    """``I cos t + sin t [a]x + (1 - cos t) a a^T`` for unit axes ``(N, 3)``."""
    a = axis / np.linalg.norm(axis, axis=-1, keepdims=True)
    c, s = np.cos(angle_rad)[:, None, None], np.sin(angle_rad)[:, None, None]
    cross = np.zeros((a.shape[0], 3, 3))
    cross[:, 0, 1], cross[:, 0, 2], cross[:, 1, 2] = -a[:, 2], a[:, 1], -a[:, 0]
    cross -= np.swapaxes(cross, 1, 2)
    outer = a[:, :, None] * a[:, None, :]
    out: NDArray[np.float64] = c * np.eye(3) + s * cross + (1.0 - c) * outer
    return out


def euler_xyz(angles_deg: NDArray[np.float64]) -> NDArray[np.float64]:
    """``Rz @ Ry @ Rx`` from the elementary rotations, written out."""
    t = np.deg2rad(angles_deg)
    n = t.shape[0]
    eye = np.tile(np.eye(3), (n, 1, 1))
    rx, ry, rz = eye.copy(), eye.copy(), eye.copy()
    c, s = np.cos(t), np.sin(t)
    rx[:, 1, 1], rx[:, 1, 2], rx[:, 2, 1], rx[:, 2, 2] = c[:, 0], -s[:, 0], s[:, 0], c[:, 0]
    ry[:, 0, 0], ry[:, 0, 2], ry[:, 2, 0], ry[:, 2, 2] = c[:, 1], s[:, 1], -s[:, 1], c[:, 1]
    rz[:, 0, 0], rz[:, 0, 1], rz[:, 1, 0], rz[:, 1, 1] = c[:, 2], -s[:, 2], s[:, 2], c[:, 2]
    out: NDArray[np.float64] = rz @ ry @ rx
    return out


def test_axis_angle_matches_rodrigues_on_random_poses() -> None:
    rng = np.random.default_rng(11)
    axis = rng.normal(size=(500, 3)) * rng.uniform(0.01, 100.0, (500, 1))
    angle = rng.uniform(-4 * np.pi, 4 * np.pi, 500)
    r = matrix_from_axis_angle(axis, angle)
    np.testing.assert_allclose(r, rodrigues(axis, angle), atol=TOL)
    unit = axis / np.linalg.norm(axis, axis=1, keepdims=True)
    np.testing.assert_allclose(r, Rotation.from_rotvec(unit * angle[:, None]).as_matrix(), atol=TOL)


def test_euler_matches_elementary_product_on_random_poses() -> None:
    angles = np.random.default_rng(12).uniform(-360.0, 360.0, (500, 3))
    np.testing.assert_allclose(matrix_from_euler_xyz_deg(angles), euler_xyz(angles), atol=TOL)


def test_euler_convention_is_extrinsic_xyz() -> None:
    """x first about the fixed axes: (90, 90, 0) sends +y to +x, not to +z."""
    r = matrix_from_euler_xyz_deg([90.0, 90.0, 0.0])
    np.testing.assert_allclose(r @ [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], atol=TOL)


def test_batch_shapes_and_broadcasting() -> None:
    rng = np.random.default_rng(13)
    axis = rng.normal(size=(4, 5, 3))
    angle = rng.uniform(-3.0, 3.0, (4, 5))
    r = matrix_from_axis_angle(axis, angle)
    assert r.shape == (4, 5, 3, 3)
    np.testing.assert_allclose(
        r.reshape(-1, 3, 3), rodrigues(axis.reshape(-1, 3), angle.ravel()), atol=TOL
    )
    # one axis, many angles; a scalar pose gives one (3, 3) matrix
    assert matrix_from_axis_angle([0.0, 0.0, 2.0], np.zeros(7)).shape == (7, 3, 3)
    assert matrix_from_axis_angle([1.0, 0.0, 0.0], 0.3).shape == (3, 3)
    assert matrix_from_euler_xyz_deg(rng.uniform(size=(2, 3, 3))).shape == (2, 3, 3, 3)
    assert matrix_from_euler_xyz_deg(np.zeros((0, 3))).shape == (0, 3, 3)
    check_rotations(r.reshape(-1, 3, 3))  # proper rotations


def test_zero_angle_is_the_identity_exactly() -> None:
    np.testing.assert_array_equal(matrix_from_axis_angle([0.2, -1.0, 0.5], 0.0), np.eye(3))
    np.testing.assert_array_equal(matrix_from_euler_xyz_deg([0.0, 0.0, 0.0]), np.eye(3))


@pytest.mark.parametrize(
    ("axis", "angle", "match"),
    [([0.0, 0.0, 0.0], 1.0, "non-zero"), ([1.0, 0.0], 1.0, r"\(\.\.\., 3\)")],
)
def test_bad_axes_are_refused(axis: list[float], angle: float, match: str) -> None:
    with pytest.raises(InputError, match=match):
        matrix_from_axis_angle(axis, angle)


def test_bad_euler_shape_is_refused() -> None:
    with pytest.raises(InputError, match="angles_deg"):
        matrix_from_euler_xyz_deg([1.0, 2.0])
