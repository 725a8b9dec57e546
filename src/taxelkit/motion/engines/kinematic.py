"""The kinematic engine: today's rolling-without-slip scripts behind the engine interface.

A thin adapter over :func:`~taxelkit.motion.scenarios.make_scenario`; poses are
computed in closed form (:mod:`taxelkit.motion.rolling`), so nothing here
simulates forces.
"""

from __future__ import annotations

from taxelkit.errors import InputError
from taxelkit.motion.rolling import DEFAULT_DEPTH_MM, DEFAULT_RATE_HZ, Scenario
from taxelkit.motion.scenarios import make_scenario
from taxelkit.sensors.noise import RngLike
from taxelkit.sensors.presets import BONNEVILLE_16X16, Sensor

__all__ = ["kinematic_scenario"]


def kinematic_scenario(
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
    """A kinematic script (:func:`~taxelkit.motion.scenarios.make_scenario`).

    Parameters
    ----------
    name : str
        One of :data:`~taxelkit.motion.scenarios.SCENARIO_NAMES`.
    rng, rate_hz, sensor, size_jitter, depth_mm, depth_jitter
        As for :func:`~taxelkit.motion.scenarios.make_scenario`.
    lift_gap_s : float
        Must be 0: the kinematic scripts have no mid-script lift-off.

    Returns
    -------
    Scenario

    Raises
    ------
    InputError
        For ``lift_gap_s != 0``, and as :func:`make_scenario`.
    """
    if lift_gap_s != 0.0:
        raise InputError(
            f"lift_gap_s={lift_gap_s!r} is not supported by the kinematic engine "
            "(use engine 'mujoco')"
        )
    return make_scenario(
        name,
        rng=rng,
        size_jitter=size_jitter,
        depth_mm=depth_mm,
        depth_jitter=depth_jitter,
        rate_hz=rate_hz,
        sensor=sensor,
    )
