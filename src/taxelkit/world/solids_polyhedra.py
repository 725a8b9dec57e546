"""Convex polyhedra: the cube and the regular tetrahedron of paper 001, and the engine they share.

A convex polyhedron is the intersection of the half-spaces ``n . p <= b`` of
its faces. After rotation, a face with ``n_z < 0`` bounds the body from below
along a vertical line, ``z >= (b - n_x x - n_y y) / n_z``, and a face with
``n_z > 0`` from above; a vertical face is tilted by
:data:`~taxelkit.world.solids_grid.TILT_EPS` so that it does the same with a
very steep plane. The bottom is the maximum of the lower planes where it does
not exceed the minimum of the upper ones.
"""

from __future__ import annotations

import math
from abc import abstractmethod
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit import _fixed_order as fo
from taxelkit.errors import check_positive
from taxelkit.world.solid_methods import SolidMethods
from taxelkit.world.solids_grid import (
    TILT_EPS,
    Combine,
    PoseGroup,
    as_rotation_batch,
    evaluate_bottom,
    finish_interval,
    line_grid,
)

if TYPE_CHECKING:
    import trimesh

__all__ = [
    "DEFAULT_CUBE_EDGE_MM",
    "DEFAULT_TETRAHEDRON_EDGE_MM",
    "LOWEST_TIE_MM",
    "Cube",
    "PolytopeSolidMethods",
    "Tetrahedron",
    "planes_from_vertices",
    "polytope_bottom_mm",
    "polytope_lowest_point_mm",
    "polytope_lowest_segment_mm",
    "polytope_lowest_z_mm",
]

#: Default cube edge, mm: 12 mm leaves the whole cube and its rolling
#: footprint on the 28 mm Bonneville array (assumed; paper 001 gives no sizes).
DEFAULT_CUBE_EDGE_MM = 12.0

#: Default regular tetrahedron edge, mm (assumed, see ``DEFAULT_CUBE_EDGE_MM``).
DEFAULT_TETRAHEDRON_EDGE_MM = 16.0


