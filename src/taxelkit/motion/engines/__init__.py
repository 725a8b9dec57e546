"""Motion engines: closed-form kinematic scripts and MuJoCo physics, both giving poses.

An engine produces a :class:`~taxelkit.motion.rolling.Scenario` (poses per
frame plus ground truth); the skin model
(:func:`~taxelkit.motion.rolling.frames_from_scenario`) turns it into frames,
whatever the engine. MuJoCo is an optional extra (``pip install
"taxelkit[mujoco]"``): :mod:`taxelkit.motion.engines.mujoco_scenes` imports
it and is therefore not re-exported here.
"""

from taxelkit.motion.engines.kinematic import kinematic_scenario
from taxelkit.motion.engines.registry import (
    ENGINE_NAMES,
    MUJOCO_INSTALL_HINT,
    engines_to_run,
    scenario_from_engine,
    scenarios_from_engine,
)

__all__ = [
    "ENGINE_NAMES",
    "MUJOCO_INSTALL_HINT",
    "engines_to_run",
    "kinematic_scenario",
    "scenario_from_engine",
    "scenarios_from_engine",
]
