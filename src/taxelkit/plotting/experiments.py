"""Which figure each registered experiment draws."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from matplotlib.figure import Figure

__all__ = ["plot_experiment"]


def _plotters() -> dict[str, Callable[[Any], Figure]]:
    from taxelkit.plotting.capacity import plot_capacity
    from taxelkit.plotting.multi_object import plot_multi_object
    from taxelkit.plotting.new_objects import plot_new_objects
    from taxelkit.plotting.paper000 import plot_fig7, plot_fig8, plot_fig9, plot_recall_vs_s
    from taxelkit.plotting.paper001 import plot_cylinder, plot_smart_sensor, plot_tacteme_table
    from taxelkit.plotting.robustness import plot_robustness
    from taxelkit.plotting.slip import plot_slip
    from taxelkit.plotting.trace_robustness import plot_trace_robustness

    return {
        "capacity": plot_capacity,
        "contact-classes": _plot_contact_classes,
        "cylinder": plot_cylinder,
        "smart-sensor": plot_smart_sensor,
        "tacteme-table": plot_tacteme_table,
        "fig7": plot_fig7,
        "fig8": plot_fig8,
        "fig9": plot_fig9,
        "fig9-readings": _plot_fig9_readings,
        "open-set": _plot_open_set,
        "multi-object": plot_multi_object,
        "new-objects": plot_new_objects,
        "new-objects-heldout": plot_new_objects,
        "recall-vs-s": plot_recall_vs_s,
        "robustness": plot_robustness,
        "robustness-heldout": plot_robustness,
        "slip": plot_slip,
        "slip-heldout": plot_slip,
        "trace-robustness": plot_trace_robustness,
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


def _plot_open_set(result: Any) -> Figure:
    """Reliability diagram, out-of-set answers per kind, in-set recognition against s."""
    import matplotlib.pyplot as plt

    doc = result.to_json()
    fig, (a, b, c) = plt.subplots(1, 3, figsize=(15, 4.4))
    bins = [x for x in doc["reliability"]["bins"] if x["n"]]
    a.plot([0, 1], [0, 1], "k:", lw=0.8)
    a.bar([x["low"] for x in bins], [x["accuracy"] for x in bins], width=0.1, align="edge",
          alpha=0.6, edgecolor="C0", label="accuracy")  # fmt: skip
    a.plot([x["confidence"] for x in bins], [x["accuracy"] for x in bins], "o", color="C3",
           label="mean confidence")  # fmt: skip
    for x in bins:
        a.text(x["low"] + 0.05, 0.02, str(x["n"]), ha="center", fontsize=6)
    a.set_xlabel("top probability")
    a.set_ylabel("fraction right")
    a.set_title(f"reliability, every s (ECE {doc['reliability']['ece']:.3f})", fontsize=9)
    a.legend(fontsize=7, loc="upper left")
    kinds = doc["out_of_set"]["kinds"]
    per = doc["out_of_set"]["per_kind"]
    n_unknown = [per[k].get("unknown", 0) for k in kinds]
    n_total = [sum(per[k].values()) for k in kinds]
    b.barh(kinds, n_total, color="C3", alpha=0.4, label="named or undecided")
    b.barh(kinds, n_unknown, color="C2", label="unknown")
    b.set_title(f"out-of-set, full trace: {100 * doc['out_of_set']['unknown_rate']:.1f} % "
                "unknown", fontsize=9)  # fmt: skip
    b.legend(fontsize=7)
    b.tick_params(labelsize=7)
    c.plot(doc["s"], doc["in_set"]["recognised_per_s"], "-o", ms=3)
    c.axhline(0.95, color="k", lw=0.6, ls=":")
    c.set_ylim(-0.03, 1.03)
    c.set_xlabel("normalised arc length s (known after the fact)")
    c.set_ylabel("in-set traces named right (decided)")
    c.set_title(f"in-set: {100 * doc['in_set']['recognised']:.1f} % at s = 1, "
                f"{doc['in_set']['wrong_names']} wrong names", fontsize=9)  # fmt: skip
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
