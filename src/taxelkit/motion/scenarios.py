"""Randomised motion scripts for the six solids of paper 001, a sliding script, and Fig. 3.

Each script places a solid on the sensor, moves it the ways its shape allows
when it rolls without slip, and lifts it off; :func:`make_scenario` draws the
sizes, the indentation, the choices of the script and the pose on the array
from one seed. The scripts aim at the tactemes of paper 001 (Table 1):

============== ===============================================================
sphere         placed, rolled in 2-3 straight runs joined by orthogonal turns
               (PC, PC moves, PC takes an orthogonal turn)
cylinder       on an end (AC) tilted onto its rim (PC), laid on its side (LC),
               rolled straight and maybe back (LCMP), maybe stood up again
               through a rim; or placed on its side directly
cube           on a face, tipped about 2-3 bottom edges in turn (AC -> LC ->
               AC -> LC, the lines parallel or at 90 deg), each time back onto
               the face or over onto the next one; maybe balanced on a vertex
tetrahedron    the same on triangular faces (lines at 60 or 120 deg)
cone           on its base tilted onto the rim and laid on its side, or placed
               on its side; rolled about its fixed apex (LCMT about one end);
               maybe tilted up onto the apex (PC)
truncated-cone on either face, tilted onto the rim and laid on its side, or
               placed on its side; rolled in an arc about the virtual apex
               (LCMT in an arc); maybe stood up onto a face
sliding        a face-down solid (cube, tetrahedron, cylinder, cone or
               truncated cone) dragged across the sensor and/or spun in place
               (AC moves, AC rotates): no rolling object can do this
============== ===============================================================

Timing and sizes (assumed; paper 001 gives neither): scripts are written in
seconds and sampled at ``rate_hz`` (default 20 Hz). Every still state,
including the lifted ones, is held 0.4-0.9 s, tips run at 60-120 deg/s,
rolling at 3-6 mm/s (:mod:`taxelkit.motion._script` lists every range), so at
20 Hz each contact state lasts at least 8 frames (the recogniser needs k = 3);
below about 8 Hz short states can fall under k frames. Each size of the solid
is scaled by its own factor drawn uniformly from ``1 +- size_jitter``; the
indentation by one factor from ``1 +- depth_jitter``.

Staying on the array: every contact point must stay :data:`EDGE_MARGIN_MM`
inside the array edge, points and lines of round bodies also their patch
half-width ``sqrt(2 rho d)``. A script that does not fit is retried with the
same random choices: the yaw in 22.5 deg steps; then without tipping a
polyhedron over onto a new face and with round bodies placed on their side
instead of laid down from a face (the roll that identifies them is kept
whole); then with rolls shortened x 0.8 per attempt. A 28.2 mm array is small
next to a 16 mm cylinder laid down from its end (26 mm from the far rim to
the line's end), so large round bodies start on their side more often than
the drawn 40-60 %.
Rocking back over the edge just tipped over is never scripted: two
consecutive edge contacts of a polyhedron are always two different edges.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError, check_in_range, check_positive
from taxelkit.motion._script import Builder, Draws, rest_pose, roll_line
from taxelkit.motion.array_placement import (
    EDGE_MARGIN_MM,
    contact_bounds,
    contact_xy,
    fit_on_array,
    yawed,
)
from taxelkit.motion.rolling import (
    DEFAULT_DEPTH_MM,
    DEFAULT_RATE_HZ,
    E_Z,
    Scenario,
)
from taxelkit.motion.scenario_scripts import SCRIPTS, Limits, limits_for_attempt, script_sliding
from taxelkit.sensors.noise import RngLike
from taxelkit.sensors.presets import BONNEVILLE_16X16, Sensor
from taxelkit.world.pose import matrix_from_axis_angle
from taxelkit.world.solids import SOLID_NAMES, AnalyticSolid, make_solid, solid_size_names
from taxelkit.world.solids_round import Cylinder, Sphere, TruncatedCone

__all__ = [
    "EDGE_MARGIN_MM",
    "FIG3_RATE_HZ",
    "FIG3_YAW_RAD",
    "SCENARIO_NAMES",
    "SLIDING_OBJECTS",
    "SPHERE_MAX_CONTACT_RADIUS_MM",
    "cylinder_fig3_scenario",
    "make_scenario",
]

#: Registry of random scripts: one per solid of paper 001, plus ``"sliding"``.
SCENARIO_NAMES: tuple[str, ...] = (*SOLID_NAMES, "sliding")
#: Largest geometric contact radius of a sphere, sqrt(2 R d), mm: about one
#: Bonneville pitch (1.76 mm), so a ball reads as a point contact. A ball pressed
#: deeper makes a disc as large as the smallest flat face (the truncated cone's
#: top), which a binary image cannot tell from an area contact.
SPHERE_MAX_CONTACT_RADIUS_MM = 2.0

#: Solids the sliding script may drag or spin on a flat face.
SLIDING_OBJECTS: tuple[str, ...] = ("cube", "tetrahedron", "cylinder", "cone", "truncated-cone")

#: Frame rate of Fig. 3 of paper 001: one image per second (Section 4).
FIG3_RATE_HZ = 1.0

#: Fig. 3's cylinder is laid down along the array's diagonal (the longest
#: room on the square array; assumed, the paper shows no coordinates), rad.
FIG3_YAW_RAD = math.pi / 4.0

# Fitting on the array: rolls shrink per attempt (scenario_scripts.SHRINK), yaw tried in
# pi / _YAW_TRIES steps.
_ATTEMPTS = 10
_YAW_TRIES = 8
_N_DRAWS = 256
# A jittered truncated cone keeps its top radius at most this fraction of its bottom
# one (half-angle >= 6 deg), so that it rolls in an arc (radius <= 45 mm at the far
# rim) visibly tighter than a cylinder's straight roll.
_TOP_OVER_BOTTOM_MAX = 0.65
# A frustum whose top radius is a small fraction q of its bottom is nearly a
# cone: its virtual apex lies 2q / (1 - q) half-lengths beyond the line's end.
# q >= 0.35 keeps that at least 1.08 half-lengths (pivot ratio >= 2.08).
_TOP_OVER_BOTTOM_MIN = 0.35


# --- sizes and placement on the array (helpers in taxelkit.motion.array_placement) --------------


def _random_solid(name: str, gen: np.random.Generator, jitter: float) -> AnalyticSolid:
    defaults = make_solid(name)
    sizes = {
        f: float(getattr(defaults, f)) * gen.uniform(1.0 - jitter, 1.0 + jitter)
        for f in solid_size_names(name)
    }
    if name == "truncated-cone":
        bottom = sizes["bottom_radius_mm"]
        top = min(sizes["top_radius_mm"], _TOP_OVER_BOTTOM_MAX * bottom)
        sizes["top_radius_mm"] = max(top, _TOP_OVER_BOTTOM_MIN * bottom)
    return make_solid(name, **sizes)


def _draw_body(
    name: str, gen: np.random.Generator, size_jitter: float, depth_mm: float, depth_jitter: float
) -> tuple[str, AnalyticSolid, float, bool]:
    """The object (drawn for the sliding script), its sizes, its press depth, mm, and the flip.

    ``flip``: a slid truncated cone stands on its top face (drawn only then).
    """
    slides = name == "sliding"
    object_name = SLIDING_OBJECTS[int(gen.integers(len(SLIDING_OBJECTS)))] if slides else name
    solid = _random_solid(object_name, gen, size_jitter)
    depth = depth_mm * gen.uniform(1.0 - depth_jitter, 1.0 + depth_jitter)
    if isinstance(solid, Sphere):  # a rolling ball is pressed lightly: a point contact
        depth = min(depth, SPHERE_MAX_CONTACT_RADIUS_MM**2 / (2.0 * solid.radius_mm))
    flip = slides and isinstance(solid, TruncatedCone) and bool(gen.integers(2))
    return object_name, solid, depth, flip


def _scenario_from(
    name: str,
    b: Builder,
    rotations: NDArray[np.float64],
    centroids_mm: NDArray[np.float64],
    indent_mm: NDArray[np.float64],
    shift_mm: NDArray[np.float64],
    rate_hz: float,
    *,
    slides: bool,
) -> Scenario:
    """The scenario of a finished script, placed on the array by ``shift_mm``.

    ``rotations`` and ``centroids_mm`` are the builder's poses after any yaw,
    ``indent_mm`` its indentation; phases come from the builder, times from
    ``rate_hz``.
    """
    return Scenario(
        name=name,
        object_name=b.solid.name,
        solid=b.solid,
        rotations=rotations,
        positions_mm=centroids_mm[:, :2] + shift_mm,
        rest_height_mm=centroids_mm[:, 2],
        indent_mm=indent_mm,
        t_s=np.arange(indent_mm.size) / rate_hz,
        phase=b.phases,
        slides=slides,
    )


def _assemble(
    name: str,
    solid: AnalyticSolid,
    script: Callable[[Builder, Draws, Limits], None],
    *,
    draws: NDArray[np.float64],
    yaw: float,
    shift_fraction: NDArray[np.float64],
    rate_hz: float,
    depth_mm: float,
    sensor: Sensor,
    slides: bool,
    rotation0: NDArray[np.float64],
) -> Scenario:
    half = 0.5 * np.array([sensor.array.width_mm, sensor.array.height_mm])
    for attempt in range(_ATTEMPTS):
        b = Builder(solid, rest_pose(solid, rotation0), rate_hz=rate_hz, depth_mm=depth_mm)
        script(b, Draws(draws), limits_for_attempt(attempt))
        rots0, cents0, indent = b.arrays()
        xy, margin = contact_xy(solid, rots0, cents0, indent)
        fit = fit_on_array(xy, margin, half, shift_fraction, yaw=yaw, tries=_YAW_TRIES)
        if fit is not None:
            rots, cents = yawed(rots0, cents0, fit[0])
            return _scenario_from(name, b, rots, cents, indent, fit[1], rate_hz, slides=slides)
    raise InputError(
        f"cannot fit a {solid!r} script on the {sensor.name} array; reduce size_jitter"
    )


def make_scenario(
    name: str,
    *,
    rng: RngLike = None,
    size_jitter: float = 0.3,
    depth_mm: float = DEFAULT_DEPTH_MM,
    depth_jitter: float = 0.3,
    rate_hz: float = DEFAULT_RATE_HZ,
    sensor: Sensor = BONNEVILLE_16X16,
) -> Scenario:
    """A randomised motion script for one solid (or the sliding script), on the array.

    Parameters
    ----------
    name : str
        One of :data:`SCENARIO_NAMES`.
    rng : int, Generator or None
        Seed: the same seed gives an identical scenario.
    size_jitter : float
        Each size of the solid is its default times its own factor drawn
        uniformly from ``[1 - size_jitter, 1 + size_jitter]``, in [0, 0.5]
        (a truncated cone's top radius is capped at 0.65 x its bottom radius,
        so that it stays clearly conical).
    depth_mm : float
        Nominal indentation while in contact, mm (:data:`DEFAULT_DEPTH_MM`).
    depth_jitter : float
        The indentation is ``depth_mm`` times one factor from ``1 +-
        depth_jitter``, in [0, 0.9].
    rate_hz : float
        Frame rate the script is sampled at, Hz (:data:`DEFAULT_RATE_HZ`).
    sensor : Sensor
        The array the motion must stay on.

    Returns
    -------
    Scenario
        Starting and ending lifted off the sensor; the solid's yaw and position
        on the array random.

    Raises
    ------
    InputError
        For an unknown name (listing the known ones), parameters out of range,
        or a script that cannot be fitted on the array.

    Examples
    --------
    >>> sc = make_scenario("cube", rng=3)
    >>> sc.object_name, sc.slides, sc.phase[0]
    ('cube', False, 'lifted')
    """
    if name not in SCENARIO_NAMES:
        raise InputError(f"unknown scenario {name!r}; known: {', '.join(SCENARIO_NAMES)}")
    jitter = check_in_range("size_jitter", size_jitter, 0.0, 0.5)
    djit = check_in_range("depth_jitter", depth_jitter, 0.0, 0.9)
    depth0 = check_positive("depth_mm", depth_mm)
    rate = check_positive("rate_hz", rate_hz)
    gen = np.random.default_rng(rng)
    slides = name == "sliding"
    object_name, solid, depth, flip = _draw_body(name, gen, jitter, depth0, djit)
    rotation0 = matrix_from_axis_angle([1.0, 0.0, 0.0], math.pi if flip else 0.0)
    return _assemble(
        name,
        solid,
        script_sliding if slides else SCRIPTS[object_name],
        draws=gen.random(_N_DRAWS),
        yaw=float(gen.uniform(0.0, 2.0 * math.pi)),
        shift_fraction=gen.random(2),
        rate_hz=rate,
        depth_mm=depth,
        sensor=sensor,
        slides=slides,
        rotation0=rotation0,
    )


def cylinder_fig3_scenario(
    *,
    depth_mm: float = DEFAULT_DEPTH_MM,
    rim_tilt_deg: float = 16.0,
    sensor: Sensor = BONNEVILLE_16X16,
) -> Scenario:
    """The cylinder of paper 001, Fig. 3 and 4, frame by frame at 1 Hz (deterministic).

    Images 1-23 (index ``t`` = image ``t + 1``): 1 nothing; 2 placing on the
    end face; 3-7 standing on the end (area); 8 tilting; 9-14 held on the rim
    (point); 15-17 laid on its side (line); 18-23 rolled 1 mm per frame, the
    line moving parallel to itself. Our copy of the figure lists images 1 and
    4-23; images 2-3 are filled as placing and standing (assumed).

    Parameters
    ----------
    depth_mm : float
        Indentation while in contact, mm.
    rim_tilt_deg : float
        Tilt of the axis while held on the rim, deg, in (0, 90) (assumed: any
        tilt above about 10 deg gives the 2-4 taxel image of a point at
        0.3 mm). The tilt runs at a constant rate over images 8-9, so image 8
        is taken half way there.
    sensor : Sensor
        The array the motion must stay on.

    Returns
    -------
    Scenario
        Named ``"cylinder-fig3"``, the default :class:`Cylinder`, 23 frames,
        laid down along the array's diagonal (:data:`FIG3_YAW_RAD`).

    Notes
    -----
    Nothing is arranged for image 8: what the sensor sees there comes from the
    end face lifting off about the rim. Pressed 0.3 mm and tilted 8 deg, the
    face still touches within about 1 mm of the rim, a circular segment whose
    chord is about 6 mm long. On the 16 x 16 array (``oversample=1``, no
    noise) that is a short bar of 5 taxels with elongation 1.6, between the
    disc of images 3-7 (28 taxels, 1.2) and the rim point of 9-14 (2 taxels),
    and far from the side's line of 15-23 (22-27 taxels, 3.7-5.1): the
    spurious image arises from the physics, but whether Level 2 calls it a
    line, as the paper's classifier did, depends on where it draws the
    boundaries.
    """
    depth = check_positive("depth_mm", depth_mm)
    tilt = math.radians(check_in_range("rim_tilt_deg", rim_tilt_deg, 1e-3, 89.999))
    solid = Cylinder()
    pose = rest_pose(solid, np.eye(3))
    b = Builder(solid, pose, rate_hz=FIG3_RATE_HZ, depth_mm=depth)
    b.lifted(1.0)
    b.place(1.0)
    b.hold(5.0, "face")
    u = np.array([1.0, 0.0, 0.0])
    pivot = pose.centroid_mm + solid.profile.rims[0][0] * E_Z + solid.radius_mm * u
    k = np.cross(E_Z, u)
    b.rotate(pivot, k, tilt, math.degrees(tilt) / 2.0, "tipping", "rim")
    b.hold(5.0, "rim")
    b.rotate(pivot, k, math.pi / 2.0 - tilt, math.degrees(math.pi / 2.0 - tilt), "tipping", "side")
    b.hold(2.0, "side")
    roll_line(b, solid.radius_mm, np.cross(E_Z, u), 6.0, 1.0, "rolling")
    rots, cents, indent = b.arrays()
    xy, margin = contact_xy(solid, rots, cents, indent)
    low, high = contact_bounds(xy, margin, FIG3_YAW_RAD)
    rots, cents = yawed(rots, cents, FIG3_YAW_RAD)
    shift = -0.5 * (low + high)
    if np.any(high - low > np.array([sensor.array.width_mm, sensor.array.height_mm])):
        raise InputError(f"the Fig. 3 motion does not fit on the {sensor.name} array")
    return _scenario_from(
        "cylinder-fig3", b, rots, cents, indent, shift, FIG3_RATE_HZ, slides=False
    )