def planes_from_vertices(
    vertices_mm: NDArray[np.float64], faces: NDArray[np.intp]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Outward unit normals and offsets of the faces of a convex polyhedron.

    Parameters
    ----------
    vertices_mm : (V, 3) float, mm
        Vertices, with the origin strictly inside the body.
    faces : (F, k) int
        Vertex indices of each face (at least three, any winding).

    Returns
    -------
    normals : (F, 3) float
        Outward unit normals.
    offsets_mm : (F,) float, mm
        ``b`` in ``n . p <= b``; positive.
    """
    p0 = vertices_mm[faces[:, 0]]
    n = np.cross(vertices_mm[faces[:, 1]] - p0, vertices_mm[faces[:, 2]] - p0)
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    b = np.einsum("fi,fi->f", n, p0)
    flip = np.where(b < 0.0, -1.0, 1.0)
    return n * flip[:, None], b * flip


#: Points within this height of the lowest one count as tied (a face or an
#: edge resting flat); their mean is the lowest point, mm.
LOWEST_TIE_MM = 1e-6


def polytope_lowest_point_mm(
    vertices_mm: NDArray[np.float64], rotations: ArrayLike
) -> NDArray[np.float64]:
    """Lowest point of rotated polyhedra, relative to the reference point.

    Parameters
    ----------
    vertices_mm : (V, 3) float, mm
    rotations : (P, 3, 3) float

    Returns
    -------
    (P, 3) float64, mm
        The lowest vertex; where several tie (an edge or a face resting flat)
        the mean of the tied vertices.
    """
    rot = as_rotation_batch(rotations)
    z = fo.matmul(rot[:, 2, :], vertices_mm.T)  # (P, V): heights of the rotated vertices
    tied = (z <= z.min(axis=1, keepdims=True) + LOWEST_TIE_MM).astype(np.float64)
    tied /= tied.sum(axis=1, keepdims=True)
    body = fo.matmul(tied, vertices_mm)  # mean of the tied vertices, body frame (P, 3)
    return fo.matvec(rot, body)


def polytope_lowest_segment_mm(
    vertices_mm: NDArray[np.float64], rotations: ArrayLike
) -> NDArray[np.float64]:
    """Ends of the lowest part of rotated polyhedra: a vertex or an edge.

    Returns
    -------
    (P, 2, 3) float64, mm
        An edge's two vertices when exactly two vertices are lowest; otherwise
        the mean of the lowest vertices twice (a vertex, or a face's centre: a
        face is sampled well and needs no groove), relative to the reference point.
    """
    rot = as_rotation_batch(rotations)
    z = fo.matmul(rot[:, 2, :], vertices_mm.T)  # (P, V) heights of the rotated vertices
    tied = z <= z.min(axis=1, keepdims=True) + LOWEST_TIE_MM
    count = tied.sum(axis=1)
    first = np.argmax(tied, axis=1)
    last = tied.shape[1] - 1 - np.argmax(tied[:, ::-1], axis=1)
    weights = tied / count[:, None]
    centre = fo.matmul(weights, vertices_mm)  # mean of the tied vertices, body frame
    edge = count == 2
    a = np.where(edge[:, None], vertices_mm[first], centre)
    b = np.where(edge[:, None], vertices_mm[last], centre)
    out: NDArray[np.float64] = np.stack([fo.matvec(rot, a), fo.matvec(rot, b)], axis=1)
    return out


def polytope_lowest_z_mm(
    vertices_mm: NDArray[np.float64], rotations: ArrayLike
) -> NDArray[np.float64]:
    """Lowest z of rotated polyhedra: the lowest rotated vertex.

    Parameters
    ----------
    vertices_mm : (V, 3) float, mm
        Vertices relative to the reference point.
    rotations : (P, 3, 3) float

    Returns
    -------
    (P,) float64, mm
    """
    rot = as_rotation_batch(rotations)
    z: NDArray[np.float64] = fo.matmul(rot[:, 2, :], vertices_mm.T).min(axis=1)
    return z


def _slot_faces(is_upper: NDArray[np.bool_]) -> tuple[NDArray[np.intp], int, int]:
    """Per pose, face indices for ``L`` lower slots then ``U`` upper slots, flattened.

    Returns indices into a ``(P * F)`` table: lower faces of each pose in their
    original order, then its upper faces. A pose with fewer lower (upper)
    faces than the batch's most repeats its last one, which leaves the
    maximum (minimum) unchanged.
    """
    n_poses, n_faces = is_upper.shape
    up = is_upper.astype(np.intp)
    n_up = up.sum(axis=1)
    n_lo = n_faces - n_up
    assert n_lo.min() >= 1 and n_up.min() >= 1, "a bounded body has faces below and above"
    # Position of each face once lower faces are moved first (a stable partition).
    rank = np.where(is_upper, n_lo[:, None] + np.cumsum(up, axis=1), np.cumsum(1 - up, axis=1))
    order = np.empty_like(rank)
    rows = np.arange(n_poses)[:, None]
    order[rows, rank - 1] = np.arange(n_faces)[None, :]
    n_lo_max, n_up_max = int(n_lo.max()), int(n_up.max())
    lo_pos = np.minimum(np.arange(n_lo_max)[None, :], n_lo[:, None] - 1)
    up_pos = n_lo[:, None] + np.minimum(np.arange(n_up_max)[None, :], n_up[:, None] - 1)
    pos = np.concatenate([lo_pos, up_pos], axis=1)
    return order[rows, pos] + rows * n_faces, n_lo_max, n_up_max


def _polytope_combine(n_lower: int, n_upper: int) -> Combine:
    def combine(
        slabs: NDArray[Any], work: Any, out: NDArray[Any], pose_values: NDArray[Any]
    ) -> None:
        lo = slabs[0]
        if n_lower > 1:
            lo = np.maximum(slabs[0], slabs[1], out=work[0])
            for k in range(2, n_lower):
                np.maximum(lo, slabs[k], out=lo)
        hi = slabs[n_lower]
        if n_upper > 1:
            hi = np.minimum(slabs[n_lower], slabs[n_lower + 1], out=work[1])
            for k in range(n_lower + 2, n_lower + n_upper):
                np.minimum(hi, slabs[k], out=hi)
        finish_interval(lo, hi, work[1], out)

    return combine


def polytope_bottom_mm(
    normals: NDArray[np.float64],
    offsets_mm: NDArray[np.float64],
    rotations: ArrayLike,
    x_mm: ArrayLike,
    y_mm: ArrayLike,
) -> NDArray[Any]:
    """Bottom of rotated convex polyhedra on a batch of vertical-line grids.

    Parameters
    ----------
    normals : (F, 3) float
        Outward unit face normals in the body frame.
    offsets_mm : (F,) float, mm
        Face offsets, ``n . p <= b`` inside (reference point at the origin).
    rotations : (P, 3, 3) float
    x_mm : (P, W) float, mm
    y_mm : (P, H) float, mm

    Returns
    -------
    (P, H, W) float, mm
        In the dtype of ``x_mm`` (float32 or float64); ``+inf`` off the body.
        See :meth:`taxelkit.world.base.Solid.bottom_mm`.
    """
    rot = as_rotation_batch(rotations)
    grid = line_grid(x_mm, y_mm, rot.shape[0])
    n_poses = rot.shape[0]
    if n_poses == 0:
        return evaluate_bottom(grid, [])
    # Rotated normals: n[p, i, f] = sum_j R[p, i, j] normals[f, j].
    n = fo.matmul(rot.reshape(-1, 3), normals.T).reshape(n_poses, 3, -1)
    nx, ny, nz = n[:, 0], n[:, 1], n[:, 2]
    sign = np.sign(nz)
    # Exactly vertical faces: split opposite faces between "lower" and "upper".
    sign = np.where(sign == 0.0, np.sign(nx), sign)
    sign = np.where(sign == 0.0, np.sign(ny), sign)
    inv_nz = 1.0 / (sign * np.maximum(np.abs(nz), TILT_EPS))
    funcs = np.zeros((*nz.shape, 4))
    funcs[..., 0] = offsets_mm[None, :] * inv_nz
    funcs[..., 1] = -nx * inv_nz
    funcs[..., 2] = -ny * inv_nz
    slots, n_lower, n_upper = _slot_faces(sign > 0.0)
    funcs = funcs.reshape(-1, 4)[slots]
    combine = _polytope_combine(n_lower, n_upper)
    return evaluate_bottom(grid, [PoseGroup(None, funcs, combine, n_work=2)])


class PolytopeSolidMethods(SolidMethods):
    """The :class:`~taxelkit.world.base.Solid` methods of a convex polyhedron.

    A subclass provides ``vertices_mm`` ``(V, 3)`` and ``planes`` (outward unit
    normals ``(F, 3)`` and offsets ``(F,)``), relative to its reference point.
    """

    if TYPE_CHECKING:  # declared for the type checker; a dataclass field may provide them

        @property
        @abstractmethod
        def vertices_mm(self) -> NDArray[np.float64]: ...

        @property
        @abstractmethod
        def planes(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...

    def _lowest_z(self, rotations: ArrayLike) -> NDArray[np.float64]:
        return polytope_lowest_z_mm(self.vertices_mm, rotations)

    def _lowest_point(self, rotations: ArrayLike) -> NDArray[np.float64]:
        return polytope_lowest_point_mm(self.vertices_mm, rotations)

    def _lowest_segment(self, rotations: ArrayLike) -> NDArray[np.float64]:
        return polytope_lowest_segment_mm(self.vertices_mm, rotations)

    def _bottom(self, rotations: ArrayLike, x_mm: ArrayLike, y_mm: ArrayLike) -> NDArray[Any]:
        return polytope_bottom_mm(*self.planes, rotations, x_mm, y_mm)

    def to_trimesh(self) -> trimesh.Trimesh:
        """The body as a triangle mesh (the convex hull of its vertices), mm, for plots and
        baselines; the reference point is the origin."""
        import trimesh

        hull: trimesh.Trimesh = trimesh.Trimesh(vertices=self.vertices_mm).convex_hull
        return hull


@dataclass(frozen=True)
class Cube(PolytopeSolidMethods):
    """A cube with faces aligned to the body axes; reference point at its centre.

    Parameters
    ----------
    edge_mm : float
        Edge length, mm.

    Notes
    -----
    Body frame: faces ``x, y, z = +-edge_mm / 2``.
    """

    edge_mm: float = DEFAULT_CUBE_EDGE_MM
    name = "cube"

    def __post_init__(self) -> None:
        check_positive("edge_mm", self.edge_mm)

    @property
    def vertices_mm(self) -> NDArray[np.float64]:
        """(8, 3) float, mm: corners in the body frame."""
        s = np.array([-0.5, 0.5]) * self.edge_mm
        return np.stack(np.meshgrid(s, s, s, indexing="ij"), axis=-1).reshape(8, 3)

    @property
    def planes(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Outward unit normals ``(6, 3)`` and offsets ``(6,)`` mm of the faces."""
        n = np.concatenate([np.eye(3), -np.eye(3)])
        return n, np.full(6, 0.5 * self.edge_mm)


@dataclass(frozen=True)
class Tetrahedron(PolytopeSolidMethods):
    """A regular tetrahedron resting on a face; reference point at its centroid.

    Parameters
    ----------
    edge_mm : float
        Edge length, mm.

    Notes
    -----
    Body frame: the base face lies in the plane ``z = -h / 4`` (``h = edge_mm
    * sqrt(2/3)``, the height) with one base vertex on the +x axis side, and
    the apex sits on the +z axis at ``z = 3 h / 4``. Every face is ``h / 4``
    from the centroid.
    """

    edge_mm: float = DEFAULT_TETRAHEDRON_EDGE_MM
    name = "tetrahedron"

    def __post_init__(self) -> None:
        check_positive("edge_mm", self.edge_mm)

    @property
    def height_mm(self) -> float:
        """Height from a face to the opposite vertex, mm."""
        return self.edge_mm * math.sqrt(2.0 / 3.0)

    @property
    def vertices_mm(self) -> NDArray[np.float64]:
        """(4, 3) float, mm: three base vertices then the apex."""
        h = self.height_mm
        r = self.edge_mm / math.sqrt(3.0)
        ang = np.deg2rad([0.0, 120.0, 240.0])
        base = np.stack([r * np.cos(ang), r * np.sin(ang), np.full(3, -h / 4.0)], axis=1)
        return np.concatenate([base, [[0.0, 0.0, 0.75 * h]]])

    @property
    def planes(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Outward unit normals ``(4, 3)`` and offsets ``(4,)`` mm of the faces."""
        faces = np.array([[0, 1, 2], [0, 1, 3], [1, 2, 3], [2, 0, 3]])
        return planes_from_vertices(self.vertices_mm, faces)
