"""Figures of the simulator demo."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from taxelkit.experiments.simulator_demo import ReliefSlide, SolidPresses
from taxelkit.plotting.strip import frame_indices_for_strip, plot_frame_strip

__all__ = ["plot_relief_slide", "plot_solid_presses"]


def plot_relief_slide(slide: ReliefSlide, *, n_shown: int = 8) -> Figure:
    """Specimen outline with the sensor's path, and the frames along it."""
    fig = plt.figure(figsize=(12, 4.6))
    grid = fig.add_gridspec(2, (n_shown + 1) // 2 + 3)
    ax = fig.add_subplot(grid[:, :3])
    o = slide.outline_mm
    ax.fill(o[:, 0], o[:, 1], color="0.85", label=f"{slide.shape} relief, 200 um")
    ax.plot(o[:, 0], o[:, 1], color="0.3", lw=1)
    p = slide.positions_mm
    ax.plot(p[:, 0], p[:, 1], ".-", color="C1", ms=3, label="sensor centre")
    w, h = slide.footprint_mm
    idx = frame_indices_for_strip(slide.recording.n_frames, n_shown)
    for k in (idx[0], idx[-1]):
        ax.add_patch(Rectangle((p[k, 0] - w / 2, p[k, 1] - h / 2), w, h, fill=False, ec="C0", lw=1))
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.legend(loc="lower left", fontsize=7)
    ax.set_title("optical 3-axis sensor on the specimen", fontsize=9)
    per_row = (idx.size + 1) // 2
    axes = [fig.add_subplot(grid[k // per_row, 3 + k % per_row]) for k in range(idx.size)]
    plot_frame_strip(
        slide.recording,
        indices=idx,
        axes=axes,
        labels=[f"x={p[k, 0]:.1f} mm" for k in idx],
    )
    image = axes[-1].images[0]
    fig.colorbar(image, ax=axes, shrink=0.8, label="displacement (mm)")
    fig.suptitle("Paper 000 world: central 6 x 6 displacement while sliding across a step")
    return fig


def plot_solid_presses(presses: SolidPresses) -> Figure:
    """Grid of contact images (rows: solids; columns: poses) over displacement."""
    s, k = presses.contact.shape[:2]
    fig, axes = plt.subplots(s, k, figsize=(2.2 * k + 1.2, 2.0 * s), squeeze=False)
    vmax = float(np.max(presses.displacement_mm))
    for i in range(s):
        for j in range(k):
            ax = axes[i, j]
            ax.imshow(
                presses.displacement_mm[i, j], origin="lower", cmap="Blues", vmin=0, vmax=vmax
            )
            outline = presses.contact[i, j].astype(float)
            if 0 < outline.sum() < outline.size:
                ax.contour(outline, levels=[0.5], colors="k", linewidths=0.8)
            ax.set_xticks([])
            ax.set_yticks([])
            if i == 0:
                ax.set_title(presses.pose_labels[j], fontsize=9)
            if j == 0:
                ax.set_ylabel(presses.names[i], fontsize=9)
    fig.suptitle("Paper 001 world: displacement (blue) and binary contact (outline), 16 x 16")
    fig.tight_layout()
    return fig
