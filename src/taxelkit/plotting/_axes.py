"""Where a two-panel figure draws: the caller's pair of axes, or a new figure."""

from __future__ import annotations

from typing import Any

import matplotlib.pyplot as plt
from matplotlib.figure import Figure

__all__ = ["axes_pair"]


def axes_pair(ax: Any, figsize: tuple[float, float]) -> tuple[Figure, Any]:
    """The figure and the two axes to draw on.

    Parameters
    ----------
    ax : pair of Axes or None
        The caller's axes; None makes a new 1 x 2 figure.
    figsize : (width, height), inch
        Size of a new figure.
    """
    if ax is None:
        fig, axes = plt.subplots(1, 2, figsize=figsize)
        return fig, axes
    return ax[0].figure, ax
