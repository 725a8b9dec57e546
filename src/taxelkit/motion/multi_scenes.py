"""Scenes with several of the six solids on one array at once.

The simplest honest composition: each object gets its own randomised motion
from either engine (:func:`~taxelkit.motion.engines.scenario_from_engine`, the
kinematic scripts or the MuJoCo scenes, each made for the 16 x 16 array), is
placed in its own *tile* of a wider array (``rows x n * cols`` of the same
pitch; the tiles side by side along x, no gap, so contacts near a tile's edge
come within a few taxels of the neighbour's), and starts after a random delay
(so that births and deaths of tracks do not coincide). The frame is the
largest of the objects' noise-free skin deflections at every taxel, with the
sensor's noise added once. The bodies do not interact: each moves as if alone
(a true multi-body physics scene is not attempted).

Ground truth for scoring only (:attr:`MultiFrames.owner`: which object
pressed each taxel hardest) never reaches a recogniser.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.frames import TactileFrames
from taxelkit.motion.engines.registry import scenario_from_engine
from taxelkit.motion.rolling import DEFAULT_RATE_HZ, Scenario
from taxelkit.sensors.array_geometry import TaxelArray
from taxelkit.sensors.noise import RngLike, apply_noise
from taxelkit.sensors.presets import BONNEVILLE_16X16, Sensor
from taxelkit.sensors.press import displacement_from_solid

__all__ = [
    "MAX_DELAY_S",
    "MultiFrames",
    "MultiScene",
    "frames_from_multi_scene",
    "multi_scene",
    "tiled_sensor",
]

#: Largest random delay of an object's start, s.
MAX_DELAY_S = 2.0


def tiled_sensor(sensor: Sensor, n_tiles: int) -> Sensor:
    """``sensor`` with ``n_tiles`` copies of its array side by side along x (columns).

    Parameters
    ----------
    sensor : Sensor
        A preset with a full (no active block) array.
    n_tiles : int
        >= 1.

    Returns
    -------
    Sensor
        Same pitch, element, skin, noise and threshold; ``rows x n_tiles * cols``.
    """
    if int(n_tiles) < 1:
        raise InputError(f"n_tiles must be >= 1, got {n_tiles!r}")
    a = sensor.array
    array = TaxelArray(
        rows=a.rows,
        cols=a.cols * int(n_tiles),
        pitch_mm=a.pitch_mm,
        element_size_mm=a.element_size_mm,
    )
    return dataclasses.replace(sensor, name=f"{sensor.name}-x{int(n_tiles)}", array=array)


@dataclass(frozen=True, eq=False)
class MultiScene:
    """Several objects, each in its own tile, each with its own delay.

    Attributes
    ----------
    scenarios : tuple of Scenario
        One per object, positions already shifted into its tile.
    delays : tuple of int
        Frames before each object's first pose.
    sensor : Sensor
        The tiled array.
    t_s : (T,) float, s
    """

    scenarios: tuple[Scenario, ...]
    delays: tuple[int, ...]
    sensor: Sensor
    t_s: NDArray[np.float64]

    @property
    def names(self) -> tuple[str, ...]:
        """Object names, in tile order (ground truth)."""
        return tuple(s.object_name for s in self.scenarios)

    @property
    def n_frames(self) -> int:
        """Frames ``T``."""
        return int(self.t_s.size)


def multi_scene(
    names: Sequence[str],
    *,
    engine: str = "kinematic",
    rng: RngLike = None,
    rate_hz: float = DEFAULT_RATE_HZ,
    sensor: Sensor = BONNEVILLE_16X16,
    max_delay_s: float = MAX_DELAY_S,
) -> MultiScene:
    """A scene with the named objects moving on one tiled array at once.

    Parameters
    ----------
    names : sequence of str
        Scenario names (:data:`~taxelkit.motion.scenarios.SCENARIO_NAMES`),
        one per tile; repeats allowed.
    engine : str
        ``"kinematic"`` or ``"mujoco"``.
    rng : int, Generator or None
        Seed: the same seed gives the same scene.
    rate_hz : float
    sensor : Sensor
        The array of one tile.
    max_delay_s : float
        Each object starts after a delay drawn from ``[0, max_delay_s]``, s.

    Returns
    -------
    MultiScene
    """
    if not names:
        raise InputError("names must hold at least one object")
    gen = np.random.default_rng(rng)
    n = len(names)
    big = tiled_sensor(sensor, n)
    width_mm = sensor.array.cols * sensor.array.pitch_mm
    scenarios: list[Scenario] = []
    delays: list[int] = []
    for k, name in enumerate(names):
        seed = int(gen.integers(2**63 - 1))
        sc = scenario_from_engine(engine, name, rng=seed, rate_hz=rate_hz, sensor=sensor)
        shift = np.array([(k - 0.5 * (n - 1)) * width_mm, 0.0])
        scenarios.append(dataclasses.replace(sc, positions_mm=sc.positions_mm + shift))
        delays.append(round(float(gen.uniform(0.0, max_delay_s)) * rate_hz))
    total = max(d + s.n_frames for d, s in zip(delays, scenarios, strict=True))
    t_s = np.arange(total, dtype=np.float64) / float(rate_hz)
    return MultiScene(tuple(scenarios), tuple(delays), big, t_s)


@dataclass(frozen=True, eq=False)
class MultiFrames:
    """The frames of a :class:`MultiScene` and who made them.

    Attributes
    ----------
    recording : TactileFrames
        ``(T, rows, n * cols)`` deflection, mm: what a recogniser sees.
    owner : (T, rows, n * cols) int8
        Ground truth for scoring: the object (tile index) that deflects each
        taxel most, -1 where none deflects it.
    """

    recording: TactileFrames
    owner: NDArray[np.int8]


def frames_from_multi_scene(
    scene: MultiScene, *, rng: RngLike = None, add_noise: bool = True
) -> MultiFrames:
    """Compose the frames: the largest deflection of any object, then the sensor's noise.

    Parameters
    ----------
    scene : MultiScene
    rng : int, Generator or None
        Seed of the noise.
    add_noise : bool

    Returns
    -------
    MultiFrames
    """
    sensor = scene.sensor
    shape = (scene.n_frames, sensor.array.rows, sensor.array.cols)
    best = np.zeros(shape, np.float32)
    owner = np.full(shape, -1, np.int8)
    for k, (sc, d) in enumerate(zip(scene.scenarios, scene.delays, strict=True)):
        disp = displacement_from_solid(
            sensor, sc.solid, sc.rotations, sc.positions_mm, indent_mm=sc.indent_mm, add_noise=False
        )
        part = best[d : d + sc.n_frames]
        wins = disp > np.maximum(part, 0.0)
        owner[d : d + sc.n_frames][wins] = k
        np.maximum(part, disp, out=part)
    frames = apply_noise(best, sensor.noise, rng) if add_noise else best
    rec = TactileFrames(
        frames, t_s=scene.t_s, pitch_mm=sensor.array.pitch_mm, units="mm", sensor=sensor.name
    )
    return MultiFrames(rec, owner)
