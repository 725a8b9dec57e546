"""One entry point for every motion engine: :func:`scenario_from_engine`."""

from __future__ import annotations

import importlib.util
from collections.abc import Sequence
from typing import Any

import numpy as np

from taxelkit.errors import InputError
from taxelkit.motion.rolling import DEFAULT_DEPTH_MM, DEFAULT_RATE_HZ, Scenario
from taxelkit.sensors.noise import RngLike
from taxelkit.sensors.presets import BONNEVILLE_16X16, Sensor

__all__ = [
    "ENGINE_NAMES",
    "MUJOCO_INSTALL_HINT",
    "engines_to_run",
    "scenario_from_engine",
    "scenarios_from_engine",
]

#: Registered engines: the closed-form scripts and MuJoCo physics (optional extra).
ENGINE_NAMES: tuple[str, ...] = ("kinematic", "mujoco")

#: How to install the optional physics engine (quoted in error messages).
MUJOCO_INSTALL_HINT = 'pip install "taxelkit[mujoco]"'


def engines_to_run(engines: Sequence[str] | None) -> tuple[list[str], dict[str, str]]:
    """The engines asked for that can run here, and those skipped with the reason.

    Parameters
    ----------
    engines : sequence of str, optional
        Names from :data:`ENGINE_NAMES` (default: all of them).

    Returns
    -------
    chosen : list of str
        In the order asked.
    skipped : dict of str to str
        MuJoCo, when it is not installed: ``'not installed (pip install ...)'``.

    Raises
    ------
    InputError
        For an unknown engine, or when none of them can run.
    """
    wanted = list(ENGINE_NAMES) if engines is None else [str(e) for e in engines]
    chosen, skipped = [], {}
    for e in wanted:
        if e not in ENGINE_NAMES:
            raise InputError(f"unknown engine {e!r}; known: {', '.join(ENGINE_NAMES)}")
        if e == "mujoco" and importlib.util.find_spec("mujoco") is None:
            skipped[e] = f"not installed ({MUJOCO_INSTALL_HINT})"
            continue
        chosen.append(e)
    if not chosen:
        raise InputError("no engine available")
    return chosen, skipped


def scenario_from_engine(
    engine: str,
    name: str,
    *,
    rng: RngLike = None,
    rate_hz: float = DEFAULT_RATE_HZ,
    sensor: Sensor = BONNEVILLE_16X16,
    size_jitter: float = 0.3,
    depth_mm: float = DEFAULT_DEPTH_MM,
    depth_jitter: float = 0.3,
    lift_gap_s: float = 0.0,
) -> Scenario:
    """A randomised scenario (poses plus ground truth) from the named engine.

    Parameters
    ----------
    engine : str
        One of :data:`ENGINE_NAMES`.
    name : str
        One of :data:`~taxelkit.motion.scenarios.SCENARIO_NAMES` (the six
        solids of paper 001 and ``"sliding"``).
    rng : int, Generator or None
        Seed: the same seed gives an identical scenario.
    rate_hz : float
        Frame rate, Hz (the MuJoCo engine: 1 to 1000, the same motion at
        every rate).
    sensor : Sensor
        The array the motion must stay on.
    size_jitter : float
        Each size of the solid is its default times a factor from ``1 +-
        size_jitter``.
    depth_mm, depth_jitter : float
        Press depth while in contact, mm, times a factor from ``1 +- depth_jitter``.
    lift_gap_s : float
        If > 0, lift the body clear of the plate once mid-script for about
        this long, s (MuJoCo only).

    Returns
    -------
    Scenario
        Feed it to :func:`~taxelkit.motion.rolling.frames_from_scenario`.

    Raises
    ------
    InputError
        Unknown engine; the MuJoCo engine without MuJoCo installed (the
        message says ``pip install "taxelkit[mujoco]"``); ``lift_gap_s`` with
        the kinematic engine; and the engine's own errors.

    Examples
    --------
    >>> sc = scenario_from_engine("kinematic", "cube", rng=3)
    >>> sc.object_name, sc.phase[0], sc.phase[-1]
    ('cube', 'lifted', 'lifted')
    """
    options: dict[str, Any] = {
        "rng": rng,
        "rate_hz": rate_hz,
        "sensor": sensor,
        "size_jitter": size_jitter,
        "depth_mm": depth_mm,
        "depth_jitter": depth_jitter,
        "lift_gap_s": lift_gap_s,
    }
    if engine == "kinematic":
        from taxelkit.motion.engines.kinematic import kinematic_scenario

        return kinematic_scenario(name, **options)
    if engine == "mujoco":
        from taxelkit.motion.engines.mujoco_scenes import mujoco_scene

        return mujoco_scene(name, **options).scenario
    raise InputError(f"unknown engine {engine!r}; known: {', '.join(ENGINE_NAMES)}")


def scenarios_from_engine(
    engine: str,
    name: str,
    *,
    rates_hz: Sequence[float],
    rng: RngLike = None,
    sensor: Sensor = BONNEVILLE_16X16,
) -> list[Scenario]:
    """The same motion at several frame rates (one simulation for MuJoCo).

    Parameters
    ----------
    engine, name : str
        As for :func:`scenario_from_engine`.
    rates_hz : sequence of float
        Frame rates, Hz.
    rng : int, Generator or None
        Seed of the motion: one seed is drawn from it and used at every rate.
    sensor : Sensor

    Returns
    -------
    list of Scenario
        One per rate, in order; each equals ``scenario_from_engine(engine,
        name, rng=seed, rate_hz=rate)``.
    """
    seed = int(np.random.default_rng(rng).integers(2**63 - 1))
    if engine == "mujoco":
        from taxelkit.motion.engines.mujoco_scenes import mujoco_scenes

        scenes = mujoco_scenes(name, rates_hz=rates_hz, rng=seed, sensor=sensor)
        return [s.scenario for s in scenes]
    return [
        scenario_from_engine(engine, name, rng=seed, rate_hz=r, sensor=sensor) for r in rates_hz
    ]
