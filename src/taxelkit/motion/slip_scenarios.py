"""Rolls with a slipping phase, for the ``slip`` experiment (kinematic engine).

Each of the six solids of paper 001 is moved as in
:mod:`taxelkit.motion.scenarios`, with one phase of sliding inside the motion
(the partial slip a real hand produces); ``phase`` labels it ``"sliding"``
and :meth:`~taxelkit.motion.rolling.Scenario.slip_mm` measures it (ground
truth, for scoring only):

============== ===============================================================
sphere         rolled, skidded without turning (2-5 mm), rolled on at a
               right angle: a point contact, whose slip no binary image shows
cylinder       on its side, rolled part of the way, slid along its own axis
               (2-5 mm), rolled on (the line slides along itself)
cube,          placed on a face, dragged across the sensor (3-8 mm), then
tetrahedron    tipped over its edges as in the rolling script
cone,          placed on the base face (a truncated cone: on either face),
truncated-cone dragged, tilted onto the rim, laid down and rolled about the
               (virtual) apex; a body too large to be laid down from its face
               on the array is rolled on its side and then slid along its
               line (2-5 mm)
============== ===============================================================

Speeds and holds are those of :mod:`taxelkit.motion._script` (slides at
3-6 mm/s); the fit on the array is that of the rolling scripts.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from taxelkit.errors import InputError, check_positive
from taxelkit.motion._script import (
    CONE_TURN_DEG,
    CYLINDER_ROLL_MM,
    FRUSTUM_TURN_DEG,
    HOLD_S,
    ROLL_MM_S,
    SLIDE_MM,
    SLIDE_MM_S,
    SPHERE_RUN_MM,
    Builder,
    Draws,
    apex_and_axis,
    begin_contact,
    end_contact,
    lay_silently,
    rest_pose,
    roll_about_apex,
    roll_line,
    tilt_from_face,
    unit_h,
)
from taxelkit.motion.roll_paths import translate
from taxelkit.motion.rolling import DEFAULT_DEPTH_MM, DEFAULT_RATE_HZ, E_Z, Scenario
from taxelkit.motion.scenario_scripts import Limits, polyhedron_tips
from taxelkit.motion.scenarios import _N_DRAWS, _assemble, _draw_body
from taxelkit.sensors.noise import RngLike
from taxelkit.sensors.presets import BONNEVILLE_16X16, Sensor
from taxelkit.world.pose import matrix_from_axis_angle
from taxelkit.world.solids import SOLID_NAMES
from taxelkit.world.solids_round import Cone, Cylinder, Sphere, TruncatedCone

__all__ = ["LINE_SLIDE_MM", "SKID_MM", "make_partial_slip_scenario"]

#: How far a lying cylinder slides along its axis, mm (its line must stay on the array).
LINE_SLIDE_MM = (2.0, 5.0)
#: How far a rolling sphere skids, mm.
SKID_MM = (2.0, 5.0)


def _slide(b: Builder, d: Draws, direction: np.ndarray, dist: float, label: str) -> None:
    """Slide the body by ``dist`` along the horizontal ``direction`` without turning it."""
    pose = b.pose
    step = dist * np.asarray(direction[:2], dtype=np.float64)
    speed = d.span(SLIDE_MM_S)
    b.move(lambda u: translate(pose, u[:, None] * step), dist / speed, "sliding", label)
    b.hold(d.span(HOLD_S), label)


def _heading(d: Draws) -> np.ndarray:
    a = d.uniform(0.0, 2.0 * math.pi)
    return np.array([math.cos(a), math.sin(a), 0.0])


def _sphere(b: Builder, d: Draws, lim: Limits) -> None:
    solid = b.solid
    assert isinstance(solid, Sphere)
    begin_contact(b, d, "side")
    direction = np.array([1.0, 0.0, 0.0])
    roll_line(b, solid.radius_mm, direction, d.span(SPHERE_RUN_MM) * lim.shrink,
              d.span(ROLL_MM_S), "side")  # fmt: skip
    _slide(b, d, direction, d.span(SKID_MM) * lim.shrink, "side")
    turn = np.array([-direction[1], direction[0], 0.0]) * d.sign()
    roll_line(b, solid.radius_mm, turn, d.span(SPHERE_RUN_MM) * lim.shrink,
              d.span(ROLL_MM_S), "side")  # fmt: skip
    b.hold(d.span(HOLD_S), "side")
    end_contact(b, d)


def _cylinder(b: Builder, d: Draws, lim: Limits) -> None:
    solid = b.solid
    assert isinstance(solid, Cylinder)
    u = unit_h(np.array([1.0, 0.0, 0.0]))
    lay_silently(b, u)  # the axis along u, the line along u
    begin_contact(b, d, "side")
    direction = np.cross(E_Z, u)
    dist = d.sign() * d.span(CYLINDER_ROLL_MM) * lim.shrink
    part = d.uniform(0.3, 0.6)
    speed = d.span(ROLL_MM_S)
    roll_line(b, solid.radius_mm, direction, part * dist, speed, "side")
    _slide(b, d, d.sign() * u, d.span(LINE_SLIDE_MM) * lim.shrink, "side")
    roll_line(b, solid.radius_mm, direction, (1.0 - part) * dist, speed, "side")
    b.hold(d.span(HOLD_S), "side")
    end_contact(b, d)


def _polyhedron(b: Builder, d: Draws, lim: Limits) -> None:
    begin_contact(b, d, "face")
    _slide(b, d, _heading(d), d.span(SLIDE_MM) * lim.shrink, "face")
    polyhedron_tips(b, d, lim)


def _cone(b: Builder, d: Draws, lim: Limits) -> None:
    solid = b.solid
    assert isinstance(solid, Cone | TruncatedCone)
    frustum = isinstance(solid, TruncatedCone)
    u = np.array([1.0, 0.0, 0.0])
    if frustum and d.coin():
        b.pose = rest_pose(solid, matrix_from_axis_angle([1.0, 0.0, 0.0], math.pi))
    turn = math.radians(d.span(FRUSTUM_TURN_DEG if frustum else CONE_TURN_DEG))
    turn *= d.sign() * lim.shrink
    speed = d.span(ROLL_MM_S)
    if lim.allow_lay:  # dragged on a face, laid down and rolled
        begin_contact(b, d, "face")
        _slide(b, d, _heading(d), d.span(SLIDE_MM) * lim.shrink, "face")
        tilt_from_face(b, u, d, lay=True)
        roll_about_apex(b, turn, speed, "side")
        b.hold(d.span(HOLD_S), "side")
    else:  # too large to lay down from a face here: rolled on its side, then slid along its line
        lay_silently(b, u)
        begin_contact(b, d, "side")
        roll_about_apex(b, turn, speed, "side")
        b.hold(d.span(HOLD_S), "side")
        line = unit_h(np.asarray(apex_and_axis(solid, b.pose)[1], dtype=np.float64))
        _slide(b, d, d.sign() * line, d.span(LINE_SLIDE_MM) * lim.shrink, "side")
    end_contact(b, d)


_SCRIPTS: dict[str, Callable[[Builder, Draws, Limits], None]] = {
    "sphere": _sphere,
    "cylinder": _cylinder,
    "cube": _polyhedron,
    "tetrahedron": _polyhedron,
    "cone": _cone,
    "truncated-cone": _cone,
}


def make_partial_slip_scenario(
    name: str,
    *,
    rng: RngLike = None,
    size_jitter: float = 0.3,
    depth_mm: float = DEFAULT_DEPTH_MM,
    depth_jitter: float = 0.3,
    rate_hz: float = DEFAULT_RATE_HZ,
    sensor: Sensor = BONNEVILLE_16X16,
) -> Scenario:
    """A roll of one solid with one slipping phase (see the module docstring).

    Parameters
    ----------
    name : str
        One of the six solids (:data:`~taxelkit.world.solids.SOLID_NAMES`).
    rng : int, Generator or None
        Seed: the same seed gives an identical scenario.
    size_jitter, depth_mm, depth_jitter, rate_hz, sensor
        As for :func:`~taxelkit.motion.scenarios.make_scenario`.

    Returns
    -------
    Scenario
        Named ``"NAME-slip"``; ``slides`` is False (the object also rolls).

    Raises
    ------
    InputError
        For an unknown name or a script that cannot be fitted on the array.

    Examples
    --------
    >>> sc = make_partial_slip_scenario("cube", rng=1)
    >>> sc.name, "sliding" in sc.phase
    ('cube-slip', True)
    """
    if name not in SOLID_NAMES:
        raise InputError(f"unknown solid {name!r}; known: {', '.join(SOLID_NAMES)}")
    rate = check_positive("rate_hz", rate_hz)
    gen = np.random.default_rng(rng)
    depth0 = check_positive("depth_mm", depth_mm)
    _, solid, depth, _ = _draw_body(name, gen, float(size_jitter), depth0, depth_jitter)
    return _assemble(
        f"{name}-slip",
        solid,
        _SCRIPTS[name],
        draws=gen.random(_N_DRAWS),
        yaw=float(gen.uniform(0.0, 2.0 * math.pi)),
        shift_fraction=gen.random(2),
        rate_hz=rate,
        depth_mm=depth,
        sensor=sensor,
        slides=False,
        rotation0=np.eye(3),
    )
