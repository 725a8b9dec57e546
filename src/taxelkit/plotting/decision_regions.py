"""Decision regions of the Level 2 contact classifier (paper 001, Figure 3)."""

from __future__ import annotations

from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.colors import BoundaryNorm, ListedColormap
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch
from numpy.typing import ArrayLike

from taxelkit.errors import InputError, check_positive
from taxelkit.smart.contact_classes import (
    DEFAULT_CONFIDENCE,
    HAND_SET,
    OUTPUT_CLASSES,
    ContactClass,
    ContactNetwork,
    classify_features,
)

__all__ = ["CLASS_COLOURS", "plot_decision_regions"]

#: Colour of each class in the figures.
CLASS_COLOURS: dict[ContactClass, str] = {
    ContactClass.NONE: "white",
    ContactClass.INDETERMINATE: "0.82",
    ContactClass.POINT: "tab:orange",
    ContactClass.LINE: "tab:blue",
    ContactClass.AREA: "tab:green",
}
_MARKERS = {ContactClass.POINT: "o", ContactClass.LINE: "s", ContactClass.AREA: "^"}


def _check_range(name: str, value: tuple[float, float], low: float) -> tuple[float, float]:
    a, b = (float(v) for v in value)
    if not (np.isfinite(a) and np.isfinite(b) and low <= a < b):
        raise InputError(f"{name} must be (lo, hi) with {low} <= lo < hi, got {value!r}")
    return a, b


def plot_decision_regions(
    network: ContactNetwork = HAND_SET,
    *,
    samples: ArrayLike | None = None,
    labels: ArrayLike | None = None,
    ax: Axes | None = None,
    confidence: float = DEFAULT_CONFIDENCE,
    area_range_mm2: tuple[float, float] = (1.0, 300.0),
    elongation_range: tuple[float, float] = (1.0, 12.0),
    resolution: int = 240,
    pitch_mm: float | None = None,
    title: str | None = None,
) -> Figure:
    """Draw how a network partitions the (area, elongation) plane.

    Point, line and area regions are filled in their colours, the
    indeterminate band in grey; both axes are logarithmic (the network's own
    scaling). Labelled samples, when given, are scattered on top.

    Parameters
    ----------
    network : ContactNetwork
        :data:`~taxelkit.smart.contact_classes.HAND_SET` by default.
    samples : (N, 2) float, optional
        ``(area_mm2, elongation)`` of contacts to show.
    labels : (N,) int, optional
        Their :class:`~taxelkit.smart.contact_classes.ContactClass` codes;
        without labels the samples are drawn in black.
    ax : Axes, optional
        Draw into these axes instead of a new figure.
    confidence : float
        Passed to :func:`~taxelkit.smart.contact_classes.classify_features`.
    area_range_mm2 : (float, float), mm^2
        Area axis limits (> 0).
    elongation_range : (float, float)
        Elongation axis limits (>= 1).
    resolution : int
        Grid cells along each axis.
    pitch_mm : float, optional
        When given, a top axis shows the area in taxels of this pitch.
    title : str, optional
        Axes title; default names the network and the confidence.

    Returns
    -------
    matplotlib.figure.Figure
        The figure; nothing is shown or saved.

    Raises
    ------
    InputError
        On bad ranges, resolution or samples.

    References
    ----------
    Paper 001, Figure 3 (tactile image classification).
    """
    areas = _check_range("area_range_mm2", area_range_mm2, 1e-12)
    elongations = _check_range("elongation_range", elongation_range, 1.0)
    if not isinstance(resolution, int | np.integer) or resolution < 2:
        raise InputError(f"resolution must be an integer >= 2, got {resolution!r}")
    if ax is None:
        fig, ax = plt.subplots(figsize=(7.4, 4.6), layout="constrained")
    else:
        fig = ax.figure  # type: ignore[assignment]
    handles = _draw_regions(ax, areas, elongations, int(resolution), network, confidence)
    if samples is not None:
        handles += _scatter_samples(ax, samples, labels)
    if pitch_mm is not None:
        _add_taxel_axis(ax, pitch_mm)
    ax.legend(
        handles=handles, loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=7, frameon=False
    )
    shown = (
        title if title is not None else f"{network.name or 'network'}, confidence {confidence:g}"
    )
    ax.set_title(shown, fontsize=9)
    return fig


