"""Round solids of paper 001: sphere, cylinder, cone and truncated cone.

Body frame: the axis of revolution is the body's +z axis and the reference
point is the centroid, so a cone's base lies at ``z = -h / 4`` and its apex at
``z = 3 h / 4``.

Method
------
The sphere is closed form: ``z = -sqrt(R**2 - x**2 - y**2)``. Cylinders and
(truncated) cones are a slab between two cap planes intersected with a
lateral quadric, evaluated by :mod:`~taxelkit.world.solids_revolution`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.world.solids_grid import PoseGroup, as_rotation_batch, evaluate_bottom, line_grid
from taxelkit.world.solids_revolution import (
    RevolutionProfile,
    RevolutionSolidMethods,
)

if TYPE_CHECKING:
    import trimesh

__all__ = [
    "DEFAULT_CONE_HEIGHT_MM",
    "DEFAULT_CONE_RADIUS_MM",
    "DEFAULT_CYLINDER_HEIGHT_MM",
    "DEFAULT_CYLINDER_RADIUS_MM",
    "DEFAULT_SECTIONS",
    "DEFAULT_SPHERE_RADIUS_MM",
    "DEFAULT_SPHERE_SUBDIVISIONS",
    "DEFAULT_TRUNCATED_CONE_BOTTOM_RADIUS_MM",
    "DEFAULT_TRUNCATED_CONE_HEIGHT_MM",
    "DEFAULT_TRUNCATED_CONE_TOP_RADIUS_MM",
    "Cone",
    "Cylinder",
    "Sphere",
    "TruncatedCone",
]

# Default sizes (assumed; paper 001 names the objects but not their sizes):
# every default body fits on the 28 mm Bonneville array in any orientation.

#: Default sphere radius, mm.
DEFAULT_SPHERE_RADIUS_MM = 6.0
#: Default cylinder radius, mm.
DEFAULT_CYLINDER_RADIUS_MM = 5.0
#: Default cylinder height, mm.
DEFAULT_CYLINDER_HEIGHT_MM = 16.0
#: Default cone base radius, mm.
DEFAULT_CONE_RADIUS_MM = 6.0
#: Default cone height, mm.
DEFAULT_CONE_HEIGHT_MM = 14.0
#: Default truncated cone bottom radius, mm.
DEFAULT_TRUNCATED_CONE_BOTTOM_RADIUS_MM = 7.0
#: Default truncated cone top radius, mm.
DEFAULT_TRUNCATED_CONE_TOP_RADIUS_MM = 3.5
#: Default truncated cone height, mm.
DEFAULT_TRUNCATED_CONE_HEIGHT_MM = 12.0

#: Points on each rim of a tessellated round body (``to_trimesh``): the
#: inscribed polygon deviates by at most ``r (1 - cos(pi / 128)) = 3.0e-4 r``.
DEFAULT_SECTIONS = 128
#: Icosphere subdivisions of a tessellated sphere (5120 triangles).
DEFAULT_SPHERE_SUBDIVISIONS = 4


def _round_trimesh(rims: tuple[tuple[float, float], ...], sections: int) -> trimesh.Trimesh:
    import trimesh

    if int(sections) < 3:
        raise InputError(f"sections must be an integer >= 3, got {sections!r}")
    ang = 2.0 * np.pi * np.arange(int(sections)) / int(sections)
    pts = [
        np.stack([r * np.cos(ang), r * np.sin(ang), np.full(ang.shape, z)], axis=1)
        if r > 0.0
        else np.array([[0.0, 0.0, z]])
        for z, r in rims
    ]
    hull: trimesh.Trimesh = trimesh.Trimesh(vertices=np.concatenate(pts)).convex_hull
    return hull


def _frustum_profile(r_bottom: float, r_top: float, height: float) -> RevolutionProfile:
    """Profile of a frustum (a cone if one radius is 0, a cylinder if equal), centroid at 0."""
    num = r_bottom**2 + 2.0 * r_bottom * r_top + 3.0 * r_top**2
    z_centroid = height * num / (4.0 * (r_bottom**2 + r_bottom * r_top + r_top**2))
    z_low, z_high = -z_centroid, height - z_centroid
    rims = ((z_low, r_bottom), (z_high, r_top))
    dr = r_bottom - r_top
    if dr == 0.0:
        return RevolutionProfile(1.0, 0.0, r_bottom**2, 0.0, 1.0, z_low, z_high, rims)
    slant2 = height * height + dr * dr
    # The apex lies h R1 / (R1 - R2) above the base: above the top if R1 > R2
    # (the body then lies below it, direction -1), below the base otherwise.
    vertex = z_low + height * r_bottom / dr
    direction = -1.0 if dr > 0.0 else 1.0
    return RevolutionProfile(
        height * height / slant2, dr * dr / slant2, 0.0, vertex, direction, z_low, z_high, rims
    )


@dataclass(frozen=True)
class Sphere:
    """A sphere; reference point at its centre.

    Parameters
    ----------
    radius_mm : float
        Radius, mm.
    """

    radius_mm: float = DEFAULT_SPHERE_RADIUS_MM
    name = "sphere"

    def __post_init__(self) -> None:
        check_positive("radius_mm", self.radius_mm)

    def lowest_z_mm(self, rotations: ArrayLike) -> NDArray[np.float64]:
        """Lowest z of the sphere: ``-radius_mm`` for every pose.

        Parameters
        ----------
        rotations : (P, 3, 3) float

        Returns
        -------
        (P,) float64, mm
        """
        rot = as_rotation_batch(rotations)
        return np.full(rot.shape[0], -float(self.radius_mm))

    def lowest_point_mm(self, rotations: ArrayLike) -> NDArray[np.float64]:
        """Lowest point of the sphere, ``(P, 3)`` mm: straight below its centre."""
        rot = as_rotation_batch(rotations)
        low = np.zeros((rot.shape[0], 3))
        low[:, 2] = -float(self.radius_mm)
        return low

    def lowest_segment_mm(self, rotations: ArrayLike) -> NDArray[np.float64]:
        """The lowest point twice, ``(P, 2, 3)`` mm."""
        low = self.lowest_point_mm(rotations)
        return np.stack([low, low], axis=1)

    def bottom_mm(self, rotations: ArrayLike, x_mm: ArrayLike, y_mm: ArrayLike) -> NDArray[Any]:
        """``-sqrt(R**2 - x**2 - y**2)`` on each vertical line, ``+inf`` off the sphere.

        See :meth:`taxelkit.world.base.Solid.bottom_mm`; the result is in the
        dtype of ``x_mm``.
        """
        rot = as_rotation_batch(rotations)
        grid = line_grid(x_mm, y_mm, rot.shape[0])
        funcs = np.zeros((rot.shape[0], 1, 4))
        funcs[:, 0, 0] = float(self.radius_mm) ** 2
        funcs[:, 0, 3] = -1.0
        return evaluate_bottom(grid, [PoseGroup(None, funcs, _combine_sphere, n_work=0)])

    def to_trimesh(self, *, subdivisions: int = DEFAULT_SPHERE_SUBDIVISIONS) -> trimesh.Trimesh:
        """An icosphere with vertices on the sphere (inscribed), for plots and baselines."""
        import trimesh

        mesh: trimesh.Trimesh = trimesh.creation.icosphere(
            subdivisions=int(subdivisions), radius=float(self.radius_mm)
        )
        return mesh


def _combine_sphere(slabs: NDArray[Any], work: Any, out: NDArray[Any], pv: NDArray[Any]) -> None:
    np.sqrt(slabs[0], out=out)  # NaN off the sphere
    np.negative(out, out=out)
    np.fmin(out, np.inf, out=out)


@dataclass(frozen=True)
class Cylinder(RevolutionSolidMethods):
    """A circular cylinder standing on its base; reference point at its centre.

    Parameters
    ----------
    radius_mm : float
        Radius, mm.
    height_mm : float
        Height along the axis (body +z), mm; the caps lie at ``+-height_mm / 2``.
    """

    radius_mm: float = DEFAULT_CYLINDER_RADIUS_MM
    height_mm: float = DEFAULT_CYLINDER_HEIGHT_MM
    name = "cylinder"

    def __post_init__(self) -> None:
        check_positive("radius_mm", self.radius_mm)
        check_positive("height_mm", self.height_mm)

    @property
    def profile(self) -> RevolutionProfile:
        """The cylinder as a :class:`RevolutionProfile`."""
        return _frustum_profile(float(self.radius_mm), float(self.radius_mm), float(self.height_mm))

    def to_trimesh(self, *, sections: int = DEFAULT_SECTIONS) -> trimesh.Trimesh:
        """Inscribed prism with ``sections`` sides, for plots and baselines."""
        return _round_trimesh(self.profile.rims, sections)


@dataclass(frozen=True)
class TruncatedCone(RevolutionSolidMethods):
    """A truncated circular cone (frustum); reference point at its centroid.

    Parameters
    ----------
    bottom_radius_mm : float
        Radius of the base at body ``z = -z_c``, mm.
    top_radius_mm : float
        Radius of the top face at ``z = height_mm - z_c``, mm; may be larger
        than the bottom radius, must differ from it (use :class:`Cylinder`).
    height_mm : float
        Distance between the two faces, mm.

    Notes
    -----
    ``z_c = h (R1**2 + 2 R1 R2 + 3 R2**2) / (4 (R1**2 + R1 R2 + R2**2))`` is
    the height of the centroid above the base.
    """

    bottom_radius_mm: float = DEFAULT_TRUNCATED_CONE_BOTTOM_RADIUS_MM
    top_radius_mm: float = DEFAULT_TRUNCATED_CONE_TOP_RADIUS_MM
    height_mm: float = DEFAULT_TRUNCATED_CONE_HEIGHT_MM
    name = "truncated-cone"

    def __post_init__(self) -> None:
        check_positive("bottom_radius_mm", self.bottom_radius_mm)
        check_positive("top_radius_mm", self.top_radius_mm)
        check_positive("height_mm", self.height_mm)
        if float(self.bottom_radius_mm) == float(self.top_radius_mm):
            raise InputError(
                "top_radius_mm must differ from bottom_radius_mm (use Cylinder), "
                f"got {self.top_radius_mm!r} and {self.bottom_radius_mm!r}"
            )

    @property
    def profile(self) -> RevolutionProfile:
        """The frustum as a :class:`RevolutionProfile`."""
        return _frustum_profile(
            float(self.bottom_radius_mm), float(self.top_radius_mm), float(self.height_mm)
        )

    def to_trimesh(self, *, sections: int = DEFAULT_SECTIONS) -> trimesh.Trimesh:
        """Inscribed frustum with ``sections`` sides, for plots and baselines."""
        return _round_trimesh(self.profile.rims, sections)


@dataclass(frozen=True)
class Cone(RevolutionSolidMethods):
    """A circular cone standing on its base, apex up; reference point at its centroid.

    Parameters
    ----------
    radius_mm : float
        Base radius, mm.
    height_mm : float
        Apex height above the base, mm. The base lies at body ``z =
        -height_mm / 4`` and the apex at ``z = 3 height_mm / 4``.
    """

    radius_mm: float = DEFAULT_CONE_RADIUS_MM
    height_mm: float = DEFAULT_CONE_HEIGHT_MM
    name = "cone"

    def __post_init__(self) -> None:
        check_positive("radius_mm", self.radius_mm)
        check_positive("height_mm", self.height_mm)

    @property
    def profile(self) -> RevolutionProfile:
        """The cone as a :class:`RevolutionProfile`."""
        return _frustum_profile(float(self.radius_mm), 0.0, float(self.height_mm))

    def to_trimesh(self, *, sections: int = DEFAULT_SECTIONS) -> trimesh.Trimesh:
        """Inscribed pyramid with ``sections`` sides, for plots and baselines."""
        return _round_trimesh(self.profile.rims, sections)
