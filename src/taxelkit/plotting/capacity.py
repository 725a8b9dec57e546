"""Figure of the ``capacity`` experiment: accuracy against stored shapes and s, every rule."""

from __future__ import annotations

from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

__all__ = ["plot_capacity"]


def _style(rule: dict[str, Any]) -> dict[str, Any]:
    """Solid lines for associative rules, dashed for template matching; the paper's rule thick."""
    return {
        "ls": "-" if rule["associative"] else "--",
        "lw": 2.4 if rule["faithful"] else 1.4,
        "marker": "o" if rule["code"] == "signature" else ".",
    }


def plot_capacity(result: Any) -> Figure:
    """Three panels: accuracy vs stored shapes at s = 0.6 and at s = 1, and vs s at 100 shapes.

    Every rule is drawn, the paper's Hebbian rule (thick) included; the
    acceptance target (90 % at 100 shapes, s = 0.6) is marked.
    """
    doc = result.to_json()
    sizes, s = doc["sizes"], doc["s"]
    fig, axes = plt.subplots(1, 3, figsize=(15, 5.6))
    panels = [(axes[0], 0.6), (axes[1], 1.0)]
    for k, (name, rule) in enumerate(doc["rules"].items()):
        acc = np.asarray(rule["accuracy"])  # (sizes, S)
        style = {**_style(rule), "color": f"C{k}", "label": f"{rule['label']} ({name})"}
        for ax, s_at in panels:
            if s_at in s:
                ax.plot(sizes, acc[:, s.index(s_at)], **style)
        target = doc["target"]["size"]
        if target in sizes:
            axes[2].plot(s, acc[sizes.index(target)], **style)
    for ax, s_at in panels:
        ax.set_xscale("log")
        ax.set_xticks(sizes, [str(n) for n in sizes])
        ax.set_xlabel("stored shapes")
        ax.set_title(f"{'whole' if s_at == 1.0 else 'partial'} traces, s = {s_at:g}", fontsize=10)
    axes[2].set_xlabel("traced fraction s (known after the fact)")
    axes[2].set_title(f"{doc['target']['size']} stored shapes", fontsize=10)
    t = doc["target"]
    axes[0].plot([t["size"]], [t["accuracy"]], "k*", ms=11, label="target (associative rule)")
    for ax in axes:
        ax.set_ylim(-0.02, 1.02)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("fraction named right (ties count wrong)")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=7, loc="lower center", ncol=3, frameon=False)
    fig.suptitle(
        f"capacity: {doc['n_shapes']} generated shapes, {doc['n_queries']} traced queries "
        "(solid: associative, dashed: template matching, o: order-aware signature)",
        fontsize=10,
    )
    fig.tight_layout(rect=(0, 0.16, 1, 1))
    return fig
