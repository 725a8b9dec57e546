"""MJCF for the MuJoCo scenes: one free solid above a rigid plate that carries the sensor.

Private to :mod:`taxelkit.motion.engines.mujoco_scenes`. The model is in SI
units (m, kg, s), as MuJoCo expects; the solids of :mod:`taxelkit.world` are in
mm and are scaled by :data:`M_PER_MM`. Every number of the model is a named
constant below with its unit and the reason for its value.

Geometry
--------
The body frame of the MuJoCo body is the body frame of the taxelkit solid
(reference point = centroid, axis along +z, see :mod:`taxelkit.world.solids`):

============== ===============================================================
sphere         ``sphere`` primitive, exact
cube           ``box`` primitive, exact
cylinder       ``cylinder`` primitive, exact (axis along z, caps at +-h/2)
cone           convex mesh: the apex and a regular :data:`MESH_SECTIONS`-gon
               circumscribing the base rim
truncated-cone convex mesh: circumscribed :data:`MESH_SECTIONS`-gons on both rims
tetrahedron    convex mesh of its four vertices, exact
============== ===============================================================

MuJoCo moves a mesh into its own inertial frame and shifts the geom by the
same offset, so the body frame stays the one the vertices are written in.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from taxelkit.sensors.presets import Sensor
from taxelkit.world.solids import AnalyticSolid
from taxelkit.world.solids_polyhedra import Cube, Tetrahedron
from taxelkit.world.solids_round import Cone, Cylinder, Sphere, TruncatedCone

#: Length unit conversion: MuJoCo runs in metres.
M_PER_MM = 1e-3

#: Physics time step, s. One millisecond resolves the fastest motion of the
#: scenes (tips at 120 deg/s turn 0.12 deg per step) and keeps the contact
#: time constant below (:data:`CONTACT_TIMECONST_S`) at 4 steps, above
#: MuJoCo's stability limit of 2 steps.
TIMESTEP_S = 1e-3

#: Physics steps per second (``1 / TIMESTEP_S`` as an exact integer, used to
#: map frame times onto steps without rounding).
PHYSICS_HZ = 1000

#: Standard gravity, m/s^2.
GRAVITY_M_S2 = 9.81

#: Density of the solids, kg/m^3, drawn uniformly per scene: plastics from
#: polyethylene to PMMA and POM (0.95-1.4 g/cm^3), what hand-sized test
#: objects are commonly turned from (assumed; paper 001 gives no material). A
#: 6 mm ball weighs 0.9-1.3 g.
DENSITY_KG_M3 = (950.0, 1400.0)

#: Coulomb friction between a rolling solid and the sensor's rubber skin,
#: drawn uniformly per scene (assumed: rubber on plastic is about 0.8-1.2). A
#: ball pushed at its centre needs ``mu >= (2/7) a / g`` to roll without slip;
#: the pushes accelerate at most 0.1 m/s^2, so 0.8 leaves a factor of 25.
ROLLING_FRICTION = (0.8, 1.2)

#: Coulomb friction of the sliding scenes, drawn uniformly per scene (assumed:
#: a lubricated or PTFE-like skin). A face dragged at its centroid tips once
#: the drag exceeds ``mu_tip = (distance from the centroid's foot to the
#: bottom edge) / (centroid height)``; the smallest ``mu_tip`` of the sliding
#: bodies, a tall jittered cylinder on its end (3.5 / 10.4), is 0.34, so 0.15
#: drags without tipping.
SLIDING_FRICTION = (0.05, 0.15)

#: Torsional and rolling friction coefficients, m: unused (condim 3, sliding
#: friction only), so a lone ball keeps rolling until the push controller
#: brakes it (the "finger" that stops it), and spinning on a face is resisted
#: by the spread of the face's contact points alone.
CONDIM = 3

#: Contact time constant and damping ratio (MuJoCo ``solref``), s and 1: a
#: stiffer contact than MuJoCo's default (0.02 s) so that a resting solid sinks
#: only a few micrometres into the rigid plate, far below the 30 um contact
#: threshold of the skin model; critically damped, so landings do not bounce.
CONTACT_TIMECONST_S = 0.004
CONTACT_DAMPRATIO = 1.0

#: Points on each rim of a meshed cone or truncated cone. The polygons
#: *circumscribe* the rims, so every flat side of the mesh is tangent to the
#: true body along a generator: a meshed cone resting on a side touches the
#: plane exactly where the analytic cone does, and rolling over a polygon
#: corner lifts it by at most ``r (1 / cos(pi / 128) - 1) = 3e-4 r`` (2 um
#: for a 7.5 mm rim), below the skin model's 30 um contact threshold.
MESH_SECTIONS = 128

#: Drawn half-size of the plate beyond the array, mm (visual only: the plate
#: collides as MuJoCo's infinite ``plane``, whose dedicated colliders give a
#: line or a face several contact points; a ``box`` plate goes through the
#: general convex collider, one point per pair, and a cylinder lying on one
#: point rolls away). The scenes are simulated about the origin and then
#: placed on the array (see :mod:`~taxelkit.motion.engines.mujoco_scenes`).
PLATE_BORDER_MM = 40.0

#: Name of the moving body, its free joint and geom, and the plate geom.
BODY_NAME = "solid"
PLATE_NAME = "plate"


def _floats(values: NDArray[np.float64]) -> str:
    return " ".join(f"{float(v):.10g}" for v in np.ravel(values))


def _geom_xml(solid: AnalyticSolid, friction: float, density: float) -> tuple[str, str]:
    """The solid's geom element and its mesh asset (empty for primitives)."""
    common = (
        f'name="{BODY_NAME}" density="{density:.10g}" friction="{friction:.10g} 0 0" '
        f'condim="{CONDIM}"'
    )
    if isinstance(solid, Sphere):
        return f'<geom type="sphere" size="{solid.radius_mm * M_PER_MM:.10g}" {common}/>', ""
    if isinstance(solid, Cube):
        half = 0.5 * solid.edge_mm * M_PER_MM
        return f'<geom type="box" size="{half:.10g} {half:.10g} {half:.10g}" {common}/>', ""
    if isinstance(solid, Cylinder):
        size = f"{solid.radius_mm * M_PER_MM:.10g} {0.5 * solid.height_mm * M_PER_MM:.10g}"
        return f'<geom type="cylinder" size="{size}" {common}/>', ""
    vertices = _mesh_vertices_mm(solid)
    asset = f'<mesh name="{BODY_NAME}" vertex="{_floats(vertices * M_PER_MM)}"/>'
    return f'<geom type="mesh" mesh="{BODY_NAME}" {common}/>', asset


