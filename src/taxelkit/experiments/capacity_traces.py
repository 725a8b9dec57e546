"""Trace units of the ``capacity`` experiment: one specimen in one pose, traced in a worker."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit.motion.probe import SimulatedProbe
from taxelkit.tracing.tracer import find_edge, trace_edge
from taxelkit.world.relief import relief_from_vertices

__all__ = ["DIAMETER_MM", "MAX_OFFSET_MM", "STEP_UM", "TraceUnit", "trace_unit"]

#: Largest translation of a query specimen, mm.
MAX_OFFSET_MM = 20.0
#: Circumscribed diameter of every specimen, mm (paper 000, Sect. VI.3).
DIAMETER_MM = 90.0
#: Step height of every specimen, um (paper 000, Sect. VI.3).
STEP_UM = 200.0


@dataclass(frozen=True)
class TraceUnit:
    """One trace to make: a specimen in a pose, with its own seed.

    Attributes
    ----------
    key : tuple of (str, int, int)
        ``(set, shape index, trial)``; trial -1 is the stored (canonical) trace.
    outline : (V, 2) float64, mm
        The specimen's outline in its pose (the world; the tracer never sees it).
    centre_mm : (2,) float
        Where the edge search starts.
    direction : (2,) float
        Direction of the edge search.
    entropy : int
        Seed of the sensor noise.
    """

    key: tuple[str, int, int]
    outline: NDArray[np.float64]
    centre_mm: tuple[float, float]
    direction: tuple[float, float]
    entropy: int


def trace_unit(unit: TraceUnit) -> tuple[NDArray[np.float64], bool]:
    """Trace one specimen (worker side): its moves ``(K, 2)`` in mm and whether it closed."""
    relief = relief_from_vertices(unit.outline, step_height_um=STEP_UM)
    probe = SimulatedProbe(relief, rng=np.random.default_rng(unit.entropy))
    start = find_edge(probe, unit.centre_mm, direction=unit.direction)
    tr = trace_edge(probe, start)
    return tr.moves_mm, bool(tr.closed)
