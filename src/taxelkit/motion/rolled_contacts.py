"""Labelled frames of whole rolls, from either motion engine, through imperfect sensors.

Level 2 sees single images, but the images a recogniser meets come from
motion: faces landing, lines rolling, points tilting, seen through dead,
stuck and flickering taxels. This module runs the motion engines
(:mod:`taxelkit.motion.engines`), simulates the frames, applies a sensor
imperfection (:mod:`taxelkit.sensors.faults`) and labels each frame with the
contact type of its ground-truth phase:

============================= ===============================================
phase                         label
============================= ===============================================
``face``                      area
``edge``                      line
``vertex``, ``rim``, ``apex`` point
``side``, ``rolling``         point for a sphere, line for a round body
others                        none (placing, lifting, tipping, sliding, lifted:
                              the contact type is changing or not a rolling one)
============================= ===============================================

Rolls are kept whole (:class:`LabelledRoll`): a recogniser's image cleaning
works on sequences.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.frames import TactileFrames
from taxelkit.motion.engines import scenario_from_engine
from taxelkit.motion.rolling import Scenario, frames_from_scenario
from taxelkit.sensors.faults import fault_model
from taxelkit.sensors.noise import RngLike
from taxelkit.sensors.presets import BONNEVILLE_16X16, Sensor

__all__ = ["LabelledRoll", "labels_from_phases", "rolled_contacts"]

_STILL_LABEL = {"face": "area", "edge": "line", "vertex": "point", "rim": "point", "apex": "point"}


def labels_from_phases(scenario: Scenario) -> NDArray[np.str_]:
    """Contact type of each frame from its phase (see the module table); ``""`` unlabelled.

    Parameters
    ----------
    scenario : Scenario

    Returns
    -------
    (T,) str
    """
    round_line = "point" if scenario.object_name == "sphere" else "line"
    out = [
        _STILL_LABEL.get(p, round_line if p in ("side", "rolling") else "") for p in scenario.phase
    ]
    return np.asarray(out)


@dataclass(frozen=True, eq=False)
class LabelledRoll:
    """One roll as the sensor saw it, with the ground-truth contact type per frame.

    Attributes
    ----------
    recording : TactileFrames
        Analog frames (mm) after the imperfection.
    labels : (T,) str
        ``"point"``, ``"line"``, ``"area"`` or ``""`` (unlabelled).
    engine, object_name, fault : str
    threshold_mm : float
        The sensor's contact threshold.
    """

    recording: TactileFrames
    labels: NDArray[np.str_]
    engine: str
    object_name: str
    fault: str
    threshold_mm: float


def rolled_contacts(
    engines: Sequence[str],
    objects: Sequence[str],
    faults: Sequence[str],
    *,
    n_rolls: int,
    rate_hz: float = 20.0,
    sensor: Sensor = BONNEVILLE_16X16,
    rng: RngLike = None,
) -> list[LabelledRoll]:
    """Rolls of every object by every engine, each seen through every imperfection.

    Parameters
    ----------
    engines, objects, faults : sequence of str
        Engine names, solid names, and fault presets.
    n_rolls : int
        Rolls per engine and object.
    rate_hz : float
        Frame rate, Hz.
    sensor : Sensor
    rng : int, Generator or None
        Seed of the motions, noise and imperfections.

    Returns
    -------
    list of LabelledRoll
        ``len(engines) x len(objects) x n_rolls x len(faults)`` rolls.
    """
    if int(n_rolls) < 1:
        raise InputError(f"n_rolls must be >= 1, got {n_rolls!r}")
    gen = np.random.default_rng(rng)
    thr = float(sensor.contact_threshold_mm)
    out: list[LabelledRoll] = []
    for engine in engines:
        for name in objects:
            for _ in range(int(n_rolls)):
                sc = scenario_from_engine(engine, name, rng=gen, rate_hz=rate_hz, sensor=sensor)
                rec = frames_from_scenario(sensor, sc, rng=gen)
                labels = labels_from_phases(sc)
                for fault in faults:
                    seen = fault_model(fault).apply(rec, threshold=thr, rng=gen)
                    out.append(LabelledRoll(seen, labels, engine, name, fault, thr))
    return out
