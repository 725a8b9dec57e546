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
    """Left: the share of each outcome per engine, frame rate, imperfection and object
    count (stacked bars). Right: the distribution of track purity (fraction of a
    track's frames owned by one object), per object count, as the sensor gives the
    frames at the first rate.

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
    fig, axes = axes_pair(ax, (14.0, 4.0))
    left, right = axes
    summaries = doc["summaries"]
    # one group of bars per engine, rate and imperfection; one bar per object count
    keys = [(s["engine"], s.get("rate_hz", 20.0), s.get("imperfection", "none")) for s in summaries]
    groups = list(dict.fromkeys(keys))
    counts = sorted({s["n_objects"] for s in summaries})
    width = 0.8 / len(counts)
    x = np.array(
        [
            groups.index(k) + (counts.index(s["n_objects"]) - 0.5 * (len(counts) - 1)) * width
            for k, s in zip(keys, summaries, strict=True)
        ]
    )
    bottom = np.zeros(len(summaries))
    for name, colour in _OUTCOMES:
        share = np.array([s[name] / max(s["objects"], 1) for s in summaries])
        left.bar(x, share, bottom=bottom, color=colour, label=name, width=0.9 * width)
        bottom += share
    labels = [f"{e}\n{r:g}/s\n{f}" for e, r, f in groups]
    left.set_xticks(np.arange(len(groups)), labels, fontsize=6)
    left.axhline(0.95, color="k", lw=0.8, ls="--")
    left.set_ylabel("share of objects")
    left.set_ylim(0.0, 1.0)
    left.legend(fontsize=7, loc="lower left")
    left.set_title(
        "outcome per object, bars: " + ", ".join(f"{n} objects" for n in counts) + " (dashed: 95 %)"
    )
    bins = np.linspace(0.0, 1.0, 11)
    for n in sorted({s["n_objects"] for s in summaries}):
        pur = [
            p
            for sc in doc["scenes"]
            if sc["n_objects"] == n
            and sc.get("imperfection", "none") == "none"
            and sc.get("rate_hz", 20.0) == doc.get("rates_hz", [20.0])[0]
            for p in sc["purities"]
        ]
        if pur:
            right.hist(pur, bins=bins, alpha=0.6, label=f"{n} objects ({len(pur)} tracks)")
    right.set_yscale("log")
    right.set_xlabel("track purity")
    right.set_ylabel("tracks")
    right.legend(fontsize=7, loc="upper left")
    right.set_title("track purity (imperfection none, the first rate)")
    fig.tight_layout()
    return fig
