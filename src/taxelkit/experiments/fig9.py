"""Experiment ``fig9``: correlation ``c`` against normalised arc length ``s`` (paper 000, Fig. 9).

The five specimens are traced and stored (the reference memory); each is then
traced again (new sensor noise, same specimen, as in the paper) and recalled
from the growing part of its trace, with the paper's rule and with the
improved one.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from taxelkit.experiments.paper000_common import (
    FAITHFUL,
    IMPROVED,
    RecallSetup,
    reference_memory,
    trace_shape,
)
from taxelkit.memory.contour_recall import RecallCurve, recall_curve
from taxelkit.world.relief import SHAPE_NAMES

__all__ = ["PAPER_RECOGNISED_FROM_S", "Fig9Result", "run_fig9"]

#: What the paper reports (Sect. VII.3): the triangle is top-ranked from s = 0.61;
#: star and circle are nearly equal until s = 0.66.
PAPER_RECOGNISED_FROM_S = {"triangle": 0.61, "star": 0.66}


@dataclass(frozen=True, eq=False)
class Fig9Result:
    """Recall curves of each traced shape, for each recall setup.

    Attributes
    ----------
    names : tuple of str
        The traced (query) shapes.
    setups : tuple of RecallSetup
    curves : dict label -> list of RecallCurve (one per query shape)
    """

    names: tuple[str, ...]
    setups: tuple[RecallSetup, ...]
    curves: dict[str, list[RecallCurve]]

    def recognised_from_s(self, setup: RecallSetup) -> dict[str, float | None]:
        """For each shape, the smallest ``s`` from which it stays top-ranked."""
        return {
            n: c.recognised_from_s(n)
            for n, c in zip(self.names, self.curves[setup.label], strict=True)
        }

    def ties_per_s(self, setup: RecallSetup) -> list[int]:
        """At each ``s``, how many of the traced shapes end in a tie at the top."""
        curves = self.curves[setup.label]
        return [sum(c.recognised[j] is None for c in curves) for j in range(len(curves[0].s))]

    def margins(self, setup: RecallSetup) -> dict[str, list[float | None]]:
        """Per traced shape, the winning margin (best ``c`` minus second best) at each ``s``."""
        return {
            n: [row["margin"] for row in c.to_json()]
            for n, c in zip(self.names, self.curves[setup.label], strict=True)
        }

    def summary(self, setup: RecallSetup) -> dict[str, Any]:
        """Verdict table of one setup: from which ``s``, margins and ties per ``s``."""
        return {
            "rule": setup.label,
            "recognised_from_s": self.recognised_from_s(setup),
            "s": [float(v) for v in self.curves[setup.label][0].s],
            "ties_per_s": self.ties_per_s(setup),
            "winning_margin": self.margins(setup),
            "final_verdicts": {
                n: c.verdicts[-1] for n, c in zip(self.names, self.curves[setup.label], strict=True)
            },
        }

    def to_json(self) -> dict[str, Any]:
        """``recognised_from_s`` of the improved rule on top; ties, margins, curves of both."""
        improved = self.summary(IMPROVED)
        return {
            "experiment": "fig9",
            **improved,
            "faithful": self.summary(FAITHFUL),
            "paper_recognised_from_s": PAPER_RECOGNISED_FROM_S,
            "curves": {
                setup.label: {
                    n: c.to_json()
                    for n, c in zip(self.names, self.curves[setup.label], strict=True)
                }
                for setup in self.setups
            },
        }


def run_fig9(*, seed: int = 0, progress: Callable[[int, int], None] | None = None) -> Fig9Result:
    """Trace each specimen again and recall it from part of the trace.

    Parameters
    ----------
    seed : int
        Seed of the query traces (the stored ones use their own fixed seed).
    progress : callable, optional
        ``progress(done, total)``.
    """
    setups = (FAITHFUL, IMPROVED)
    memories = {s.label: reference_memory(s) for s in setups}
    curves: dict[str, list[RecallCurve]] = {s.label: [] for s in setups}
    for k, name in enumerate(SHAPE_NAMES):
        tr = trace_shape(name, seed=seed * 100 + 50 + k)
        for s in setups:
            curves[s.label].append(recall_curve(tr.moves_mm, memories[s.label], phases=s.phases))
        if progress is not None:
            progress(k + 1, len(SHAPE_NAMES))
    return Fig9Result(tuple(SHAPE_NAMES), setups, curves)
