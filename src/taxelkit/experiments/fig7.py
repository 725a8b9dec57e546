"""Experiment ``fig7``: tracing straight 50 um edges at 0..90 deg (paper 000, Fig. 7)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.motion.probe import SimulatedProbe
from taxelkit.tracing.edge_estimate import ESTIMATORS, EdgeDetectorConfig
from taxelkit.tracing.tracer import TracerConfig, trace_edge
from taxelkit.world.relief import EdgeRelief

__all__ = ["FIG7_SECTIONS", "FIG7_STEP_UM", "FIG7_THETAS_DEG", "Fig7Result", "run_fig7"]

#: Edge directions of paper 000, Sect. VI.2, deg.
FIG7_THETAS_DEG = (0.0, 15.0, 30.0, 45.0, 60.0, 75.0, 90.0)
#: Step height of the edge-direction experiment, um (paper 000, Sect. VI.2).
FIG7_STEP_UM = 50.0
#: Sections traced per edge (20 x 3 mm = 60 mm).
FIG7_SECTIONS = 20


@dataclass(frozen=True, eq=False)
class Fig7Result:
    """Traces of straight edges with both edge-direction estimators.

    Attributes
    ----------
    theta_deg : tuple of float
    points_mm : dict estimator -> list of (K + 1, 2) arrays
    abs_r : dict estimator -> list of float or None
        Straightness ``|r|`` (None where undefined: parallel to an axis).
    direction_error_deg : dict estimator -> list of float
        Mean angle between the estimated edge direction ``dv`` and the true edge.
    """

    theta_deg: tuple[float, ...]
    points_mm: dict[str, list[NDArray[np.float64]]]
    abs_r: dict[str, list[float | None]]
    direction_error_deg: dict[str, list[float]]

    def to_json(self) -> dict[str, Any]:
        """JSON figures: the improved estimator at the top level, the paper's Eq. 8 beside it."""
        return {
            "experiment": "fig7",
            "step_height_um": FIG7_STEP_UM,
            "sections": FIG7_SECTIONS,
            "estimator": "crossings",
            "theta_deg": list(self.theta_deg),
            "abs_r": self.abs_r["crossings"],
            "direction_error_deg": self.direction_error_deg["crossings"],
            "faithful_eq8": {
                "abs_r": self.abs_r["eq8"],
                "direction_error_deg": self.direction_error_deg["eq8"],
            },
            "paper": {"abs_r_range": [0.96, 0.99], "resolves_deg": 15},
        }


def _angle_error_deg(vectors: NDArray[np.float64], theta_deg: float) -> float:
    ang = np.rad2deg(np.arctan2(vectors[:, 1], vectors[:, 0]))
    return float(np.mean(np.abs((ang - theta_deg + 180.0) % 360.0 - 180.0)))


def run_fig7(*, seed: int = 0, progress: Callable[[int, int], None] | None = None) -> Fig7Result:
    """Trace a 50 um straight edge at each angle with the Eq. 8 and crossing-line estimators.

    Parameters
    ----------
    seed : int
        Sensor-noise seed (default sensor noise of the optical preset).
    progress : callable, optional
        ``progress(done, total)``.
    """
    points: dict[str, list[NDArray[np.float64]]] = {e: [] for e in ESTIMATORS}
    abs_r: dict[str, list[float | None]] = {e: [] for e in ESTIMATORS}
    err: dict[str, list[float]] = {e: [] for e in ESTIMATORS}
    total, done = len(FIG7_THETAS_DEG) * len(ESTIMATORS), 0
    for k, theta in enumerate(FIG7_THETAS_DEG):
        relief = EdgeRelief((0.0, 0.0), theta, step_height_um=FIG7_STEP_UM)
        for estimator in ESTIMATORS:
            cfg = TracerConfig(
                max_sections=FIG7_SECTIONS,
                detector=EdgeDetectorConfig(estimator=estimator),  # type: ignore[arg-type]
            )
            probe = SimulatedProbe(relief, rng=seed * 1000 + k)
            tr = trace_edge(probe, (0.0, 0.0), cfg)
            points[estimator].append(tr.points_mm)
            abs_r[estimator].append(tr.straightness())
            err[estimator].append(_angle_error_deg(tr.dv_mm, theta))
            done += 1
            if progress is not None:
                progress(done, total)
    return Fig7Result(FIG7_THETAS_DEG, points, abs_r, err)
