"""Bars of the ``multi-object`` experiment: outcome per object and track purity."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from taxelkit.plotting._axes import axes_pair

__all__ = ["plot_multi_object"]

#: Outcomes in drawing order, with their colours.
_OUTCOMES = (
    ("identified", "C2"),
    ("undecided", "C7"),
    ("unknown", "C1"),
    ("wrong", "C3"),
    ("missed", "k"),
)


def plot_multi_object(result: Any, ax: Any = None) -> Figure:
    """Left: the share of each outcome per engine, imperfection and object count
    (stacked bars). Right: the distribution of track purity (fraction of a track's
    frames owned by one object), per object count, as the sensor gives the frames.

    Parameters
    ----------
    result : MultiObjectResult
    ax : pair of Axes, optional
        Where to draw (a new figure by default).

    Returns
    -------
    Figure
    """
    doc = result.to_json()
    fig, axes = axes_pair(ax, (13.0, 3.8))
    left, right = axes
    summaries = doc["summaries"]
    labels = [
        f"{s['engine']}\n{s.get('imperfection', 'none')}\n{s['n_objects']} objects"
        for s in summaries
    ]
    x = np.arange(len(summaries))
    bottom = np.zeros(len(summaries))
    for name, colour in _OUTCOMES:
        share = np.array([s[name] / max(s["objects"], 1) for s in summaries])
        left.bar(x, share, bottom=bottom, color=colour, label=name, width=0.6)
        bottom += share
    left.axhline(0.95, color="k", lw=0.8, ls="--")
    left.set_xticks(x, labels, fontsize=7)
    left.set_ylabel("share of objects")
    left.set_ylim(0.0, 1.0)
    left.legend(fontsize=7, loc="lower left")
    left.set_title("outcome per object (dashed: 95 %)")
    bins = np.linspace(0.0, 1.0, 11)
    for n in sorted({s["n_objects"] for s in summaries}):
        pur = [
            p
            for sc in doc["scenes"]
            if sc["n_objects"] == n and sc.get("imperfection", "none") == "none"
            for p in sc["purities"]
        ]
        if pur:
            right.hist(pur, bins=bins, alpha=0.6, label=f"{n} objects ({len(pur)} tracks)")
    right.set_yscale("log")
    right.set_xlabel("track purity")
    right.set_ylabel("tracks")
    right.legend(fontsize=7, loc="upper left")
    right.set_title("track purity (imperfection none)")
    fig.tight_layout()
    return fig
