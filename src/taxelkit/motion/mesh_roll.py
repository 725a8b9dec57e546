"""Rolling a general convex body over the plane, one small turn at a time.

:func:`roll_path` turns the body by :data:`ROLL_STEP_DEG` about the
horizontal axis ``e_z x d`` through its lowest point farthest along the
direction of travel ``d``, sets it back on the plane, and repeats: rolling
without slip and without spin for a smooth body, tipping over the front edge
for a face. The scripts of :mod:`taxelkit.motion.mesh_scenarios` roll learnt
meshes with it. Each step's pose is built on the last, so its products are
summed in a fixed order (:mod:`taxelkit._fixed_order`): the same roll on
every CPU, whatever BLAS kernel NumPy's ``@`` would pick.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from taxelkit._fixed_order import dot, matmul, matvec, rotate_points, scalar_dot
from taxelkit.errors import InputError
from taxelkit.motion._script import unit_h
from taxelkit.motion.rolling import E_Z, Pose
from taxelkit.world.mesh_solid import MeshSolid
from taxelkit.world.pose import matrix_from_axis_angle

__all__ = ["ROLL_STEP_DEG", "roll_path"]

#: Turn of one step of the general roller, deg (0.5 deg moves the contact of
#: a 6 mm ball by 0.05 mm).
ROLL_STEP_DEG = 0.5


def roll_path(
    solid: MeshSolid,
    pose: Pose,
    direction: NDArray[np.float64],
    *,
    distance_mm: float | None = None,
    angle_rad: float | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Roll a convex body over the plane towards ``direction`` (see the module notes).

    Parameters
    ----------
    solid : MeshSolid
    pose : Pose
        Resting start pose.
    direction : (3,) float
        Horizontal direction of travel.
    distance_mm, angle_rad : float
        Stop once the contact has advanced this far along ``direction``, or
        the body has turned this much (exactly one of the two).

    Returns
    -------
    rotations : (n, 3, 3) float
    centroids_mm : (n, 3) float
        One pose per step of :data:`ROLL_STEP_DEG`, the start excluded.
    """
    if (distance_mm is None) == (angle_rad is None):
        raise InputError("give exactly one of distance_mm and angle_rad")
    d = unit_h(np.asarray(direction, dtype=np.float64))
    step = math.radians(ROLL_STEP_DEG)
    q = matrix_from_axis_angle(np.cross(E_Z, d), step)
    rot, cen = pose.rotation.copy(), pose.centroid_mm.copy()
    verts = solid.vertices_mm
    rots, cents = [], []
    travelled, turned = 0.0, 0.0
    world = cen + rotate_points(verts, rot)
    lowest = world[:, 2] <= world[:, 2].min() + 1e-6
    pivot = world[np.argmax(np.where(lowest, dot(world, d), -np.inf))]
    while (travelled < distance_mm) if distance_mm is not None else (turned < abs(angle_rad or 0)):
        rot = matmul(q, rot)
        cen = pivot + matvec(q, cen - pivot)
        world = cen + rotate_points(verts, rot)
        low = world[:, 2].min()
        cen[2] -= low  # rest on the plane again (a finite step dips a little)
        world[:, 2] -= low
        front = np.where(world[:, 2] <= 1e-6, dot(world, d), -np.inf)
        new = world[np.argmax(front)]
        travelled += scalar_dot(new - pivot, d)  # the contact's advance along d
        turned += step
        pivot = new
        rots.append(rot.copy())
        cents.append(cen.copy())
        if len(rots) > 20000:
            raise InputError("roll_path: the body does not roll (20000 steps)")
    return np.array(rots), np.array(cents)
