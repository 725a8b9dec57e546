"""The world the sensor touches: relief specimens (paper 000), solids (paper 001), poses."""

from taxelkit.world.base import Relief, Solid
from taxelkit.world.mesh_solid import MeshSolid, load_mesh_solid
from taxelkit.world.pose import matrix_from_axis_angle, matrix_from_euler_xyz_deg
from taxelkit.world.random_shapes import GeneratedShape, generate_shapes
from taxelkit.world.relief import (
    SHAPE_NAMES,
    CircleRelief,
    EdgeRelief,
    HeightmapRelief,
    PolygonRelief,
    heightmap_from_relief,
    load_heightmap,
    relief_from_heightmap,
    relief_from_vertices,
    relief_shape,
)
from taxelkit.world.solids import (
    SOLID_NAMES,
    Cone,
    Cube,
    Cylinder,
    Sphere,
    Tetrahedron,
    TruncatedCone,
    make_solid,
)

__all__ = [
    "SHAPE_NAMES",
    "SOLID_NAMES",
    "CircleRelief",
    "Cone",
    "Cube",
    "Cylinder",
    "EdgeRelief",
    "GeneratedShape",
    "HeightmapRelief",
    "MeshSolid",
    "PolygonRelief",
    "Relief",
    "Solid",
    "Sphere",
    "Tetrahedron",
    "TruncatedCone",
    "generate_shapes",
    "heightmap_from_relief",
    "load_heightmap",
    "load_mesh_solid",
    "make_solid",
    "matrix_from_axis_angle",
    "matrix_from_euler_xyz_deg",
    "relief_from_heightmap",
    "relief_from_vertices",
    "relief_shape",
]
