"""Labelled contact images from the simulator, for learning and testing the Level 2 network.

The contact type of a solid pressed onto the sensor is known by construction
when the pose is chosen: a sphere, a vertex or an apex touches at a point; a
cylinder on its side or a polyhedron on an edge along a line; a flat face over
an area. This module presses the solids of :mod:`taxelkit.world` onto a
simulated sensor in such poses, with random sizes, depths, positions, yaw
and read-out noise (:func:`pressed_contacts`; the scenarios are those of
:mod:`taxelkit.motion.contact_scenarios`); the frames of whole rolls from
either motion engine, labelled by the engine's phase of each frame, come from
:func:`~taxelkit.motion.rolled_contacts.rolled_contacts`. It returns images
and labels only: the features are the recogniser's business, and
:mod:`taxelkit.smart` imports nothing of the world.

Depth ranges (mm of indentation of the lowest point) are part of each
scenario's construction: they keep the contact in the regime its label
names. A sphere's depth is also capped so that its geometric contact radius
``sqrt(2 R d)`` stays below :data:`POINT_MAX_CONTACT_RADIUS_MM` (a large
sphere pressed deep makes an area contact, and its label would lie). An edge
(90 deg cube or 70.5 deg tetrahedron dihedral) penetrates only a strip about
``2 d`` wide, narrower than a taxel, so edges are pressed 0.4-0.8 mm before
the simulated skin shows them along their length.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.motion.contact_scenarios import CONTACT_LABELS, CONTACT_SCENARIOS, ContactScenario
from taxelkit.sensors.noise import RngLike
from taxelkit.sensors.presets import BONNEVILLE_16X16, Sensor
from taxelkit.sensors.press import displacement_from_solid
from taxelkit.world.pose import matrix_from_axis_angle
from taxelkit.world.solids import Sphere

__all__ = [
    "DEFAULT_OFFSET_MM",
    "DEFAULT_OVERSAMPLE",
    "POINT_MAX_CONTACT_RADIUS_MM",
    "LabelledContacts",
    "pressed_contacts",
]


#: Largest geometric contact radius of a sphere labelled "point", mm: 1.5 mm
#: keeps the contact disc (3 mm across) within two Bonneville taxels.
POINT_MAX_CONTACT_RADIUS_MM = 1.5
#: Largest offset of the body's reference point from the array centre along
#: x and y, mm: every scenario's contact then stays on the 28.2 mm array.
DEFAULT_OFFSET_MM = 2.0
#: Samples per element along each axis for the area average (see
#: :func:`~taxelkit.sensors.press.displacement_from_solid`): 3 resolves the
#: thin strip of an edge, which taxel-centre sampling (1) often misses.
DEFAULT_OVERSAMPLE = 3
#: Distinct body sizes drawn per scenario in one call (each size is one
#: batched call of the simulator).
_SIZES_PER_SCENARIO = 6
#: Rounds of drawing allowed to replace empty images before giving up.
_MAX_ROUNDS = 20


def _rotation_down(direction: NDArray[np.float64]) -> NDArray[np.float64]:
    """The rotation taking the unit vector of ``direction`` to ``(0, 0, -1)``."""
    d = direction / np.linalg.norm(direction)
    target = np.array([0.0, 0.0, -1.0])
    axis = np.cross(d, target)
    s = float(np.linalg.norm(axis))
    c = float(d @ target)
    if s < 1e-12:
        if c > 0:
            return np.eye(3)
        return matrix_from_axis_angle([1.0, 0.0, 0.0], math.pi)
    return matrix_from_axis_angle(axis, math.atan2(s, c))


@dataclass(frozen=True, eq=False)
class LabelledContacts:
    """Contact images labelled with the contact type that made them.

    Parameters
    ----------
    labels : (N,) str
        ``"point"``, ``"line"`` or ``"area"`` (:data:`CONTACT_LABELS`).
    scenario : (N,) str
        Name of the scenario that made each sample.
    images : (N, rows, cols) bool
        The binary contact images.
    depth_mm : (N,) float
        Indentation, mm.
    pitch_mm : float
        Taxel pitch of the sensor, mm.
    """

    labels: NDArray[np.str_]
    scenario: NDArray[np.str_]
    images: NDArray[np.bool_]
    depth_mm: NDArray[np.float64]
    pitch_mm: float

    def __len__(self) -> int:
        return int(self.labels.shape[0])

    def subset(self, index: NDArray[Any]) -> LabelledContacts:
        """The samples selected by an index or boolean mask."""
        return LabelledContacts(
            self.labels[index],
            self.scenario[index],
            self.images[index],
            self.depth_mm[index],
            self.pitch_mm,
        )


def _press_scenario(
    scenario: ContactScenario,
    n: int,
    sensor: Sensor,
    gen: np.random.Generator,
    *,
    offset_mm: float,
    oversample: int,
    add_noise: bool,
) -> tuple[NDArray[np.bool_], NDArray[np.float64]]:
    """``n`` non-empty contact images of one scenario and their depths."""
    images: list[NDArray[np.bool_]] = []
    depths: list[NDArray[np.float64]] = []
    have = 0
    for _ in range(_MAX_ROUNDS):
        need = n - have
        if need <= 0:
            break
        counts = np.bincount(gen.integers(0, _SIZES_PER_SCENARIO, size=need))
        for k in counts[counts > 0]:
            solid = scenario.make_solid(gen)
            lo, hi = scenario.depth_mm
            if isinstance(solid, Sphere):
                hi = min(hi, POINT_MAX_CONTACT_RADIUS_MM**2 / (2.0 * solid.radius_mm))
            yaw = gen.uniform(0.0, 2.0 * math.pi, size=int(k))
            rot = matrix_from_axis_angle([0.0, 0.0, 1.0], yaw) @ _rotation_down(
                scenario.down(solid)
            )
            pos = gen.uniform(-offset_mm, offset_mm, size=(int(k), 2))
            depth = gen.uniform(lo, max(lo, hi), size=int(k))
            u = displacement_from_solid(
                sensor,
                solid,
                rot,
                pos,
                indent_mm=depth,
                oversample=oversample,
                add_noise=add_noise,
                rng=gen,
            )
            img = sensor.contact_from_displacement(u)
            keep = img.any(axis=(1, 2))
            images.append(img[keep])
            depths.append(depth[keep])
            have += int(np.count_nonzero(keep))
    if have < n:
        raise InputError(
            f"scenario {scenario.name!r} gave only {have} non-empty images of {n} "
            f"on sensor {sensor.name!r}; its depths may be below the contact threshold"
        )
    return np.concatenate(images)[:n], np.concatenate(depths)[:n]


def _scenario_shares(
    scenarios: tuple[ContactScenario, ...], n_per_class: int
) -> list[tuple[ContactScenario, int]]:
    """Each scenario with its number of samples, by class: a class's ``n_per_class``
    split evenly between its scenarios (the first ones take the remainder)."""
    out: list[tuple[ContactScenario, int]] = []
    for label in CONTACT_LABELS:
        group = [s for s in scenarios if s.label == label]
        if not group:
            continue
        shares = np.full(len(group), n_per_class // len(group))
        shares[: n_per_class % len(group)] += 1
        out += [(sc, int(c)) for sc, c in zip(group, shares, strict=True) if c > 0]
    return out


def pressed_contacts(
    sensor: Sensor = BONNEVILLE_16X16,
    *,
    n_per_class: int = 400,
    scenarios: tuple[ContactScenario, ...] = CONTACT_SCENARIOS,
    offset_mm: float = DEFAULT_OFFSET_MM,
    oversample: int = DEFAULT_OVERSAMPLE,
    add_noise: bool = True,
    rng: RngLike = None,
) -> LabelledContacts:
    """Simulated contact images labelled point, line or area by construction.

    Each class's samples are split evenly between its scenarios; every sample
    has a random body size (scenario ranges), random yaw about the vertical,
    random position within ``+-offset_mm`` of the array centre and random
    depth (scenario range), and the sensor's noise. Empty images (a depth too
    shallow after noise) are replaced by new draws.

    Parameters
    ----------
    sensor : Sensor
        Simulated sensor (geometry, skin, noise, contact threshold).
    n_per_class : int
        Samples of each class present in ``scenarios``.
    scenarios : tuple of ContactScenario
        Which constructions to use (default :data:`CONTACT_SCENARIOS`).
    offset_mm : float
        Largest offset of the body from the array centre along x and y, mm.
    oversample : int
        Simulator samples per element along each axis.
    add_noise : bool
        Apply the sensor's noise model.
    rng : int, Generator or None
        Seed; same seed, same samples.

    Returns
    -------
    LabelledContacts
        Ordered by class (point, line, area) and scenario.

    Raises
    ------
    InputError
        On bad options, or when a scenario cannot produce contact images.
    """
    if not isinstance(n_per_class, int | np.integer) or n_per_class < 1:
        raise InputError(f"n_per_class must be an integer >= 1, got {n_per_class!r}")
    if len(scenarios) == 0:
        raise InputError("scenarios must not be empty")
    off = check_positive("offset_mm", offset_mm, allow_zero=True)
    gen = np.random.default_rng(rng)
    images: list[NDArray[np.bool_]] = []
    depths: list[NDArray[np.float64]] = []
    labels: list[NDArray[np.str_]] = []
    names: list[NDArray[np.str_]] = []
    for scenario, count in _scenario_shares(scenarios, int(n_per_class)):
        img, dep = _press_scenario(
            scenario, count, sensor, gen, offset_mm=off, oversample=oversample, add_noise=add_noise
        )
        images.append(img)
        depths.append(dep)
        labels.append(np.full(count, scenario.label))
        names.append(np.full(count, scenario.name))
    return LabelledContacts(
        labels=np.concatenate(labels),
        scenario=np.concatenate(names),
        images=np.concatenate(images),
        depth_mm=np.concatenate(depths),
        pitch_mm=float(sensor.array.pitch_mm),
    )