def _draw_regions(
    ax: Axes,
    area_range_mm2: tuple[float, float],
    elongation_range: tuple[float, float],
    resolution: int,
    network: ContactNetwork,
    confidence: float,
) -> list[Any]:
    """Fill each cell of a log-spaced grid with the colour of its class, on log axes.

    Returns the legend handles of the classes.
    """
    area_edges = np.geomspace(*area_range_mm2, resolution + 1)
    elong_edges = np.geomspace(*elongation_range, resolution + 1)
    area_mid = np.sqrt(area_edges[:-1] * area_edges[1:])
    elong_mid = np.sqrt(elong_edges[:-1] * elong_edges[1:])
    aa, ee = np.meshgrid(area_mid, elong_mid)
    codes = classify_features(
        np.column_stack([aa.ravel(), ee.ravel()]), network, confidence=confidence
    ).reshape(aa.shape)
    order = list(ContactClass)
    cmap = ListedColormap([CLASS_COLOURS[c] for c in order])
    norm = BoundaryNorm(np.arange(len(order) + 1) - 0.5, cmap.N)
    ax.pcolormesh(area_edges, elong_edges, codes, cmap=cmap, norm=norm, alpha=0.45, shading="flat")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(*area_range_mm2)
    ax.set_ylim(*elongation_range)
    ax.set_xlabel("area of contact m00 (mm$^2$)")
    ax.set_ylabel("elongation")
    return [
        Patch(facecolor=CLASS_COLOURS[c], alpha=0.45, label=c.name.lower())
        for c in (*OUTPUT_CLASSES, ContactClass.INDETERMINATE)
    ]


def _scatter_samples(ax: Axes, samples: ArrayLike, labels: ArrayLike | None) -> list[Any]:
    """Scatter ``(area, elongation)`` samples, per class when labelled; their legend handles."""
    pts = np.asarray(samples, dtype=np.float64)
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise InputError(f"samples must have shape (N, 2), got {pts.shape}")
    if labels is None:
        ax.scatter(pts[:, 0], pts[:, 1], s=10, c="k", alpha=0.6, lw=0, clip_on=False)
        return []
    lab = np.asarray(labels)
    if lab.shape != (pts.shape[0],):
        raise InputError(f"labels must have shape ({pts.shape[0]},), got {lab.shape}")
    handles: list[Any] = []
    for c in OUTPUT_CLASSES:
        m = lab == int(c)
        if not np.any(m):
            continue
        ax.scatter(
            pts[m, 0],
            pts[m, 1],
            s=14,
            marker=_MARKERS[c],
            facecolor=CLASS_COLOURS[c],
            edgecolor="k",
            linewidth=0.3,
            alpha=0.7,
            clip_on=False,  # elongation 1 lies on the axis
        )
        handles.append(
            Line2D(
                [],
                [],
                ls="",
                marker=_MARKERS[c],
                markerfacecolor=CLASS_COLOURS[c],
                markeredgecolor="k",
                label=f"{c.name.lower()} samples",
            )
        )
    return handles


def _add_taxel_axis(ax: Axes, pitch_mm: float) -> None:
    """A top axis giving the area in taxels of ``pitch_mm``."""
    p2 = check_positive("pitch_mm", pitch_mm) ** 2

    def taxels_from_area(area: Any) -> Any:
        return np.asarray(area, dtype=np.float64) / p2

    def area_from_taxels(taxels: Any) -> Any:
        return np.asarray(taxels, dtype=np.float64) * p2

    top = ax.secondary_xaxis("top", functions=(taxels_from_area, area_from_taxels))
    top.set_xlabel(f"taxels at {float(pitch_mm):.4g} mm pitch")
