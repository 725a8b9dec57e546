"""Which figure each registered experiment draws."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from matplotlib.figure import Figure

__all__ = ["plot_experiment"]


def _plotters() -> dict[str, Callable[[Any], Figure]]:
    from taxelkit.plotting.paper000 import plot_fig7, plot_fig8, plot_fig9, plot_recall_vs_s
    from taxelkit.plotting.paper001 import plot_cylinder, plot_smart_sensor, plot_tacteme_table

    return {
        "cylinder": plot_cylinder,
        "smart-sensor": plot_smart_sensor,
        "tacteme-table": plot_tacteme_table,
        "fig7": plot_fig7,
        "fig8": plot_fig8,
        "fig9": plot_fig9,
        "recall-vs-s": plot_recall_vs_s,
    }


def plot_experiment(name: str, result: Any) -> Figure:
    """The figure of experiment ``name`` for its ``result``."""
    return _plotters()[name](result)
