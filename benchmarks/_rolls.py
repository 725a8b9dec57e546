"""The rolls the benchmarks share: randomised rolls of the six objects on the Bonneville array.

Roll ``k`` is object ``k % 6`` of :data:`~taxelkit.smart.tacteme_table.OBJECTS`,
drawn with seed ``k`` at the array's maximum rate (240 frames/s), as binary
contact images ``(T, 16, 16)``: as the array gives them, or seen through every
sensor imperfection at once (``fault_model("all")``, seed ``k``).
"""

from __future__ import annotations

import numpy as np

from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import make_scenario
from taxelkit.sensors import BONNEVILLE_16X16
from taxelkit.sensors.faults import fault_model
from taxelkit.smart.tacteme_table import OBJECTS

RATE_HZ = BONNEVILLE_16X16.max_rate_hz


def roll_images(n: int, *, faults: bool) -> list[np.ndarray]:
    """Binary images of rolls ``0 .. n - 1``, each ``(T_k, 16, 16)``.

    ``faults``: seen through every imperfection (``fault_model("all")``).
    """
    sensor, thr = BONNEVILLE_16X16, BONNEVILLE_16X16.contact_threshold_mm
    out = []
    for k in range(n):
        rng = np.random.default_rng(k)
        sc = make_scenario(OBJECTS[k % len(OBJECTS)], rng=rng, rate_hz=RATE_HZ)
        rec = frames_from_scenario(sensor, sc, rng=rng)
        if faults:
            out.append(fault_model("all").apply(rec, threshold=thr, rng=k).frames > thr)
        else:
            out.append(sensor.contact_from_displacement(rec.frames))
    return out
