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

    return {
        "contact-classes": _plot_contact_classes,
        "cylinder": plot_cylinder,
        "smart-sensor": plot_smart_sensor,
        "tacteme-table": plot_tacteme_table,
        "fig7": plot_fig7,
        "fig8": plot_fig8,
        "fig9": plot_fig9,
        "fig9-readings": _plot_fig9_readings,
        "recall-vs-s": plot_recall_vs_s,
        "robustness": plot_robustness,
    }


def _plot_fig9_readings(result: Any) -> Figure:
    """The best readings of Fig. 9 (rows): the triangle's and the star's recall curves."""
    import matplotlib.pyplot as plt

    doc = result.to_json()
    rows = doc["readings"][:4] + [
        r for r in doc["readings"]
        if r["frequency"] == "relative" and r["thresholds"] == "rounding" and r["phases"] == 1
        and r["diagonal_kept"] and r["phi_m_threshold"] == 0.0
    ]  # fmt: skip
    s = doc["s"]
    fig, axes = plt.subplots(len(rows), 2, figsize=(10, 2.3 * len(rows)), sharex=True, sharey=True)
    for i, row in enumerate(rows):
        for j, query in enumerate(("triangle", "star")):
            ax = axes[i, j]
            for k, (stored, c) in enumerate(row["curves"][query].items()):
                ax.plot(s, c, "-" if stored == query else "--", color=f"C{k}", label=stored,
                        lw=1.6 if stored == query else 1)  # fmt: skip
            ax.axvline(doc["paper_recognised_from_s"][query], color="k", lw=0.6, ls=":")
            found = row["recognised_from_s"][query]
            ax.set_title(
                f"{query}: from {'never' if found is None else found} "
                f"({row['criteria_met']}/4 criteria)",
                fontsize=8,
            )
            ax.set_ylim(-1.05, 1.05)
        axes[i, 0].set_ylabel("c", fontsize=8)
        axes[i, 0].text(0.02, 0.04, row["label"], transform=axes[i, 0].transAxes, fontsize=6)
    axes[0, 0].legend(fontsize=6, loc="lower right")
    for ax in axes[-1]:
        ax.set_xlabel("normalised arc length s")
    fig.suptitle("Fig. 9 readings: the best four and the faithful default as printed (bottom)")
    fig.tight_layout()
    return fig


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
