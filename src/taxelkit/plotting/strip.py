"""Draw tactile frames as an image strip."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.frames import TactileFrames

__all__ = ["frame_indices_for_strip", "plot_frame_strip"]


def frame_indices_for_strip(n_frames: int, max_frames: int) -> NDArray[np.intp]:
    """Evenly spaced frame indices, first and last included, at most ``max_frames``."""
    if max_frames < 1:
        raise InputError(f"max_frames must be >= 1, got {max_frames!r}")
    if n_frames <= max_frames:
        return np.arange(n_frames)
    return np.unique(np.round(np.linspace(0, n_frames - 1, max_frames)).astype(np.intp))


def plot_frame_strip(
    recording: TactileFrames,
    *,
    indices: Sequence[int] | NDArray[np.intp] | None = None,
    max_frames: int = 12,
    columns: int = 6,
    labels: Sequence[str] | None = None,
    title: str | None = None,
    axes: Sequence[Axes] | None = None,
) -> Figure:
    """Draw frames side by side with a shared colour scale.

    Parameters
    ----------
    recording : TactileFrames
        Frames to draw; bool frames are drawn black on white.
    indices : sequence of int, optional
        Which frames; default: at most ``max_frames`` evenly spaced frames.
    max_frames : int
        Limit used when ``indices`` is not given.
    columns : int
        Panels per row of the figure.
    labels : sequence of str, optional
        A caption under each drawn frame (for example its contact class);
        default: frame number and time.
    title : str, optional
        Figure title.
    axes : sequence of Axes, optional
        Draw into these axes (one per frame) instead of a new figure.

    Returns
    -------
    matplotlib.figure.Figure
        The figure; nothing is shown or saved.
    """
    idx = (
        frame_indices_for_strip(recording.n_frames, max_frames)
        if indices is None
        else np.asarray(indices, dtype=np.intp)
    )
    if idx.size == 0 or idx.min() < 0 or idx.max() >= recording.n_frames:
        raise InputError(f"indices must lie in [0, {recording.n_frames - 1}], got {list(idx)}")
    if labels is not None and len(labels) != idx.size:
        raise InputError(f"labels must have {idx.size} entries, got {len(labels)}")
    frames = recording.frames[idx]
    if axes is None:
        ncols = min(columns, idx.size)
        nrows = int(np.ceil(idx.size / ncols))
        fig, grid = plt.subplots(
            nrows, ncols, figsize=(1.9 * ncols, 2.1 * nrows + 0.4), squeeze=False
        )
        ax_list: list[Axes] = list(grid.ravel())
        for ax in ax_list[idx.size :]:
            ax.set_visible(False)
    else:
        ax_list = list(axes)
        fig = ax_list[0].figure  # type: ignore[assignment]
    kwargs: dict[str, Any]
    if recording.is_contact:
        kwargs = {"cmap": "gray_r", "vmin": 0, "vmax": 1}
    else:
        hi = float(np.max(frames)) if np.max(frames) > 0 else 1.0
        kwargs = {"cmap": "viridis", "vmin": min(0.0, float(np.min(frames))), "vmax": hi}
    image = None
    for k, (ax, t) in enumerate(zip(ax_list, idx, strict=False)):
        image = ax.imshow(recording.frames[t].astype(float), origin="lower", **kwargs)
        ax.set_xticks([])
        ax.set_yticks([])
        caption = labels[k] if labels is not None else f"#{t}  {recording.t_s[t]:.3g} s"
        ax.set_xlabel(caption, fontsize=8)
    if image is not None and not recording.is_contact and axes is None:
        bar = fig.colorbar(image, ax=ax_list[: idx.size], shrink=0.8)
        bar.set_label(f"displacement ({recording.units})")
    if title:
        fig.suptitle(title)
    return fig
