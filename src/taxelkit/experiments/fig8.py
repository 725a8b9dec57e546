"""Experiment ``fig8``: tracing the five 200 um specimens (paper 000, Fig. 8)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.experiments.paper000_common import SHAPE_DIAMETER_MM, SHAPE_STEP_UM, trace_shape
from taxelkit.world.relief import SHAPE_NAMES, relief_shape

__all__ = ["Fig8Result", "run_fig8"]


@dataclass(frozen=True, eq=False)
class Fig8Result:
    """Traced contours against the true ones.

    Attributes
    ----------
    names : tuple of str
    outlines_mm : list of (V, 2) arrays
        True contours.
    points_mm : list of (K + 1, 2) arrays
        Traced array-centre positions.
    error_mean_mm, error_max_mm : list of float
        Distance of the traced points from the true contour.
    closed : list of bool
    sections : list of int
    """

    names: tuple[str, ...]
    outlines_mm: list[NDArray[np.float64]]
    points_mm: list[NDArray[np.float64]]
    error_mean_mm: list[float]
    error_max_mm: list[float]
    closed: list[bool]
    sections: list[int]

    def to_json(self) -> dict[str, Any]:
        """``tracing_error_mm``: mean, max and closure per shape."""
        return {
            "experiment": "fig8",
            "step_height_um": SHAPE_STEP_UM,
            "diameter_mm": SHAPE_DIAMETER_MM,
            "tracing_error_mm": {
                n: {"mean": m, "max": x, "closed": c, "sections": k}
                for n, m, x, c, k in zip(
                    self.names,
                    self.error_mean_mm,
                    self.error_max_mm,
                    self.closed,
                    self.sections,
                    strict=True,
                )
            },
            "target": {"mean_mm_at_most": 1.5, "closed": True},
        }


def run_fig8(*, seed: int = 0, progress: Callable[[int, int], None] | None = None) -> Fig8Result:
    """Trace each specimen from its centre outwards and measure the error.

    Parameters
    ----------
    seed : int
        Sensor-noise seed.
    progress : callable, optional
        ``progress(done, total)``.
    """
    outlines, points, mean, worst, closed, sections = [], [], [], [], [], []
    for k, name in enumerate(SHAPE_NAMES):
        relief = relief_shape(name, diameter_mm=SHAPE_DIAMETER_MM, step_height_um=SHAPE_STEP_UM)
        tr = trace_shape(name, seed=seed * 100 + k)
        d = relief.distance_to_edge_mm(tr.points_mm)  # evaluation only: the tracer never saw it
        outlines.append(np.asarray(relief.outline_mm()))
        points.append(tr.points_mm)
        mean.append(float(d.mean()))
        worst.append(float(d.max()))
        closed.append(tr.closed)
        sections.append(tr.n_sections)
        if progress is not None:
            progress(k + 1, len(SHAPE_NAMES))
    return Fig8Result(tuple(SHAPE_NAMES), outlines, points, mean, worst, closed, sections)
