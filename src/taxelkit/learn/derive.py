"""A row of the tacteme-object table from a mesh's geometry and the sensor.

The rules read :class:`~taxelkit.world.mesh_features.MeshFeatures` and what
each flat face reads as on the sensor (:mod:`taxelkit.learn.footprints`:
area, line, shape classes), and give every
tacteme the object can produce rolling (or tipping) without slip, with the
reason. They reproduce the six hand-written rows of Table 1 and the face
rows from meshes of the six solids (tested):

=================================  ==============================================
PC                                 always: a vertex, a rim point or a curved patch
LC                                 a polyhedral edge, a ruled (singly curved)
                                   side, or a face that reads as a line
AC                                 a face that reads as an area
PC moves                           a doubly curved patch rolls; a rim rolls
PC takes an orthogonal turn        a doubly curved patch rolls in any direction
LCM                                a ruled side rolls; a line face tips onto an edge
LCMP                               ... a ruled side with parallel rulings (a
                                   cylinder); two line faces with parallel axes
                                   across an edge (a long prism rolled over its sides)
LCMT                               converging rulings (a cone); two line faces
                                   with converging axes (a tall pyramid)
LCMT about one end / in an arc     ... converging on the body (an apex) / off it
LC -> AC, AC -> LC                 an area face bounded by a polyhedral edge
LC -> AC -> LC (parallel or 90)    two polyhedral edges of an area face at 0 or 90 deg
LC -> AC -> LC (60 or 120)         two polyhedral edges of an area face at 60 deg
AC -> LC -> AC onto another face   two area faces share a polyhedral edge
AC compact / elongated / ...       as the area faces read
AC moves, AC rotates, LC slides,   never: sliding
LC spins
=================================  ==============================================

A row that holds too much only makes the object harder to identify; one
that holds too little makes the recogniser rule the object out when it is
there, so the rules err on the side of more (angles within
:data:`ANGLE_MARGIN_DEG` of a limit count on both sides).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from taxelkit.learn.footprints import FaceReading, read_face
from taxelkit.sensors.presets import BONNEVILLE_16X16, Sensor
from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.object_table import ObjectRow
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.tactemes import TactemeConfig
from taxelkit.world.mesh_features import FlatFace, MeshFeatures
from taxelkit.world.mesh_solid import MeshSolid

__all__ = ["ANGLE_MARGIN_DEG", "MIN_EDGE_MM", "SIZE_FACTORS", "derive_row"]

#: Edge angles within this of a limit of ``edge_angle_tol_deg`` count on both sides, deg.
ANGLE_MARGIN_DEG = 2.0
#: A face is read at these multiples of its size: a learnt object is that
#: object at that size (learn it again with another ``--scale`` for another).
SIZE_FACTORS = (1.0,)
#: Polyhedral edges shorter than this never read as lines (Level 2's shortest
#: line, 6 mm, less its 15 % hysteresis), mm.
MIN_EDGE_MM = 5.1
#: Long axes of two line faces within this angle are parallel, deg.
PARALLEL_AXES_DEG = 5.0


def _edge_angles(face: FlatFace) -> list[float]:
    """Axis differences (0-90 deg) between every two of a face's edges that read as lines."""
    d = face.edge_dirs[face.edge_lengths_mm >= MIN_EDGE_MM]
    out = []
    for i in range(len(d)):
        for j in range(i + 1, len(d)):
            c = abs(float(d[i] @ d[j]))
            out.append(math.degrees(math.acos(min(1.0, c))))
    return out


def read_faces(
    solid: MeshSolid, features: MeshFeatures, *, config: TactemeConfig, sensor: Sensor
) -> list[FaceReading]:
    """Every face's reading, united over :data:`SIZE_FACTORS`."""
    out = []
    for face in features.faces:
        classes: set[ContactClass] = set()
        shapes: set[Tacteme] = set()
        for k, factor in enumerate(SIZE_FACTORS):
            scaled = MeshSolid(solid.vertices_mm * factor, solid.normals, solid.offsets_mm * factor)
            big = replace(
                face,
                triangles_2d_mm=face.triangles_2d_mm * factor,
                centroid_mm=face.centroid_mm * factor,
            )
            r = read_face(scaled, big, config=config, sensor=sensor, rng=k)
            classes |= r.classes
            shapes |= r.shapes
        out.append(FaceReading(frozenset(classes), frozenset(shapes)))
    return out


def _line_faces(
    features: MeshFeatures, readings: list[FaceReading], out: dict[Tacteme, str]
) -> None:
    """Tactemes of faces that read as lines, and of tipping between two of them."""
    lines = [i for i, r in enumerate(readings) if r.line]
    if not lines:
        return
    out.setdefault(Tacteme.LC, f"{len(lines)} face(s) read as a line")
    out.setdefault(Tacteme.LCM, "a face read as a line tips onto its edge: the line moves")
    for i in lines:
        fi = features.faces[i]
        for j in (int(n) for n in fi.neighbours if readings[int(n)].line and int(n) > i):
            fj = features.faces[j]
            c = abs(float(fi.long_axis @ fj.long_axis))
            if c >= np.cos(np.radians(PARALLEL_AXES_DEG)):
                out.setdefault(Tacteme.LCMP, "tipped over from a line face onto a parallel one")
                continue
            out.setdefault(Tacteme.LCMT, "tipped over from a line face onto a turned one")
            # where the two axes (through the faces' centroids) come closest: the pivot
            a, b = fi.long_axis, fj.long_axis
            m = np.array([[a @ a, -(a @ b)], [a @ b, -(b @ b)]])
            rhs = np.array(
                [(fj.centroid_mm - fi.centroid_mm) @ a, (fj.centroid_mm - fi.centroid_mm) @ b]
            )
            t = np.linalg.solve(m, rhs)
            pivot = 0.5 * (fi.centroid_mm + t[0] * a + fj.centroid_mm + t[1] * b)
            reach = max(float(np.abs(fi.triangles_2d_mm).max()), 1e-9)
            dist = float(np.linalg.norm(pivot - fi.centroid_mm))
            tac = Tacteme.LCMT_ABOUT_END if dist <= 1.5 * reach else Tacteme.LCMT_ARC
            out.setdefault(tac, "the line faces turn about a point at or beyond their ends")