def _mesh_vertices_mm(solid: AnalyticSolid) -> NDArray[np.float64]:
    """Vertices (body frame, mm) whose convex hull is the meshed solid."""
    if isinstance(solid, Tetrahedron):
        return np.asarray(solid.vertices_mm, dtype=np.float64)
    if isinstance(solid, Cone | TruncatedCone):
        ang = 2.0 * math.pi * np.arange(MESH_SECTIONS) / MESH_SECTIONS
        out = 1.0 / math.cos(math.pi / MESH_SECTIONS)  # circumscribed polygon
        rings = [
            np.stack([out * r * np.cos(ang), out * r * np.sin(ang), np.full(ang.shape, z)], axis=1)
            if r > 0.0
            else np.array([[0.0, 0.0, z]])
            for z, r in solid.profile.rims
        ]
        return np.concatenate(rings)
    raise TypeError(f"no mesh for {solid!r}")  # pragma: no cover - all six handled


def scene_xml(
    solid: AnalyticSolid, sensor: Sensor, *, friction: float, density_kg_m3: float
) -> str:
    """MJCF of one solid (free joint, at the origin) above the plate carrying ``sensor``.

    Parameters
    ----------
    solid : AnalyticSolid
        One of the six solids; sizes in mm.
    sensor : Sensor
        Its array's width and height set the drawn sensor site and plate.
    friction : float
        Coulomb friction of the solid and the plate (MuJoCo takes the larger).
    density_kg_m3 : float
        Density of the solid, kg/m^3 (MuJoCo derives mass and inertia).

    Returns
    -------
    str
        The MJCF document. The plate's top face (the skin surface) is ``z = 0``.
    """
    geom, asset = _geom_xml(solid, friction, density_kg_m3)
    hx = (0.5 * sensor.array.width_mm + PLATE_BORDER_MM) * M_PER_MM
    hy = (0.5 * sensor.array.height_mm + PLATE_BORDER_MM) * M_PER_MM
    sx = 0.5 * sensor.array.width_mm * M_PER_MM
    sy = 0.5 * sensor.array.height_mm * M_PER_MM
    return f"""<mujoco model="taxelkit-{solid.name}">
  <compiler angle="radian" autolimits="true"/>
  <option timestep="{TIMESTEP_S:g}" gravity="0 0 {-GRAVITY_M_S2:g}" integrator="implicitfast"/>
  <default>
    <geom solref="{CONTACT_TIMECONST_S:g} {CONTACT_DAMPRATIO:g}"/>
  </default>
  <asset>{asset}</asset>
  <worldbody>
    <geom name="{PLATE_NAME}" type="plane" size="{hx:.10g} {hy:.10g} 0.001"
          friction="{friction:.10g} 0 0" condim="{CONDIM}"/>
    <site name="sensor" type="box" size="{sx:.10g} {sy:.10g} 1e-5" pos="0 0 0"/>
    <body name="{BODY_NAME}">
      <freejoint name="{BODY_NAME}"/>
      {geom}
    </body>
  </worldbody>
</mujoco>
"""
