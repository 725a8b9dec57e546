"""The four example objects shipped as meshes (``examples/objects/*.stl``).

Sizes (assumed) fit the 28.2 mm Bonneville array through every script of
:mod:`taxelkit.motion.mesh_scenarios`, and keep the faces of the polyhedra
large enough to read as areas on it (on the 1.76 mm pitch a slender prism's
sides read as lines, and it then rolls like a cylinder):

==================  ==========================================================
``hex-prism``       regular hexagonal prism, side 6 mm, 11 mm long: two
                    hexagons (compact faces) and six 6 x 11 mm rectangles
                    (elongated faces, or lines at some yaws)
``square-pyramid``  square base 12 mm, height 10 mm: a square and four
                    isosceles triangles (base 12 mm, height 11.7 mm; their
                    edges meet at 62.8 and 54.5 deg)
``ellipsoid``       semi-axes 9, 7 and 6 mm (icosphere, 1280 triangles)
``capsule``         radius 5 mm, 12 mm between the centres of its caps
                    (2048 triangles)
==================  ==========================================================

:func:`example_mesh` builds them with trimesh; ``examples/objects/make_objects.py``
writes the files (a test checks the files against this module).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from taxelkit.errors import InputError

if TYPE_CHECKING:
    import trimesh

__all__ = ["EXAMPLE_OBJECTS", "OUTSIDE_OBJECTS", "example_mesh"]

#: Names of the shipped examples, in the order of the experiment.
EXAMPLE_OBJECTS: tuple[str, ...] = ("hex-prism", "square-pyramid", "ellipsoid", "capsule")
#: Objects the experiment rolls without learning them (they must end "not identified"):
#: a triangular prism (equilateral ends of side 12 mm, 12 mm long), which paper 001's
#: table calls a cube when it tips over the edges of its square sides.
OUTSIDE_OBJECTS: tuple[str, ...] = ("triangular-prism",)

HEX_SIDE_MM = 6.0
HEX_LENGTH_MM = 11.0
PYRAMID_BASE_MM = 12.0
PYRAMID_HEIGHT_MM = 10.0
ELLIPSOID_SEMI_AXES_MM = (9.0, 7.0, 6.0)
CAPSULE_RADIUS_MM = 5.0
CAPSULE_LENGTH_MM = 12.0


def example_mesh(name: str) -> trimesh.Trimesh:
    """The example mesh ``name`` (mm, centred on its centroid).

    Raises
    ------
    InputError
        For an unknown name.
    """
    import trimesh

    if name == "hex-prism":
        mesh = trimesh.creation.cylinder(radius=HEX_SIDE_MM, height=HEX_LENGTH_MM, sections=6)
    elif name == "square-pyramid":
        mesh = trimesh.creation.cone(
            radius=PYRAMID_BASE_MM / math.sqrt(2.0), height=PYRAMID_HEIGHT_MM, sections=4
        )
    elif name == "ellipsoid":
        mesh = trimesh.creation.icosphere(subdivisions=3, radius=1.0)
        mesh.apply_scale(ELLIPSOID_SEMI_AXES_MM)
    elif name == "capsule":
        mesh = trimesh.creation.capsule(
            height=CAPSULE_LENGTH_MM, radius=CAPSULE_RADIUS_MM, count=[32, 32]
        )
    elif name == "triangular-prism":
        mesh = trimesh.creation.cylinder(radius=12.0 / math.sqrt(3.0), height=12.0, sections=3)
    else:
        known = ", ".join((*EXAMPLE_OBJECTS, *OUTSIDE_OBJECTS))
        raise InputError(f"unknown example object {name!r}; known: {known}")
    mesh.apply_translation(-mesh.center_mass)
    out: trimesh.Trimesh = mesh
    return out
