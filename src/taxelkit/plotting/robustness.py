"""Heat map of the ``robustness`` experiment: accuracy per engine, imperfection, rate and object."""

from __future__ import annotations

from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

__all__ = ["plot_robustness"]


def plot_robustness(result: Any) -> Figure:
    """One panel per engine: rows are imperfections, columns rate x object.

    Each cell shows the accuracy in percent; a red frame marks a cell with a
    wrong identity. The sliding trials' count of identities is in the title.
    """
    doc = result.to_json()
    objects: list[str] = doc["objects"]
    rates: list[float] = doc["rates_hz"]
    rows: list[str] = [*doc["faults"], doc["lift_off"]]
    engines: list[str] = doc["engines"]
    cells = {(c["engine"], c["rate_hz"], c["fault"], c["object"]): c for c in doc["cells"]}
    short = {"truncated-cone": "trunc.", "tetrahedron": "tetra.", "cylinder": "cyl."}
    has_arrays = bool(doc.get("arrays", {}).get("cells"))
    fig, axes = plt.subplots(
        len(engines) + int(has_arrays),
        1,
        figsize=(1.0 + 0.42 * len(rates) * len(objects), 1.2 + 2.6 * len(engines)),
        squeeze=False,
    )
    for ax, engine in zip(axes[: len(engines), 0], engines, strict=True):
        acc = np.full((len(rows), len(rates) * len(objects)), np.nan)
        for i, fault in enumerate(rows):
            for j, rate in enumerate(rates):
                for k, obj in enumerate(objects):
                    c = cells.get((engine, rate, fault, obj))
                    if c is None or c["accuracy"] is None:
                        continue
                    col = j * len(objects) + k
                    acc[i, col] = c["accuracy"]
                    ax.text(
                        col,
                        i,
                        f"{100 * c['accuracy']:.0f}",
                        ha="center",
                        va="center",
                        fontsize=6.5,
                        color="black" if c["accuracy"] > 0.6 else "white",
                    )
                    if c["wrong"]:
                        ax.add_patch(
                            Rectangle(
                                (col - 0.5, i - 0.5),
                                1,
                                1,
                                fill=False,
                                edgecolor="red",
                                linewidth=1.5,
                            )
                        )
        ax.imshow(acc, vmin=0.5, vmax=1.0, cmap="viridis", aspect="auto")
        ax.set_yticks(range(len(rows)), rows, fontsize=8)
        ax.set_xticks(
            range(acc.shape[1]),
            [short.get(o, o) for o in objects] * len(rates),
            rotation=90,
            fontsize=7,
        )
        for j, rate in enumerate(rates):
            ax.axvline(j * len(objects) - 0.5, color="white", linewidth=2)
            ax.text(
                (j + 0.5) * len(objects) - 0.5, -0.9, f"{rate:g} frames/s", ha="center", fontsize=8
            )
        sl = [s for s in doc["cells"] if s["engine"] == engine and s["object"] == "sliding"]
        ident = sum(s["n"] - s["correct"] for s in sl)
        ax.set_title(
            f"{engine}: accuracy (%) per cell, {doc['n_trials']} trials; red frame = a wrong "
            f"identity; sliding trials identified: {ident} of {sum(s['n'] for s in sl)}",
            fontsize=9,
            pad=16,
        )
    if has_arrays:
        _arrays_panel(axes[-1, 0], doc, short)
    fig.tight_layout()
    return fig


def _arrays_panel(ax: Any, doc: dict[str, Any], short: dict[str, str]) -> None:
    """Rows: array x imperfection; columns: engine x object (sliding: right if not named)."""
    part = doc["arrays"]
    truths = [*doc["objects"], "sliding"]
    cells = {(c["array"], c["engine"], c["fault"], c["object"]): c for c in part["cells"]}
    arrays = sorted({c["array"] for c in part["cells"]}, key=lambda a: int(a.split("x")[0]))
    rows = [(a, f) for a in arrays for f in part["faults"]]
    cols = [(e, t) for e in doc["engines"] for t in truths]
    acc = np.full((len(rows), len(cols)), np.nan)
    for i, (a, f) in enumerate(rows):
        for j, (e, t) in enumerate(cols):
            c = cells.get((a, e, f, t))
            if c is None or c["accuracy"] is None:
                continue
            acc[i, j] = c["accuracy"]
            colour = "black" if c["accuracy"] > 0.6 else "white"
            ax.text(j, i, f"{100 * c['accuracy']:.0f}", ha="center", va="center",
                    fontsize=6.5, color=colour)  # fmt: skip
            if c["wrong"]:
                ax.add_patch(Rectangle((j - 0.5, i - 0.5), 1, 1, fill=False, edgecolor="red",
                                       linewidth=1.5))  # fmt: skip
    ax.imshow(acc, vmin=0.5, vmax=1.0, cmap="viridis", aspect="auto")
    ax.set_yticks(range(len(rows)), [f"{a} mm, {f}" for a, f in rows], fontsize=8)
    ax.set_xticks(range(len(cols)), [short.get(t, t) for _, t in cols], rotation=90, fontsize=7)
    for k, e in enumerate(doc["engines"]):
        ax.axvline(k * len(truths) - 0.5, color="white", linewidth=2)
        ax.text((k + 0.5) * len(truths) - 0.5, -0.9, e, ha="center", fontsize=8)
    ax.set_title(
        f"other arrays at {part['rate_hz']:g} frames/s: accuracy (%) per cell "
        "(sliding: not given an identity)",
        fontsize=9,
        pad=16,
    )
