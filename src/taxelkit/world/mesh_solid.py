"""Convex solids from triangle meshes (STL, OBJ, PLY, ...), as half-spaces.

A closed convex mesh is turned into the intersection of its face planes
(coplanar triangles merged into one plane) and evaluated with the same
analytic engine as the cube and the tetrahedron
(:func:`~taxelkit.world.solids_polyhedra.polytope_bottom_mm`). The reference
point is the volume centroid. Files are assumed to be in mm unless ``scale``
says otherwise.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import (
    CorruptRecordingError,
    FileTooLargeError,
    InputError,
    RecordingAccessError,
    UnsupportedFormatError,
    check_finite_array,
    check_positive,
)
from taxelkit.io.limits import open_budget
from taxelkit.world.solids_polyhedra import PolytopeSolidMethods

if TYPE_CHECKING:
    import trimesh

__all__ = [
    "COPLANAR_DECIMALS",
    "MESH_SUFFIXES",
    "MeshSolid",
    "load_mesh_solid",
]

#: File suffixes read through trimesh.
MESH_SUFFIXES: tuple[str, ...] = ("stl", "obj", "ply", "off", "glb", "gltf")

#: Face normals equal after rounding to this many decimals are one plane (a
#: convex body has one supporting plane per outward direction); the merged
#: plane keeps the largest offset so that no vertex is cut off.
COPLANAR_DECIMALS = 7

#: Tolerance of the unit-length check of face normals.
_UNIT_TOL = 1e-6


@dataclass(frozen=True, eq=False)
class MeshSolid(PolytopeSolidMethods):
    """A convex polyhedron given by its vertices and face planes.

    Build it with :meth:`from_trimesh` or :func:`load_mesh_solid`.

    Parameters
    ----------
    vertices_mm : (V, 3) float, mm
        Vertices relative to the reference point (the volume centroid).
    normals : (F, 3) float
        Outward unit normals of the (merged) faces.
    offsets_mm : (F,) float, mm
        Face offsets: the body is ``normals @ p <= offsets_mm``; all > 0
        (the reference point is inside).
    label : str
        Free text, for example the file name.

    Raises
    ------
    InputError
        If shapes or values are inconsistent.
    """

    vertices_mm: NDArray[np.float64]
    normals: NDArray[np.float64]
    offsets_mm: NDArray[np.float64]
    label: str = "mesh"
    name = "mesh"

    def __post_init__(self) -> None:
        v = np.asarray(self.vertices_mm, dtype=np.float64)
        n = np.asarray(self.normals, dtype=np.float64)
        b = np.asarray(self.offsets_mm, dtype=np.float64)
        if v.ndim != 2 or v.shape[1] != 3 or v.shape[0] < 4:
            raise InputError(f"vertices_mm must have shape (V >= 4, 3), got {v.shape}")
        if n.ndim != 2 or n.shape[1] != 3 or n.shape[0] < 4:
            raise InputError(f"normals must have shape (F >= 4, 3), got {n.shape}")
        if b.shape != (n.shape[0],):
            raise InputError(f"offsets_mm must have shape ({n.shape[0]},), got {b.shape}")
        for label, arr in (("vertices_mm", v), ("normals", n), ("offsets_mm", b)):
            check_finite_array(label, arr)
        if np.abs(np.linalg.norm(n, axis=1) - 1.0).max() > _UNIT_TOL:
            raise InputError("normals must have unit length")
        if b.min() <= 0.0:
            raise InputError(
                f"offsets_mm must be > 0 (reference point inside the body), got min {b.min()!r}"
            )
        object.__setattr__(self, "vertices_mm", v)
        object.__setattr__(self, "normals", n)
        object.__setattr__(self, "offsets_mm", b)

    @classmethod
    def from_trimesh(
        cls,
        mesh: trimesh.Trimesh,
        *,
        convex_hull: bool = False,
        scale: float = 1.0,
        label: str = "mesh",
    ) -> MeshSolid:
        """Convert a closed convex triangle mesh.

        Parameters
        ----------
        mesh : trimesh.Trimesh
            Coordinates in file units.
        convex_hull : bool
            Use the mesh's convex hull instead of rejecting a mesh that is not
            closed or not convex.
        scale : float
            mm per file unit.
        label : str
            Stored as :attr:`label`.

        Raises
        ------
        InputError
            If the mesh is empty, not watertight or not convex (without
            ``convex_hull``), or flat.
        """
        factor = check_positive("scale", scale)
        if len(mesh.faces) == 0:
            raise InputError(f"mesh {label!r} holds no triangles")
        if not convex_hull:
            if not mesh.is_watertight:
                raise InputError(
                    f"mesh {label!r} is not watertight; pass convex_hull=True to use its hull"
                )
            if not mesh.is_convex:
                raise InputError(
                    f"mesh {label!r} is not convex; pass convex_hull=True to use its hull"
                )
        try:
            hull = mesh.convex_hull
            volume = float(hull.volume)
        except Exception as exc:  # qhull rejects flat or degenerate point sets
            raise InputError(f"mesh {label!r} encloses no volume ({type(exc).__name__})") from None
        if not volume > 0.0:
            raise InputError(f"mesh {label!r} encloses no volume")
        centroid = np.asarray(hull.center_mass, dtype=np.float64)
        vertices = (np.asarray(hull.vertices, dtype=np.float64) - centroid) * factor
        normals = np.asarray(hull.face_normals, dtype=np.float64)
        first = np.asarray(hull.triangles, dtype=np.float64)[:, 0] - centroid
        offsets = np.einsum("fi,fi->f", normals, first) * factor
        key = np.round(normals, COPLANAR_DECIMALS)
        _, first_index, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
        merged = np.full(first_index.shape[0], -np.inf)
        np.maximum.at(merged, inverse.ravel(), offsets)
        return cls(vertices, normals[first_index], merged, label=label)

    @property
    def planes(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Outward unit normals ``(F, 3)`` and offsets ``(F,)`` mm of the merged faces."""
        return self.normals, self.offsets_mm


