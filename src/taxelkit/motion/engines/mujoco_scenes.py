"""Physics-engine scenes: the six solids pushed, rolled, tipped and dragged on a plate (MuJoCo).

The optional extra ``taxelkit[mujoco]`` (developed against MuJoCo 4.0.0; any
``mujoco >= 3.2`` exposes what is used here). The engine gives the *pose*; the
skin model of :func:`~taxelkit.motion.rolling.frames_from_scenario` gives the
frame, exactly as for the kinematic scripts of
:mod:`~taxelkit.motion.scenarios`, and the result is the same
:class:`~taxelkit.motion.rolling.Scenario` record.

Scenes (what paper 001's recogniser must see; segments in
:mod:`~taxelkit.motion.engines._mj_hand`, timing ranges shared with the
kinematic scripts, :mod:`taxelkit.motion._script`):

=============== ==============================================================
sphere          placed, pushed in 2-3 straight runs, each braked to a stop,
                the next at +-90 deg (PC, PC moves, PC takes an orthogonal turn)
cylinder        on its side, or on an end tilted over its rim onto its side;
                pushed across its axis (rolls straight), maybe pushed back
cone            on its side, or on its base tilted over the rim onto its
                side; pushed across its axis: it rolls about its apex
truncated-cone  the same from either face or its side: it rolls in an arc
                about its virtual apex
cube,           on a face, tipped about 2-3 bottom edges in turn by a couple
tetrahedron     (tilt, hold on the edge, back onto the face or over onto the
                next), never the same edge twice in a row
sliding         a face-down cube, tetrahedron, cylinder, cone or truncated
                cone on a low-friction skin (``SLIDING_FRICTION`` in
                :mod:`~taxelkit.motion.engines._mjcf`): dragged, spun, or both
=============== ==============================================================

Drawn per scene from the seed, besides the choices of the script: the sizes
(as the kinematic scripts), the press depth, the friction and the density
(ranges in :mod:`~taxelkit.motion.engines._mjcf`), the yaw and the placement.

Every scene starts held lifted, is lowered onto the plate, and is lifted off
at the end. With ``lift_gap_s > 0`` the body is lifted clear once after its
first motion (about ``lift_gap_s`` without contact) and set down again.

Conventions: ``rotations`` body to sensor, MuJoCo's body frame being the
solid's own (centroid, axis along +z); ``positions_mm`` the centroid's xy;
``rest_height_mm = -solid.lowest_z_mm(R)``; ``indent_mm`` the drawn press
depth (``depth_mm (1 +- depth_jitter)``) times the press ramp while the body
touches the plate, minus the lowest point's clearance when it does not. The
physical gap of the lowest point above the plate is kept in
:attr:`MujocoScene.gap_mm` (a few micrometres of penetration at rest).

Placement: the plate is uniform, so a scene is simulated about the origin and
then turned about the vertical (in 22.5 deg steps) and shifted so that every
contact point stays :data:`~taxelkit.motion.array_placement.EDGE_MARGIN_MM` (plus the
patch half-width of a curved contact) inside the array; a scene that does not
fit is simulated again without tipping over or laying down, then with
pushes x 0.8 per attempt, and :class:`~taxelkit.errors.InputError` is raised
after :data:`ATTEMPTS`.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit import _fixed_order as fo
from taxelkit.errors import InputError, check_in_range, check_positive
from taxelkit.motion.array_placement import fit_on_array
from taxelkit.motion.engines import _mj_hand as mh
from taxelkit.motion.engines import _mj_scripts as ms_scripts
from taxelkit.motion.engines._mj_simulate import import_mujoco, simulate
from taxelkit.motion.engines._mjcf import PHYSICS_HZ
from taxelkit.motion.engines._sampling import (
    PHYSICS_SPREAD_MM,
    PHYSICS_TIE_MM,
    StepRecord,
    contact_footprint_mm,
    matrices_from_quats,
    phase_labels,
    sample_record,
)
from taxelkit.motion.rolling import DEFAULT_DEPTH_MM, DEFAULT_RATE_HZ, E_Z, Scenario
from taxelkit.motion.scenarios import SCENARIO_NAMES
from taxelkit.sensors.noise import RngLike
from taxelkit.sensors.presets import BONNEVILLE_16X16, Sensor
from taxelkit.world.pose import matrix_from_axis_angle

__all__ = ["ATTEMPTS", "MAX_LIFT_GAP_S", "MujocoScene", "mujoco_scene"]

#: Simulations tried before a scene that does not fit on the array is refused.
ATTEMPTS = 6
#: Longest mid-script lift-off, s (a recogniser's loss-of-contact window is
#: far shorter; longer gaps are two placements).
MAX_LIFT_GAP_S = 2.0
#: Steps between the poses checked for fitting on the array (10 ms at
#: 1 kHz: the fastest contact point moves 0.06 mm in that time, well inside
#: the 1 mm edge margin).
_FIT_STRIDE = 10
#: Yaw tried for fitting, in pi / _YAW_TRIES steps.
_YAW_TRIES = 8


@dataclass(frozen=True, eq=False)
class MujocoScene:
    """A MuJoCo scene sampled at a frame rate: the scenario plus engine diagnostics.

    Attributes
    ----------
    scenario : Scenario
        Poses and ground truth, ready for
        :func:`~taxelkit.motion.rolling.frames_from_scenario`.
    gap_mm : (T,) float, mm
        Height of the body's lowest point above the plate (negative: the
        contact's penetration into the rigid plate).
    slip_mm_s : (T,) float, mm/s
        Fastest horizontal speed of a material contact point (0 when lifted).
    contact : tuple of str, length T
        ``"none"`` when lifted, else the contact type with the tolerances of
        physics poses: :attr:`Scenario.contact` of ``scenario``, which carries
        them (:data:`~taxelkit.motion.engines._sampling.PHYSICS_TIE_MM`; the
        exact poses' 1e-6 mm would call a resting edge a point, a face a line).
    n_steps : int
        Physics steps simulated (:data:`~taxelkit.motion.engines._mjcf.TIMESTEP_S` each).
    attempts : int
        Simulations run to fit the scene on the array.
    friction : float
        Coulomb friction drawn for the scene.
    density_kg_m3 : float
        Density drawn for the solid, kg/m^3.
    mujoco_version : str
    wall_s : float
        Seconds spent simulating and sampling (a diagnostic; not compared
        by equality tests).
    """

    scenario: Scenario
    gap_mm: NDArray[np.float64]
    slip_mm_s: NDArray[np.float64]
    contact: tuple[str, ...]
    n_steps: int
    attempts: int
    friction: float
    density_kg_m3: float
    mujoco_version: str
    wall_s: float


def _fit(
    plan: ms_scripts.Plan, rec: StepRecord, sensor: Sensor
) -> tuple[float, NDArray[np.float64]] | None:
    """Extra yaw and xy shift that keep every contact on the array, or None."""
    idx = np.arange(0, rec.quats.shape[0], _FIT_STRIDE)
    idx = idx[rec.touching[idx]]
    rots = matrices_from_quats(rec.quats[idx])
    xy, margin = contact_footprint_mm(plan.solid, rots, rec.centroids_mm[idx, :2], plan.depth_mm)
    half = 0.5 * np.array([sensor.array.width_mm, sensor.array.height_mm])
    return fit_on_array(xy, margin, half, plan.shift_fraction, tries=_YAW_TRIES)


def mujoco_scene(
    name: str,
    *,
    rng: RngLike = None,
    rate_hz: float = DEFAULT_RATE_HZ,
    sensor: Sensor = BONNEVILLE_16X16,
    size_jitter: float = 0.3,
    depth_mm: float = DEFAULT_DEPTH_MM,
    depth_jitter: float = 0.3,
    lift_gap_s: float = 0.0,
) -> MujocoScene:
    """Simulate one randomised scene in MuJoCo and sample it at ``rate_hz``.

    Parameters
    ----------
    name : str
        One of :data:`~taxelkit.motion.scenarios.SCENARIO_NAMES` (six solids
        and ``"sliding"``).
    rng : int, Generator or None
        Seed of every random choice (sizes, depth, yaw, placement, pushes):
        the same seed gives an identical scene at every rate.
    rate_hz : float
        Frame rate, Hz, in [1, 1000]; frames at ``t = k / rate_hz``. The
        physics does not depend on it.
    sensor : Sensor
        The array the motion must stay on.
    size_jitter, depth_mm, depth_jitter : float
        As for :func:`~taxelkit.motion.scenarios.make_scenario`.
    lift_gap_s : float
        If > 0, the body is lifted clear of the plate once, after its first
        motion, for about this long (s, at most :data:`MAX_LIFT_GAP_S`).

    Returns
    -------
    MujocoScene

    Raises
    ------
    InputError
        Unknown name, parameters out of range, MuJoCo not installed (the
        message says ``pip install "taxelkit[mujoco]"``), or a scene that does
        not fit on the array after :data:`ATTEMPTS` simulations.
    """
    return mujoco_scenes(
        name,
        rates_hz=(rate_hz,),
        rng=rng,
        sensor=sensor,
        size_jitter=size_jitter,
        depth_mm=depth_mm,
        depth_jitter=depth_jitter,
        lift_gap_s=lift_gap_s,
    )[0]


def mujoco_scenes(
    name: str,
    *,
    rates_hz: Sequence[float],
    rng: RngLike = None,
    sensor: Sensor = BONNEVILLE_16X16,
    size_jitter: float = 0.3,
    depth_mm: float = DEFAULT_DEPTH_MM,
    depth_jitter: float = 0.3,
    lift_gap_s: float = 0.0,
) -> list[MujocoScene]:
    """One simulation of :func:`mujoco_scene`, sampled at several frame rates.

    The physics does not depend on the rate, so this equals calling
    :func:`mujoco_scene` once per rate with the same seed, for the cost of one
    simulation.

    Parameters
    ----------
    name : str
    rates_hz : sequence of float
        Frame rates, Hz, each in [1, 1000].
    rng, sensor, size_jitter, depth_mm, depth_jitter, lift_gap_s
        As for :func:`mujoco_scene`.

    Returns
    -------
    list of MujocoScene
        One per rate, in order.
    """
    if name not in SCENARIO_NAMES:
        raise InputError(f"unknown scenario {name!r}; known: {', '.join(SCENARIO_NAMES)}")
    rates = [check_in_range("rate_hz", r, 1.0, 1000.0) for r in rates_hz]
    jitter = check_in_range("size_jitter", size_jitter, 0.0, 0.5)
    djit = check_in_range("depth_jitter", depth_jitter, 0.0, 0.9)
    depth0 = check_positive("depth_mm", depth_mm)
    gap = check_in_range("lift_gap_s", lift_gap_s, 0.0, MAX_LIFT_GAP_S)
    mujoco = import_mujoco()
    t_start = time.perf_counter()
    plan = ms_scripts.draw_plan(name, np.random.default_rng(rng), jitter, depth0, djit)
    for attempt in range(ATTEMPTS):
        segments, rotation0 = ms_scripts.segments_for(plan, attempt, gap)
        rec = simulate(mujoco, sensor, plan, segments, rotation0)
        placed = _fit(plan, rec, sensor)
        if placed is not None:
            return [
                _sampled(name, plan, rec, placed, rate, attempt + 1, mujoco, t_start)
                for rate in rates
            ]
    raise InputError(
        f"cannot fit the {name} scene ({plan.solid!r}) on the {sensor.name} array; "
        "reduce size_jitter or try another seed"
    )


def _sampled(
    name: str,
    plan: ms_scripts.Plan,
    rec: StepRecord,
    placed: tuple[float, NDArray[np.float64]],
    rate: float,
    attempts: int,
    mujoco: Any,
    t_start: float,
) -> MujocoScene:
    turn, shift = placed
    rots, cents, t_s, nearest = sample_record(rec, PHYSICS_HZ, rate)
    z = matrix_from_axis_angle(E_Z, turn)
    rots = fo.matmul(z, rots)
    cents = fo.rotate_points(cents, z)
    rest = -plan.solid.lowest_z_mm(rots)
    gap_mm = cents[:, 2] - rest
    touching = rec.touching[nearest]
    indent = np.where(
        touching,
        plan.depth_mm * np.maximum(rec.press[nearest], mh.PRESS_MIN),
        -np.maximum(gap_mm, 0.0),
    )
    scenario = Scenario(
        name=name,
        object_name=plan.object_name,
        solid=plan.solid,
        rotations=rots,
        positions_mm=cents[:, :2] + shift,
        rest_height_mm=rest,
        indent_mm=indent,
        t_s=t_s,
        phase=phase_labels(plan.solid, rec, rots, nearest),
        slides=plan.slides,
        contact_tie_mm=PHYSICS_TIE_MM,
        contact_spread_mm=PHYSICS_SPREAD_MM,
    )
    return MujocoScene(
        scenario=scenario,
        gap_mm=gap_mm,
        slip_mm_s=rec.slip_mm_s[nearest],
        contact=scenario.contact,
        n_steps=int(rec.quats.shape[0]),
        attempts=attempts,
        friction=plan.friction,
        density_kg_m3=plan.density_kg_m3,
        mujoco_version=str(mujoco.__version__),
        wall_s=time.perf_counter() - t_start,
    )
