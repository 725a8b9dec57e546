"""Figures of the ``slip`` experiment: detection latency and recognition under slip."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib.figure import Figure

from taxelkit.plotting._axes import axes_pair

__all__ = ["plot_slip"]


def plot_slip(result: Any, ax: Any = None) -> Figure:
    """Left: the share of slip phases found within a latency, per frame rate and
    imperfection (dashed: through every imperfection at once).
    Right: recognition of the partial-slip rolls with and without slip detection.

    Parameters
    ----------
    result : SlipResult
    ax : pair of Axes, optional
        Where to draw (a new figure by default).

    Returns
    -------
    Figure
    """
    doc = result.to_json()
    fig, axes = axes_pair(ax, (11.0, 3.6))
    left, right = axes
    grid = np.linspace(0.0, 1.0, 101)
    detectable = set(doc["detectable_kinds"])
    styles = ("-", "--", ":", "-.")
    for i, rate in enumerate(doc["rates_hz"]):
        for name, style in zip(doc.get("imperfections", ["none"]), styles, strict=False):
            lat = [
                p["latency_s"]
                for t in doc["trials"]
                if t["rate_hz"] == rate
                and t["kind"] != "roll"
                and t.get("imperfection", "none") == name
                for p in t["phases"]
                if p["kind"] in detectable
            ]
            if lat:
                found = np.array([np.inf if x is None else x for x in lat])
                label = f"{rate:g} frames/s" + ("" if name == "none" else f", {name}")
                left.plot(
                    grid,
                    [(found <= g).mean() for g in grid],
                    color=f"C{i}",
                    ls=style,
                    label=label,
                )
    left.axvline(doc["latency_s"], color="k", lw=0.8, ls="--")
    left.axhline(0.95, color="k", lw=0.8, ls=":")
    left.set_xlabel("latency, s")
    left.set_ylabel("share of slip phases found")
    left.set_ylim(0.0, 1.0)
    left.legend(fontsize=7, loc="lower right")
    left.set_title("faces and lines slipping (dashed: 0.2 s)")
    rows = [(r, o) for r, o in doc["overall"].items() if o["partial"]["identified"] is not None]
    x = np.arange(len(rows))
    n = [max(1, sum(o["partial"].values())) for _, o in rows]
    with_slip = [o["partial"]["identified"] / k for (_, o), k in zip(rows, n, strict=True)]
    without = [
        o["partial_without_slip"]["identified"] / k for (_, o), k in zip(rows, n, strict=True)
    ]
    right.bar(x - 0.2, with_slip, width=0.4, color="C2", label="slip detection")
    right.bar(x + 0.2, without, width=0.4, color="C7", label="paper 001 (none)")
    right.set_xticks(x, [f"{r} frames/s" for r, _ in rows])
    right.set_ylim(0.0, 1.0)
    right.set_ylabel("share identified")
    right.legend(fontsize=7, loc="lower right")
    right.set_title("rolls with a slipping phase")
    fig.tight_layout()
    return fig
