"""The six solids of paper 001 and a registry to build them by name.

Paper 001 recognises a cube, a sphere, a cone, a truncated cone, a cylinder
and a tetrahedron pressed onto the 16 x 16 Bonneville array. Each class here
implements the :class:`~taxelkit.world.base.Solid` protocol analytically (see
:mod:`~taxelkit.world.solids_polyhedra` and :mod:`~taxelkit.world.solids_round`
for the method), with sizes in mm and defaults that fit on the 28 mm array in
any orientation. Arbitrary convex meshes live in
:mod:`~taxelkit.world.mesh_solid`.

Body frames (reference point = centroid in every case):

========================  ==========================================================
``Cube``                  faces ``x, y, z = +-edge/2``
``Sphere``                centre at the origin
``Cylinder``              axis along +z, caps at ``z = +-height/2``
``Cone``                  axis along +z, base at ``z = -height/4``, apex at ``3 height/4``
``TruncatedCone``         axis along +z, bottom (``bottom_radius_mm``) below the top
``Tetrahedron``           base face at ``z = -h/4``, apex on +z at ``3 h/4``
========================  ==========================================================
"""

from __future__ import annotations

import dataclasses
from typing import Any

from taxelkit.errors import InputError, check_positive
from taxelkit.world.solids_polyhedra import (
    DEFAULT_CUBE_EDGE_MM,
    DEFAULT_TETRAHEDRON_EDGE_MM,
    Cube,
    Tetrahedron,
)
from taxelkit.world.solids_round import (
    DEFAULT_CONE_HEIGHT_MM,
    DEFAULT_CONE_RADIUS_MM,
    DEFAULT_CYLINDER_HEIGHT_MM,
    DEFAULT_CYLINDER_RADIUS_MM,
    DEFAULT_SPHERE_RADIUS_MM,
    DEFAULT_TRUNCATED_CONE_BOTTOM_RADIUS_MM,
    DEFAULT_TRUNCATED_CONE_HEIGHT_MM,
    DEFAULT_TRUNCATED_CONE_TOP_RADIUS_MM,
    Cone,
    Cylinder,
    Sphere,
    TruncatedCone,
)

__all__ = [
    "DEFAULT_CONE_HEIGHT_MM",
    "DEFAULT_CONE_RADIUS_MM",
    "DEFAULT_CUBE_EDGE_MM",
    "DEFAULT_CYLINDER_HEIGHT_MM",
    "DEFAULT_CYLINDER_RADIUS_MM",
    "DEFAULT_SPHERE_RADIUS_MM",
    "DEFAULT_TETRAHEDRON_EDGE_MM",
    "DEFAULT_TRUNCATED_CONE_BOTTOM_RADIUS_MM",
    "DEFAULT_TRUNCATED_CONE_HEIGHT_MM",
    "DEFAULT_TRUNCATED_CONE_TOP_RADIUS_MM",
    "SOLID_NAMES",
    "AnalyticSolid",
    "Cone",
    "Cube",
    "Cylinder",
    "Sphere",
    "Tetrahedron",
    "TruncatedCone",
    "make_solid",
    "solid_size_names",
]

#: Any of the six analytic solids.
AnalyticSolid = Cube | Sphere | Cone | TruncatedCone | Cylinder | Tetrahedron

#: Registry names of the six solids of paper 001, in the paper's order.
SOLID_NAMES: tuple[str, ...] = (
    "cube",
    "sphere",
    "cone",
    "truncated-cone",
    "cylinder",
    "tetrahedron",
)

_CLASSES: dict[str, type[AnalyticSolid]] = {
    cls.name: cls for cls in (Cube, Sphere, Cone, TruncatedCone, Cylinder, Tetrahedron)
}
assert tuple(_CLASSES) == SOLID_NAMES


def _solid_class(name: str) -> type[AnalyticSolid]:
    try:
        return _CLASSES[name]
    except (KeyError, TypeError):
        known = ", ".join(SOLID_NAMES)
        raise InputError(f"unknown solid {name!r}; known solids: {known}") from None


def solid_size_names(name: str) -> tuple[str, ...]:
    """The size parameters (all in mm) of the solid called ``name``.

    Raises
    ------
    InputError
        If ``name`` is not in :data:`SOLID_NAMES`.

    Examples
    --------
    >>> solid_size_names("cylinder")
    ('radius_mm', 'height_mm')
    """
    return tuple(f.name for f in dataclasses.fields(_solid_class(name)) if f.init)


def make_solid(name: str, *, scale: float = 1.0, **sizes: float) -> AnalyticSolid:
    """Build one of the six solids by name, with default or given sizes.

    Parameters
    ----------
    name : str
        One of :data:`SOLID_NAMES`.
    scale : float
        Factor applied to every size (after overrides), > 0.
    **sizes : float, mm
        Size overrides by field name (see :func:`solid_size_names`), for
        example ``radius_mm=4.0``.

    Returns
    -------
    Cube, Sphere, Cone, TruncatedCone, Cylinder or Tetrahedron

    Raises
    ------
    InputError
        For an unknown name (listing the known ones), an unknown size
        keyword (listing the valid ones) or a size that is not positive.

    Examples
    --------
    >>> make_solid("cube", scale=0.5)
    Cube(edge_mm=6.0)
    >>> make_solid("cone", height_mm=10.0).height_mm
    10.0
    """
    cls = _solid_class(name)
    factor = check_positive("scale", scale)
    fields = [f for f in dataclasses.fields(cls) if f.init]
    valid = tuple(f.name for f in fields)
    unknown = sorted(set(sizes) - set(valid))
    if unknown:
        raise InputError(
            f"unknown size(s) {', '.join(unknown)} for solid {name!r}; "
            f"valid sizes: {', '.join(valid)}"
        )
    kwargs: dict[str, Any] = {}
    for f in fields:
        value = check_positive(f.name, sizes.get(f.name, f.default))  # type: ignore[arg-type]
        kwargs[f.name] = value * factor
    return cls(**kwargs)
