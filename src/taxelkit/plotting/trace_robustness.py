"""Bars of the ``trace-robustness`` experiment: error, closure and recognition per condition."""

from __future__ import annotations

from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

__all__ = ["plot_trace_robustness"]

#: Bar colours of the tracers.
_COLOURS = {"faithful": "C0", "robust": "C3"}


def plot_trace_robustness(result: Any) -> Figure:
    """Three panels, one row per condition and a bar per tracer.

    Left: mean distance of the traced points to the true outline (mm, log
    scale; a trace that found no edge is drawn at the right edge). Middle:
    fraction of loops closed. Right: fraction of the five stored shapes named
    right (empty for the re-entrant shapes, which are not stored).
    """
    doc = result.to_json()
    names = [c["name"] for c in doc["conditions"]]
    tracers = list(next(iter(doc["summary"].values())))
    y = np.arange(len(names))
    height = 0.8 / len(tracers)
    fig, axes = plt.subplots(1, 3, figsize=(13.5, 0.9 + 0.36 * len(names)), sharey=True)
    for k, tracer in enumerate(tracers):
        rows = [doc["summary"][n][tracer] for n in names]
        err = [r["error_mean_mm"] if r["error_mean_mm"] is not None else 1e3 for r in rows]
        closed = [r["closed"] / r["n"] for r in rows]
        named = [
            r["recognised"] / r["n_recognisable"] if r["n_recognisable"] else np.nan for r in rows
        ]
        pos = y - 0.4 + height * (k + 0.5)
        style = {"height": height, "color": _COLOURS.get(tracer, f"C{k}"), "label": tracer}
        axes[0].barh(pos, err, **style)
        axes[1].barh(pos, closed, **style)
        axes[2].barh(pos, named, **style)
    axes[0].set_xscale("log")
    axes[0].axvline(0.5, color="0.3", ls="--", lw=0.8)
    axes[0].set_xlabel("mean tracing error, mm (dashed: 0.5 mm)")
    axes[1].set_xlabel("loops closed")
    axes[2].set_xlabel("stored shapes named right")
    for ax in axes[1:]:
        ax.set_xlim(0, 1.05)
    axes[0].set_yticks(y, names, fontsize=8)
    axes[0].invert_yaxis()
    axes[0].legend(fontsize=8, loc="lower right")
    fig.suptitle(
        f"trace-robustness: {doc['n_trials_per_shape']} random pose(s) per shape and condition"
    )
    fig.tight_layout()
    return fig
