"""Confusion matrices of the ``new-objects`` experiment: one roll (ten-object table, paper
001's six) and the exploration (the object handled until decided)."""

from __future__ import annotations

from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure

__all__ = ["plot_new_objects"]


def _matrix(
    confusion: dict[str, dict[str, int]], rows: list[str], cols: list[str]
) -> np.ndarray[Any, np.dtype[np.int64]]:
    return np.array([[confusion.get(r, {}).get(c, 0) for c in cols] for r in rows], dtype=np.int64)


def _draw(
    ax: Any, m: np.ndarray[Any, np.dtype[np.int64]], rows: list[str], cols: list[str], title: str
) -> None:
    share = m / np.maximum(m.sum(axis=1, keepdims=True), 1)
    ax.imshow(share, cmap="Blues", vmin=0.0, vmax=1.0)
    for i in range(m.shape[0]):
        for j in range(m.shape[1]):
            if m[i, j]:
                ax.text(j, i, str(m[i, j]), ha="center", va="center", fontsize=6,
                        color="w" if share[i, j] > 0.6 else "k")  # fmt: skip
    ax.set_xticks(range(len(cols)), cols, rotation=60, ha="right", fontsize=7)
    ax.set_yticks(range(len(rows)), rows, fontsize=7)
    ax.set_xlabel("outcome")
    ax.set_title(title, fontsize=9)


def plot_new_objects(result: Any, ax: Any = None) -> Figure:
    """Left: outcomes of one roll with the ten-object table and face tactemes. Middle: the
    same rolls recognised with paper 001's six-object table. Right: the ten-object table
    over up to ``handlings`` rolls of the object (the exploration).

    Parameters
    ----------
    result : NewObjectsResult
    ax : three Axes, optional

    Returns
    -------
    Figure
    """
    doc = result.to_json()
    objects = list(doc["objects"])
    rows = objects + sorted(doc["outside"])
    cols = [*objects, "unknown", "undecided"]
    if ax is None:
        fig, axes = plt.subplots(1, 3, figsize=(19.0, 5.8))
    else:
        fig, axes = ax[0].figure, ax
    ten = {**doc["confusion"], **doc["outside"]}
    six = {**doc["baseline"], **doc["outside_baseline"]}
    s = doc["summary"]
    _draw(axes[0], _matrix(ten, rows, cols), rows, cols,
          f"ten objects, face tactemes: {s['wrong']} wrong, "
          f"{100 * s['distinguishable_rate']:.1f} % of distinguishable identified")  # fmt: skip
    six_cols = [*objects[:6], "unknown", "undecided"]
    _draw(axes[1], _matrix(six, rows, six_cols), rows, six_cols, "paper 001's six-object table")
    ex = doc["explore"]
    explored = {r["object"]: r["outcomes"] for r in ex["per_object"]}
    es = ex["summary"]
    _draw(axes[2], _matrix(explored, rows, cols), rows, cols,
          f"handled up to {ex['handlings']} times: {es['wrong']} wrong, "
          f"{100 * es['distinguishable_rate']:.1f} % of distinguishable identified")  # fmt: skip
    axes[0].set_ylabel("object rolled")
    fig.tight_layout()
    return fig
