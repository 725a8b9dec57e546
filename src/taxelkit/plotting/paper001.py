"""Figures of the paper-001 experiments (Fig. 3 / Table 2, confusion matrix, tacteme table)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

from taxelkit.experiments.paper001 import (
    OUTCOMES,
    CylinderResult,
    SmartSensorResult,
    TactemeTableResult,
)
from taxelkit.smart.tacteme_table import OBJECTS, TABLE

__all__ = ["plot_cylinder", "plot_smart_sensor", "plot_tacteme_table"]


def plot_cylinder(result: CylinderResult, *, columns: int = 12) -> Figure:
    """Binary images with their Level 2 class and the Level 2-4 events (Fig. 3, Table 2)."""
    rec, r = result.recording, result.recognition
    n = rec.n_frames
    rows = int(np.ceil(n / columns))
    fig = plt.figure(figsize=(1.25 * columns, 1.5 * rows + 2.6))
    grid = fig.add_gridspec(rows + 1, columns, height_ratios=[1.0] * rows + [1.4])
    names = r.class_names()
    for k in range(n):
        ax = fig.add_subplot(grid[k // columns, k % columns])
        ax.imshow(rec.frames[k], cmap="gray_r", origin="lower", vmin=0, vmax=1)
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_xlabel(f"{k + 1} {names[k][:5]}", fontsize=7)
    table = fig.add_subplot(grid[rows, :])
    table.axis("off")
    lines = ["frame  event"]
    for e in r.events:
        value = ", ".join(e.value) if isinstance(e.value, tuple) else e.value
        lines.append(f"{e.frame + 1:5d}  {e.kind}: {value}")
    table.text(0.0, 1.0, "\n".join(lines[:14]), va="top", family="monospace", fontsize=7)
    fig.suptitle(f"Cylinder (paper 001, Fig. 3): identified as {r.identified}")
    return fig


def plot_smart_sensor(result: SmartSensorResult) -> Figure:
    """Confusion matrix: object against outcome (including unknown and undecided)."""
    doc = result.to_json()
    fig, ax = plt.subplots(figsize=(8.5, 4.8))
    c = result.confusion
    ax.imshow(c, cmap="Blues")
    for i in range(c.shape[0]):
        for j in range(c.shape[1]):
            if c[i, j]:
                color = "white" if c[i, j] > c.max() / 2 else "black"
                ax.text(j, i, str(c[i, j]), ha="center", va="center", color=color, fontsize=9)
    ax.set_xticks(range(len(OUTCOMES)), OUTCOMES, rotation=30, ha="right")
    ax.set_yticks(range(len(OBJECTS)), OBJECTS)
    ax.set_xlabel("outcome")
    ax.set_ylabel("object rolled")
    ax.set_title(
        f"Smart sensor: accuracy {doc['accuracy']:.3f}, wrong {doc['wrong']}, "
        f"sliding identified {doc['sliding_identified']}/{doc['sliding_trials']} "
        f"(paper: 0.83)",
        fontsize=10,
    )
    fig.tight_layout()
    return fig


def plot_tacteme_table(result: TactemeTableResult) -> Figure:
    """Tactemes produced per object (counts) beside the table's eliminations (shaded)."""
    fig, ax = plt.subplots(figsize=(8.5, 7.0))
    elim = np.array([[obj in row.eliminates for obj in OBJECTS] for row in TABLE], dtype=float)
    ax.imshow(elim, cmap="Reds", vmin=0, vmax=3, aspect="auto")
    for i in range(elim.shape[0]):
        for j in range(elim.shape[1]):
            n = int(result.counts[i, j])
            if n:
                bad = elim[i, j] > 0
                ax.text(
                    j,
                    i,
                    str(n),
                    ha="center",
                    va="center",
                    fontsize=8,
                    color="red" if bad else "black",
                    weight="bold" if bad else "normal",
                )
    ax.set_xticks(range(len(OBJECTS)), OBJECTS, rotation=30, ha="right")
    ax.set_yticks(range(len(TABLE)), [r.tacteme.value for r in TABLE], fontsize=8)
    ax.set_title(
        f"Tactemes in {result.n_trials} simulated trials per object "
        f"(shaded: the table eliminates; {len(result.violations())} violations)",
        fontsize=10,
    )
    fig.tight_layout()
    return fig