def _polyhedral(
    features: MeshFeatures, readings: list[FaceReading], config: TactemeConfig
) -> dict[Tacteme, str]:
    """Tactemes of flat faces and polyhedral edges."""
    out: dict[Tacteme, str] = {}
    tol = config.edge_angle_tol_deg + ANGLE_MARGIN_DEG
    areas = [f for f, r in zip(features.faces, readings, strict=True) if r.area]
    n_edges = sum(int(np.sum(f.edge_lengths_mm >= MIN_EDGE_MM)) for f in features.faces) // 2
    if areas:
        out[Tacteme.AC] = f"{len(areas)} face(s) read as an area"
    if n_edges:
        out[Tacteme.LC] = f"{n_edges} polyhedral edge(s)"
    if any(np.any(f.edge_lengths_mm >= MIN_EDGE_MM) for f in areas):
        out[Tacteme.LC_TO_AC] = "tipping from a polyhedral edge onto a face"
        out[Tacteme.AC_TO_LC] = "tipping from a face onto a polyhedral edge"
    square = [f for f in areas if any(a <= tol or a >= 90.0 - tol for a in _edge_angles(f))]
    tri = [f for f in areas if any(abs(a - 60.0) <= tol for a in _edge_angles(f))]
    if square:
        out[Tacteme.LC_AC_LC_SQUARE] = f"{len(square)} face(s) with two edges parallel or at 90 deg"
    if tri:
        out[Tacteme.LC_AC_LC_TRIANGLE] = f"{len(tri)} face(s) with two edges at 60 or 120 deg"
    for i, (face, r) in enumerate(zip(features.faces, readings, strict=True)):
        if r.area and any(readings[int(n)].area for n in face.neighbours):
            out.setdefault(Tacteme.AC_OVER, f"face {i} and a neighbour both read as areas")
        for tac in sorted(r.shapes, key=list(Tacteme).index):
            out.setdefault(
                tac,
                f"face {i} (elongation {face.elongation:.2f}, triangularity "
                f"{face.triangularity:.3f}, {face.area_mm2:.0f} mm^2) read so",
            )
    _line_faces(features, readings, out)
    return out


def _curved(features: MeshFeatures) -> dict[Tacteme, str]:
    """Tactemes of curved surfaces and rims."""
    out: dict[Tacteme, str] = {}
    rim = sum(f.rim_mm for f in features.faces)
    if features.doubly_curved_mm2 > 0.0:
        area = f"{features.doubly_curved_mm2:.0f} mm^2 of doubly curved surface"
        out[Tacteme.PC_MOVES] = area + " rolls on a point"
        out[Tacteme.PC_ORTHOGONAL_TURN] = area + " rolls in any direction"
    elif rim > 0.0:
        out[Tacteme.PC_MOVES] = f"a rim ({rim:.0f} mm) rolls on a point"
    for r in features.ruled:
        out.setdefault(Tacteme.LC, "a ruled side lies on a line")
        out.setdefault(Tacteme.LCM, "a ruled side rolls across its line")
        if r.parallel:
            out.setdefault(Tacteme.LCMP, "a ruled side with parallel rulings rolls straight")
        else:
            out.setdefault(Tacteme.LCMT, "a ruled side with converging rulings rolls in a circle")
            if r.apex_on_body:
                out.setdefault(Tacteme.LCMT_ABOUT_END, "its rulings meet at an apex on the body")
            else:
                out.setdefault(Tacteme.LCMT_ARC, "its rulings meet beyond the body")
    return out


def derive_row(
    solid: MeshSolid,
    features: MeshFeatures,
    name: str,
    *,
    source: str = "",
    config: TactemeConfig | None = None,
    sensor: Sensor = BONNEVILLE_16X16,
) -> ObjectRow:
    """The row of an object from its mesh features and what its faces read as.

    Parameters
    ----------
    solid : MeshSolid
        The mesh as a solid (for pressing its faces on the simulated sensor).
    features : MeshFeatures
        Of the same mesh.
    name : str
    source : str
        Recorded in the row (the mesh file).
    config : TactemeConfig, optional
        The recogniser's limits (edge angle tolerance, face-shape limits).
    sensor : Sensor
        The array the faces are read on.

    Returns
    -------
    ObjectRow
    """
    cfg = TactemeConfig() if config is None else config
    readings = read_faces(solid, features, config=cfg, sensor=sensor)
    found: dict[Tacteme, str] = {Tacteme.PC: "a vertex, a rim point or a curved patch alone"}
    found.update(_polyhedral(features, readings, cfg))
    for tac, why in _curved(features).items():
        found.setdefault(tac, why)
    order = [t for t in Tacteme if t in found]
    return ObjectRow(name, frozenset(order), tuple((t, found[t]) for t in order), source)
