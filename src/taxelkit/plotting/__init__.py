"""Figures from data and result objects (``ax=None`` style, never ``show()``)."""

from taxelkit.plotting.strip import frame_indices_for_strip, plot_frame_strip

__all__ = ["frame_indices_for_strip", "plot_frame_strip"]
