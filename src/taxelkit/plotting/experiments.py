"""Which figure each registered experiment draws."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from matplotlib.figure import Figure

__all__ = ["plot_experiment"]


def _plotters() -> dict[str, Callable[[Any], Figure]]:
    from taxelkit.plotting.paper000 import plot_fig7, plot_fig8, plot_fig9, plot_recall_vs_s
    from taxelkit.plotting.paper001 import plot_cylinder, plot_smart_sensor, plot_tacteme_table
    from taxelkit.plotting.robustness import plot_robustness

    return {
        "contact-classes": _plot_contact_classes,
        "cylinder": plot_cylinder,
        "smart-sensor": plot_smart_sensor,
        "tacteme-table": plot_tacteme_table,
        "fig7": plot_fig7,
        "fig8": plot_fig8,
        "fig9": plot_fig9,
        "recall-vs-s": plot_recall_vs_s,
        "robustness": plot_robustness,
    }


def _plot_contact_classes(result: Any) -> Figure:
    import matplotlib.pyplot as plt

    from taxelkit.plotting.decision_regions import plot_decision_regions

    fig, (a, b) = plt.subplots(1, 2, figsize=(13, 5.2))
    s = result.samples
    doc = result.to_json()
    plot_decision_regions(
        samples=s.features,
        labels=s.labels,
        ax=a,
        title=f"hand-set weights: held-out accuracy {doc['hand_set']['accuracy']:.3f}",
    )
    plot_decision_regions(
        result.trained,
        samples=s.features,
        labels=s.labels,
        ax=b,
        title=f"trained by back-propagation: {doc['trained']['accuracy']:.3f}",
    )
    fig.tight_layout()
    return fig


def plot_experiment(name: str, result: Any) -> Figure:
    """The figure of experiment ``name`` for its ``result``."""
    return _plotters()[name](result)
