"""The poses whose contact type is known by construction: Level 2's labelled scenarios.

Each :class:`ContactScenario` is a solid of :mod:`taxelkit.world` with a
random size, turned so that one of its features (a sphere's surface, a
vertex, an edge, a face, a cylinder's side) points down onto the sensor, and
pressed within a depth range that keeps the contact in the regime its label
names (see :mod:`taxelkit.motion.contact_samples`, which presses them).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.world.base import Solid
from taxelkit.world.solids import Cone, Cube, Cylinder, Sphere, Tetrahedron

__all__ = ["CONTACT_LABELS", "CONTACT_SCENARIOS", "ContactScenario"]

#: The contact types a sample can be labelled with, in the order of Level 2's outputs.
CONTACT_LABELS: tuple[str, ...] = ("point", "line", "area")


def _tetrahedron(solid: Solid) -> Tetrahedron:
    if not isinstance(solid, Tetrahedron):
        raise InputError(f"expected a Tetrahedron, got {type(solid).__name__}")
    return solid


def _down_apex_tetra(solid: Solid) -> NDArray[np.float64]:
    """Direction of the apex (highest body-frame vertex) from the centroid."""
    v = _tetrahedron(solid).vertices_mm
    return np.asarray(v[int(np.argmax(v[:, 2]))] - v.mean(axis=0))


def _down_edge_tetra(solid: Solid) -> NDArray[np.float64]:
    """Direction of the midpoint of the edge between vertices 0 and 1."""
    v = _tetrahedron(solid).vertices_mm
    return np.asarray(0.5 * (v[0] + v[1]) - v.mean(axis=0))


def _fixed(direction: tuple[float, float, float]) -> Callable[[Solid], NDArray[np.float64]]:
    def down(_: Solid) -> NDArray[np.float64]:
        return np.asarray(direction, dtype=np.float64)

    return down


@dataclass(frozen=True)
class ContactScenario:
    """A solid in a pose whose contact type is known by construction.

    Parameters
    ----------
    name : str
        ``"<solid>-<feature>"``, e.g. ``"cube-edge"``.
    label : str
        ``"point"``, ``"line"`` or ``"area"``.
    make_solid : callable
        ``(rng) -> Solid`` with a random size.
    down : callable
        ``(solid) -> (3,)``: the body-frame direction (from the reference
        point) that is turned to point straight down, onto the sensor.
    depth_mm : tuple of float
        Range of indentation of the lowest point, mm.
    reason : str
        Why the label holds.
    """

    name: str
    label: str
    make_solid: Callable[[np.random.Generator], Solid]
    down: Callable[[Solid], NDArray[np.float64]]
    depth_mm: tuple[float, float]
    reason: str


def _u(rng: np.random.Generator, lo: float, hi: float) -> float:
    return float(rng.uniform(lo, hi))


#: The scenarios, by class. Sizes (mm) keep every body on the 28.2 mm
#: Bonneville array at any yaw with
#: :data:`~taxelkit.motion.contact_samples.DEFAULT_OFFSET_MM`.
CONTACT_SCENARIOS: tuple[ContactScenario, ...] = (
    ContactScenario(
        "sphere",
        "point",
        lambda r: Sphere(_u(r, 3.0, 8.0)),
        _fixed((0.0, 0.0, -1.0)),
        (0.08, 0.3),
        "a sphere touches a plane at one point (depth capped, see module notes)",
    ),
    ContactScenario(
        "cube-vertex",
        "point",
        lambda r: Cube(_u(r, 8.0, 14.0)),
        _fixed((1.0, 1.0, 1.0)),
        (0.08, 0.3),
        "a cube standing on a corner",
    ),
    ContactScenario(
        "tetrahedron-vertex",
        "point",
        lambda r: Tetrahedron(_u(r, 10.0, 18.0)),
        _down_apex_tetra,
        (0.08, 0.3),
        "a tetrahedron standing on a corner",
    ),
    ContactScenario(
        "cone-apex",
        "point",
        lambda r: Cone(_u(r, 4.0, 8.0), _u(r, 10.0, 16.0)),
        _fixed((0.0, 0.0, 1.0)),
        (0.08, 0.3),
        "a cone standing on its apex",
    ),
    ContactScenario(
        "cylinder-side",
        "line",
        lambda r: Cylinder(_u(r, 3.0, 8.0), _u(r, 12.0, 20.0)),
        _fixed((1.0, 0.0, 0.0)),
        (0.08, 0.5),
        "a cylinder lying on its side touches along a generator",
    ),
    ContactScenario(
        "cube-edge",
        "line",
        lambda r: Cube(_u(r, 8.0, 14.0)),
        _fixed((1.0, 0.0, 1.0)),
        (0.4, 0.8),
        "a cube resting on an edge",
    ),
    ContactScenario(
        "tetrahedron-edge",
        "line",
        lambda r: Tetrahedron(_u(r, 12.0, 18.0)),
        _down_edge_tetra,
        (0.4, 0.8),
        "a tetrahedron resting on an edge",
    ),
    ContactScenario(
        "cube-face",
        "area",
        lambda r: Cube(_u(r, 6.0, 14.0)),
        _fixed((0.0, 0.0, -1.0)),
        (0.08, 0.5),
        "a cube resting on a face",
    ),
    ContactScenario(
        "cylinder-end",
        "area",
        lambda r: Cylinder(_u(r, 3.0, 8.0), _u(r, 8.0, 16.0)),
        _fixed((0.0, 0.0, -1.0)),
        (0.08, 0.5),
        "a cylinder standing on an end",
    ),
    ContactScenario(
        "tetrahedron-face",
        "area",
        lambda r: Tetrahedron(_u(r, 10.0, 18.0)),
        _fixed((0.0, 0.0, -1.0)),
        (0.08, 0.5),
        "a tetrahedron resting on a face",
    ),
    ContactScenario(
        "cone-base",
        "area",
        lambda r: Cone(_u(r, 3.0, 8.0), _u(r, 8.0, 16.0)),
        _fixed((0.0, 0.0, -1.0)),
        (0.08, 0.5),
        "a cone standing on its base",
    ),
)
