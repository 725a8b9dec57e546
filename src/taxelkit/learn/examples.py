"""The four example objects shipped as meshes (``examples/objects/*.stl``).

Sizes are chosen to fit the 28.2 mm Bonneville array in every resting pose
(assumed; with the +-10 % size jitter of the ``new-objects`` experiment):

==================  ==========================================================
``hex-prism``       regular hexagonal prism, side 5.5 mm, 13 mm long: two
                    hexagons (compact faces) and six 5.5 x 13 mm rectangles
                    (elongated faces)
``square-pyramid``  square base 8 mm, height 20 mm: a square (compact) and
                    four tall isosceles triangles (elongated, triangular),
                    whose edges meet at 79 and 22 deg, never near 60
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

__all__ = ["EXAMPLE_OBJECTS", "example_mesh"]

#: Names of the shipped examples, in the order of the experiment.
EXAMPLE_OBJECTS: tuple[str, ...] = ("hex-prism", "square-pyramid", "ellipsoid", "capsule")

HEX_SIDE_MM = 4.2
HEX_LENGTH_MM = 14.0
PYRAMID_BASE_MM = 7.0
PYRAMID_HEIGHT_MM = 20.0
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
    else:
        raise InputError(f"unknown example object {name!r}; known: {', '.join(EXAMPLE_OBJECTS)}")
    mesh.apply_translation(-mesh.center_mass)
    return mesh
