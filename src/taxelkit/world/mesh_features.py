"""What a convex mesh can touch a plane with: flat faces, edges, rims, curved patches.

Pure geometry of a closed convex triangle mesh (mm), the world-side half of
learning a new object (:mod:`taxelkit.learn` turns these features into a row
of the tacteme-object table). No sensor and no tacteme is named here.

Method (tolerances are the named constants below)
-------------------------------------------------
1. Adjacent coplanar triangles are merged into *planar regions* (trimesh
   facets). Two regions meet at a *sharp* edge when their normals differ by
   at least :data:`SHARP_DEG`; a tessellated curved surface meets its
   neighbours at smaller angles.
2. A region is a *flat face* when at least half of its boundary (by length)
   is sharp: a cube's face, a cylinder's end disc. Every other triangle is
   part of a *curved* surface (a cylinder's side strips, a sphere's facets).
3. Each curved triangle is classed by the normals of the curved triangles
   within :data:`PATCH_RADIUS_MM` of it (about a contact patch): their
   area-weighted covariance has eigenvalues ``l1 >= l2``; ``l2 / l1 <``
   :data:`SINGLY_RATIO` means the normals turn in one direction only,
   a *singly curved* (ruled) surface whose rulings run along
   ``mean normal x first eigenvector`` (a cylinder's or cone's side); else
   *doubly curved* (a sphere's, an ellipsoid's, a capsule's caps).
4. Connected singly curved triangles form a *ruled region*: its rulings are
   parallel (within :data:`PARALLEL_DEG`, a cylinder) or meet near one point,
   the least-squares common point of the rulings (a cone's apex on the body,
   within :data:`APEX_ON_BODY_MM` of it, or a truncated cone's virtual apex
   off it).
5. A flat face's edges shared with other flat faces are *polyhedral edges*;
   its sharp boundary towards a curved surface is a *rim*.
6. A flat face's *shape*: elongation ``sqrt(l_max / l_min)`` of its second
   moments of area and triangularity ``4 h^2 / (e A)`` (``h^2 = 3 l_max``;
   1 for any rectangle, 1.155 for an equilateral triangle, 0.955 for a disc).
   It is *stable* when the centroid's projection along the face normal falls
   inside the face.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

if TYPE_CHECKING:
    import trimesh

__all__ = [
    "APEX_ON_BODY_MM",
    "PARALLEL_DEG",
    "PATCH_RADIUS_MM",
    "SHARP_DEG",
    "SINGLY_RATIO",
    "FlatFace",
    "MeshFeatures",
    "RuledRegion",
    "mesh_features",
]

#: Normals differing by at least this meet at a sharp edge, deg: a tessellated
#: curve with 20 or more segments per turn stays below it.
SHARP_DEG = 20.0
#: Neighbourhood of a curved triangle for its curvature class, mm (a contact patch).
PATCH_RADIUS_MM = 3.0
#: Below this ratio of the normals' second to first spread the surface is singly curved.
SINGLY_RATIO = 0.15
#: Rulings within this angle of their mean are parallel, deg.
PARALLEL_DEG = 5.0
#: The rulings' common point lies on the body when this close to it, mm.
APEX_ON_BODY_MM = 1.0
#: Curved surfaces smaller than this are ignored (a bevel, a seam), mm^2.
MIN_CURVED_AREA_MM2 = 4.0


@dataclass(frozen=True, eq=False)
class FlatFace:
    """One flat face of the mesh.

    Attributes
    ----------
    normal : (3,) float
        Outward unit normal, body frame.
    area_mm2 : float
    elongation : float
        ``sqrt(l_max / l_min)`` of its second moments of area.
    triangularity : float
        ``4 h^2 / (e A)``.
    stable : bool
        The body can rest on it (centroid above the face).
    edge_dirs : (k, 3) float
        Unit directions of its polyhedral edges (shared with another flat face).
    edge_lengths_mm : (k,) float
    neighbours : (k,) int
        Index of the flat face across each polyhedral edge.
    rim_mm : float
        Length of its sharp boundary towards a curved surface.
    triangles_2d_mm : (m, 3, 2) float
        Its triangles in the face plane, about the face's centroid, mm.
    long_axis : (3,) float
        Body-frame direction of its largest second moment of area.
    centroid_mm : (3,) float
        Body-frame centroid of the face, mm.
    """

    normal: NDArray[np.float64]
    area_mm2: float
    elongation: float
    triangularity: float
    stable: bool
    edge_dirs: NDArray[np.float64]
    edge_lengths_mm: NDArray[np.float64]
    neighbours: NDArray[np.intp]
    rim_mm: float
    triangles_2d_mm: NDArray[np.float64]
    long_axis: NDArray[np.float64]
    centroid_mm: NDArray[np.float64]


@dataclass(frozen=True)
class RuledRegion:
    """A singly curved surface (a cylinder's or a cone's side).

    Attributes
    ----------
    area_mm2 : float
    parallel : bool
        Rulings parallel (cylinder-like).
    apex_on_body : bool
        For converging rulings: their common point lies on the body (a cone's
        apex); False for a virtual apex (a truncated cone) or parallel rulings.
    """

    area_mm2: float
    parallel: bool
    apex_on_body: bool


@dataclass(frozen=True, eq=False)
class MeshFeatures:
    """Everything :func:`mesh_features` found.

    Attributes
    ----------
    faces : tuple of FlatFace
    ruled : tuple of RuledRegion
    doubly_curved_mm2 : float
        Area of doubly curved surface (points that can roll in any direction).
    n_vertices : int
    """

    faces: tuple[FlatFace, ...]
    ruled: tuple[RuledRegion, ...]
    doubly_curved_mm2: float
    n_vertices: int

    @property
    def curved(self) -> bool:
        """Whether any curved surface was found."""
        return bool(self.ruled) or self.doubly_curved_mm2 > 0.0


def _regions(mesh: trimesh.Trimesh) -> NDArray[np.intp]:
    """Planar region label of every triangle (merged coplanar facets, else its own)."""
    label = np.full(len(mesh.faces), -1, dtype=np.intp)
    for i, group in enumerate(mesh.facets):
        label[np.asarray(group)] = i
    lone = np.flatnonzero(label < 0)
    label[lone] = len(mesh.facets) + np.arange(lone.size)
    return label


def _shape(
    tris: NDArray[np.float64], normal: NDArray[np.float64]
) -> tuple[float, float, NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Elongation, triangularity, centroid, 2-D triangles and long axis of a planar face."""
    u = np.cross(normal, [1.0, 0.0, 0.0] if abs(normal[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(normal, u)
    p = np.stack([tris @ u, tris @ v], axis=-1)  # (m, 3, 2)
    a = 0.5 * np.abs(
        (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
        - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1])
    )
    area = float(a.sum())
    centre = (a[:, None] * p.mean(axis=1)).sum(axis=0) / area
    q = p - centre
    s = q.sum(axis=1)
    second = np.einsum(
        "m,mij->ij", a / 12.0, np.einsum("mki,mkj->mij", q, q) + s[:, :, None] * s[:, None, :]
    )
    lam, vec = np.linalg.eigh(second / area)
    e = float(np.sqrt(lam[1] / max(lam[0], 1e-12)))
    tau = 4.0 * 3.0 * float(lam[1]) / (e * area)
    centroid3 = centre[0] * u + centre[1] * v + float(tris[0, 0] @ normal) * normal
    axis3 = vec[0, 1] * u + vec[1, 1] * v
    return e, tau, centroid3, q, axis3


def _inside(
    tris: NDArray[np.float64], point: NDArray[np.float64], normal: NDArray[np.float64]
) -> bool:
    """Whether ``point`` (in the face plane) lies inside one of the triangles."""
    a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
    s1 = np.einsum("ij,j->i", np.cross(b - a, point - a), normal)
    s2 = np.einsum("ij,j->i", np.cross(c - b, point - b), normal)
    s3 = np.einsum("ij,j->i", np.cross(a - c, point - c), normal)
    tol = -1e-9
    return bool(np.any((s1 >= tol) & (s2 >= tol) & (s3 >= tol)))


def _local_curvature(
    centres: NDArray[np.float64], normals: NDArray[np.float64], areas: NDArray[np.float64]
) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """Singly curved flag and ruling direction of each curved triangle."""
    from scipy.sparse import csr_matrix
    from scipy.spatial import cKDTree

    n = centres.shape[0]
    pairs = cKDTree(centres).query_pairs(PATCH_RADIUS_MM, output_type="ndarray")
    rows = np.concatenate([pairs[:, 0], pairs[:, 1], np.arange(n)])
    cols = np.concatenate([pairs[:, 1], pairs[:, 0], np.arange(n)])
    w = csr_matrix((areas[cols], (rows, cols)), shape=(n, n))
    wsum = np.asarray(w.sum(axis=1)).ravel()
    mean = (w @ normals) / wsum[:, None]
    outer = (normals[:, :, None] * normals[:, None, :]).reshape(-1, 9)
    second = (w @ outer).reshape(-1, 3, 3) / wsum[:, None, None]
    cov = second - mean[:, :, None] * mean[:, None, :]
    lam, vec = np.linalg.eigh(cov)
    singly = lam[:, 1] < SINGLY_RATIO * np.maximum(lam[:, 2], 1e-12)
    ruling = np.cross(mean, vec[:, :, 2])
    ruling /= np.maximum(np.linalg.norm(ruling, axis=1, keepdims=True), 1e-12)
    return singly, ruling


def _ruled_regions(
    mesh: trimesh.Trimesh,
    tri: NDArray[np.intp],
    ruling: NDArray[np.float64],
    centres: NDArray[np.float64],
) -> list[RuledRegion]:
    """Connected singly curved triangles ``tri`` grouped into ruled regions."""
    import trimesh as tm

    if tri.size == 0:
        return []
    keep = np.zeros(len(mesh.faces), bool)
    keep[tri] = True
    adj = mesh.face_adjacency
    adj = adj[keep[adj[:, 0]] & keep[adj[:, 1]]]
    pos = {int(t): i for i, t in enumerate(tri)}
    groups = tm.graph.connected_components(adj, nodes=tri, min_len=1)
    out = []
    areas = mesh.area_faces
    for g in groups:
        idx = np.array([pos[int(t)] for t in g])
        area = float(areas[np.asarray(g)].sum())
        if area < MIN_CURVED_AREA_MM2:
            continue
        r = ruling[idx]
        r = r * np.sign(r @ r[0])[:, None]
        mean = r.mean(axis=0)
        mean /= np.linalg.norm(mean)
        parallel = bool(np.min(np.abs(r @ mean)) >= np.cos(np.deg2rad(PARALLEL_DEG)))
        on_body = False
        if not parallel:
            proj = np.eye(3)[None] - r[:, :, None] * r[:, None, :]
            apex = np.linalg.lstsq(
                proj.sum(0), np.einsum("nij,nj->i", proj, centres[idx]), rcond=None
            )[0]
            normals = mesh.face_normals
            offsets = np.einsum("ij,ij->i", normals, mesh.triangles[:, 0])
            on_body = bool(np.max(normals @ apex - offsets) <= APEX_ON_BODY_MM)
        out.append(RuledRegion(area, parallel, on_body))
    return out


def _curved_surfaces(
    hull: trimesh.Trimesh, curved: NDArray[np.intp], normals: NDArray[np.float64]
) -> tuple[list[RuledRegion], float]:
    """Ruled regions and doubly curved area of the triangles ``curved``."""
    if curved.size == 0:
        return [], 0.0
    centres = np.asarray(hull.triangles_center, dtype=np.float64)[curved]
    areas = np.asarray(hull.area_faces, dtype=np.float64)[curved]
    singly, ruling = _local_curvature(centres, normals[curved], areas)
    ruled = _ruled_regions(hull, curved[singly], ruling[singly], centres[singly])
    doubly = float(areas[~singly].sum())
    return ruled, (doubly if doubly >= MIN_CURVED_AREA_MM2 else 0.0)


def mesh_features(mesh: trimesh.Trimesh) -> MeshFeatures:
    """The flat faces, ruled regions and doubly curved area of a convex mesh (mm).

    Parameters
    ----------
    mesh : trimesh.Trimesh
        Closed and convex, in mm (its convex hull is used).

    Returns
    -------
    MeshFeatures
    """
    hull = mesh.convex_hull
    centroid = np.asarray(hull.center_mass, dtype=np.float64)
    label = _regions(hull)
    normals = np.asarray(hull.face_normals, dtype=np.float64)
    adj = np.asarray(hull.face_adjacency)
    angle = np.asarray(hull.face_adjacency_angles)
    edges = np.asarray(hull.face_adjacency_edges)
    verts = np.asarray(hull.vertices, dtype=np.float64)
    length = np.linalg.norm(verts[edges[:, 0]] - verts[edges[:, 1]], axis=1)
    la, lb = label[adj[:, 0]], label[adj[:, 1]]
    between = la != lb
    sharp = between & (angle >= np.deg2rad(SHARP_DEG))
    n_lab = int(label.max()) + 1
    border = np.bincount(la[between], length[between], n_lab) + np.bincount(
        lb[between], length[between], n_lab
    )
    sharp_len = np.bincount(la[sharp], length[sharp], n_lab) + np.bincount(
        lb[sharp], length[sharp], n_lab
    )
    flat_label = np.flatnonzero((border > 0) & (sharp_len >= 0.5 * border))
    face_of = {int(lab): i for i, lab in enumerate(flat_label)}
    is_flat = np.isin(label, flat_label)
    tris = np.asarray(hull.triangles, dtype=np.float64)
    faces: list[FlatFace] = []
    for lab in flat_label:
        members = np.flatnonzero(label == lab)
        n = normals[members[0]]
        e, tau, c3, tri2, axis3 = _shape(tris[members], n)
        foot = centroid - ((centroid - c3) @ n) * n
        stable = _inside(tris[members], foot, n)
        dirs, lens, nbrs = [], [], []
        rim = 0.0
        for other in sorted(
            {int(x) for x in np.concatenate([lb[sharp & (la == lab)], la[sharp & (lb == lab)]])}
        ):
            sel = sharp & (((la == lab) & (lb == other)) | ((lb == lab) & (la == other)))
            if other in face_of:
                pts = verts[np.unique(edges[sel])]
                d = pts - pts.mean(axis=0)
                direction = np.linalg.svd(d, full_matrices=False)[2][0]
                span = d @ direction
                dirs.append(direction)
                lens.append(float(span.max() - span.min()))
                nbrs.append(face_of[other])
            else:
                rim += float(length[sel].sum())
        faces.append(
            FlatFace(
                n,
                float(hull.area_faces[members].sum()),
                e,
                tau,
                stable,
                np.array(dirs, dtype=np.float64).reshape(-1, 3),
                np.array(lens, dtype=np.float64),
                np.array(nbrs, dtype=np.intp),
                rim,
                tri2,
                axis3,
                c3 - centroid,
            )
        )
    ruled, doubly = _curved_surfaces(hull, np.flatnonzero(~is_flat), normals)
    return MeshFeatures(tuple(faces), tuple(ruled), doubly, len(verts))
