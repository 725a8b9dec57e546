"""Which figure each registered experiment draws."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from matplotlib.figure import Figure

__all__ = ["plot_experiment"]


def _plotters() -> dict[str, Callable[[Any], Figure]]:
    from taxelkit.plotting.paper000 import plot_fig7, plot_fig8, plot_fig9, plot_recall_vs_s
    from taxelkit.plotting.paper001 import plot_cylinder, plot_smart_sensor, plot_tacteme_table
    from taxelkit.plotting.robustness import plot_robustness
    from taxelkit.plotting.trace_robustness import plot_trace_robustness

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
        "trace-robustness": plot_trace_robustness,
    }


def _plot_contact_classes(result: Any) -> Figure:
    import matplotlib.pyplot as plt

    from taxelkit.plotting.decision_regions import plot_decision_regions
    from taxelkit.smart.contact_classes import HAND_SET

    fig, axes = plt.subplots(2, 2, figsize=(13, 10.4))
    doc = result.to_json()
    rolls = doc["rolls"]["scores"]
    pick = np.random.default_rng(0).permutation(result.roll_test.labels.size)[:3000]
    rf, rl = result.roll_test.features[pick], result.roll_test.labels[pick]
    panels = (
        (HAND_SET, result.features, result.labels,
         f"hand-set, pressed contacts: held-out accuracy {doc['hand_set']['accuracy']:.3f}"),
        (result.trained, result.features, result.labels,
         f"trained on pressed contacts: {doc['trained']['accuracy']:.3f}"),
        (HAND_SET, rf, rl,
         f"hand-set, rolls ({' + '.join(result.engines)}, all imperfections): "
         f"{rolls['hand_set']['all']['accuracy']:.3f}"),
        (result.roll_trained, rf, rl,
         f"trained on rolls of other seeds: {rolls['trained_on_rolls']['all']['accuracy']:.3f}"),
    )  # fmt: skip
    for ax, (net, x, y, title) in zip(axes.ravel(), panels, strict=True):
        plot_decision_regions(net, samples=x, labels=y, ax=ax, title=title)
    fig.tight_layout()
    return fig


def plot_experiment(name: str, result: Any) -> Figure:
    """The figure of experiment ``name`` for its ``result``."""
    return _plotters()[name](result)
