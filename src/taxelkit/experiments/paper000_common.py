"""Shared pieces of the paper-000 experiments: tracing a specimen, the reference memory.

The world (a relief specimen) is created here and handed to a
:class:`~taxelkit.motion.probe.SimulatedProbe`; the tracer and the memory see
only what the probe returns.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike

from taxelkit.memory.associatron import AssociativeMemory
from taxelkit.memory.chain_code import DEFAULT_CHAIN_CODE, ChainCodeConfig
from taxelkit.memory.contour_recall import memorise_contours
from taxelkit.motion.probe import MotionNoise, SimulatedProbe
from taxelkit.tracing.tracer import Trace, TracerConfig, find_edge, trace_edge
from taxelkit.world.relief import SHAPE_NAMES, relief_shape

__all__ = [
    "FAITHFUL",
    "IMPROVED",
    "IMPROVED_CHAIN_CODE",
    "SHAPE_DIAMETER_MM",
    "SHAPE_STEP_UM",
    "RecallSetup",
    "reference_memory",
    "reference_traces",
    "trace_shape",
]

#: Circumscribed-circle diameter of the five specimens, mm (paper 000, Sect. VI.3).
SHAPE_DIAMETER_MM = 90.0
#: Step height of the five specimens, um (paper 000, Sect. VI.3).
SHAPE_STEP_UM = 200.0
#: Seed of the traces stored in the reference memory.
REFERENCE_SEED = 2006


@dataclass(frozen=True)
class RecallSetup:
    """A recall rule with its chain-code options.

    Attributes
    ----------
    label : str
        Name used in reports.
    rule : str
        Recall rule of :mod:`taxelkit.memory.recall_rules`.
    phases : int
        Sector phases (1 = the paper's binning).
    config : ChainCodeConfig
        Sectors ``m``, levels ``l`` and thresholds of the chain code.
    """

    label: str
    rule: str
    phases: int
    config: ChainCodeConfig = field(default=DEFAULT_CHAIN_CODE)


#: Chain code of the improved setup: 24 sectors of 15 deg and 8 levels
#: (thresholds (j - 1/2)/24: every multiple of 1/24 up to 1/3, so a half-traced
#: star's directions (about 0.1 each) already rise above a circle's 1/24, and a
#: triangle's 1/3 stays apart from a hexagon's 1/6).
IMPROVED_CHAIN_CODE = ChainCodeConfig(m=24, l=8)
#: The paper: Hebbian storage, one-step recall, Eq. 13 codes (m = 12, l = 4).
FAITHFUL = RecallSetup("faithful (hebbian)", "hebbian", 1)
#: taxelkit's improved recall: template matching on the known elements of a
#: 0 = unknown partial code, 24 x 8 chain code, two sector phases.
IMPROVED = RecallSetup(
    "improved (matched, 24 x 8 code, 2 phases)", "matched", 2, IMPROVED_CHAIN_CODE
)


def trace_shape(
    shape: str,
    *,
    rotation_deg: float = 0.0,
    offset_mm: ArrayLike = (0.0, 0.0),
    start_direction: ArrayLike = (1.0, 0.0),
    seed: int | np.random.Generator | None = 0,
    step_height_um: float = SHAPE_STEP_UM,
    diameter_mm: float = SHAPE_DIAMETER_MM,
    noise: MotionNoise | None = None,
    config: TracerConfig | None = None,
) -> Trace:
    """Trace one specimen: find its edge from its centre, then follow it.

    Parameters
    ----------
    shape : str
        One of :data:`~taxelkit.world.relief.SHAPE_NAMES`.
    rotation_deg, offset_mm
        Pose of the specimen.
    start_direction : (2,) float
        Direction of the search for the edge from the specimen's centre
        (sets the start point on the contour).
    seed : int, Generator or None
        Sensor and motion noise.
    step_height_um, diameter_mm : float
        Specimen size.
    noise : MotionNoise, optional
    config : TracerConfig, optional

    Returns
    -------
    Trace
    """
    off = np.asarray(offset_mm, dtype=np.float64)
    relief = relief_shape(
        shape,
        diameter_mm=diameter_mm,
        step_height_um=step_height_um,
        rotation_deg=rotation_deg,
        offset_mm=(float(off[0]), float(off[1])),
    )
    probe = SimulatedProbe(relief, noise=noise, rng=seed)
    start = find_edge(probe, off, direction=start_direction, config=config)
    return trace_edge(probe, start, config)


@lru_cache(maxsize=4)
def reference_traces(seed: int = REFERENCE_SEED) -> tuple[Trace, ...]:
    """Traces of the five specimens in their canonical pose, in :data:`SHAPE_NAMES` order."""
    return tuple(trace_shape(name, seed=seed + k) for k, name in enumerate(SHAPE_NAMES))


def reference_memory(setup: RecallSetup, seed: int = REFERENCE_SEED) -> AssociativeMemory:
    """Memory of the five traced specimens (paper 000: "first stored in the memory matrix")."""
    traces = reference_traces(seed)
    return memorise_contours(
        SHAPE_NAMES,
        [t.moves_mm for t in traces],
        rule=setup.rule,
        phases=setup.phases,
        config=setup.config,
    )