def load_mesh_solid(
    path: str | PathLike[str], *, convex_hull: bool = False, scale: float = 1.0
) -> MeshSolid:
    """Read a convex solid from a mesh file (STL, OBJ, PLY, OFF, glTF).

    Parameters
    ----------
    path : str or path-like
    convex_hull : bool
        Use the convex hull of a mesh that is not closed or not convex
        instead of rejecting it.
    scale : float
        mm per file unit.

    Returns
    -------
    MeshSolid
        Labelled with the file name.

    Raises
    ------
    InputError
        If the mesh is not a closed convex body (and ``convex_hull`` is
        false). The message names the file.
    RecordingNotFoundError, RecordingAccessError
        If the file does not exist or is not a regular file.
    FileTooLargeError
        If the file is over the read limit (:mod:`taxelkit.io.limits`).
    UnsupportedFormatError
        If the suffix is not one of :data:`MESH_SUFFIXES`.
    CorruptRecordingError
        If the file cannot be parsed or holds no triangles.
    """
    p = Path(path)
    suffix = p.suffix.lower().lstrip(".")
    if suffix not in MESH_SUFFIXES:
        raise UnsupportedFormatError(
            f"cannot read {p.name}: mesh suffix must be one of {', '.join(MESH_SUFFIXES)}"
        )
    open_budget(p, what="mesh")
    try:
        data = p.read_bytes()
    except OSError as exc:
        raise RecordingAccessError(f"{p}: cannot read ({exc.strerror or exc})") from None
    import trimesh

    try:
        # From bytes, with no resolver: material, texture and buffer files that
        # the mesh names (OBJ mtllib, glTF uri) are never opened.
        mesh = trimesh.load(io.BytesIO(data), file_type=suffix, force="mesh", resolver=None)
    except MemoryError:
        raise FileTooLargeError(f"{p}: not enough memory to read the mesh") from None
    except Exception as exc:  # trimesh raises many kinds on damaged files
        first_line = " ".join((str(exc).splitlines() or [""])[0].split())[:120]
        raise CorruptRecordingError(
            f"{p}: cannot read mesh file: {type(exc).__name__}: {first_line}"
        ) from None
    if not isinstance(mesh, trimesh.Trimesh) or len(mesh.faces) == 0:
        raise CorruptRecordingError(f"{p}: mesh file holds no triangles")
    try:
        return MeshSolid.from_trimesh(mesh, convex_hull=convex_hull, scale=scale, label=p.name)
    except InputError as exc:
        raise InputError(f"{p}: {exc}") from None
