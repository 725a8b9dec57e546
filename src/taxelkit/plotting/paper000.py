"""Figures of the paper-000 experiments (Fig. 7, 8, 9 and recall against s)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.figure import Figure
from matplotlib.patches import Rectangle

from taxelkit.experiments.fig7 import Fig7Result
from taxelkit.experiments.fig8 import Fig8Result
from taxelkit.experiments.fig9 import Fig9Result
from taxelkit.experiments.paper000_common import FAITHFUL, IMPROVED
from taxelkit.experiments.recall_vs_s import RecallVsSResult
from taxelkit.memory.contour_recall import RecallCurve
from taxelkit.tracing.tracer import Trace

__all__ = ["plot_fig7", "plot_fig8", "plot_fig9", "plot_recall_vs_s", "plot_trace_recall"]


def plot_fig7(result: Fig7Result) -> Figure:
    """Traced straight 50 um edges, both estimators (paper 000, Fig. 7)."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.2), sharex=True, sharey=True)
    for ax, est, title in zip(
        axes, ("eq8", "crossings"), ("Eq. 8 (paper)", "crossing-line (taxelkit)"), strict=True
    ):
        for k, theta in enumerate(result.theta_deg):
            p = result.points_mm[est][k]
            r = result.abs_r[est][k]
            err = result.direction_error_deg[est][k]
            label = f"{theta:.0f} deg: |r|={'n/a' if r is None else f'{r:.3f}'}, err {err:.1f} deg"
            ax.plot(p[:, 0], p[:, 1], ".-", ms=3, label=label)
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
        ax.set_title(f"edge direction by {title}", fontsize=10)
        ax.legend(fontsize=7, loc="upper left")
    axes[0].set_ylabel("y (mm)")
    fig.suptitle("Fig. 7: tracing a 50 um step at 0-90 deg (20 sections of 3 mm)")
    fig.tight_layout()
    return fig


def plot_fig8(result: Fig8Result) -> Figure:
    """Traced contours over the true ones with the sensing area (paper 000, Fig. 8)."""
    n = len(result.names)
    fig, axes = plt.subplots(1, n, figsize=(3.4 * n, 3.8))
    for ax, name, outline, pts, mean, closed in zip(
        axes,
        result.names,
        result.outlines_mm,
        result.points_mm,
        result.error_mean_mm,
        result.closed,
        strict=True,
    ):
        ax.plot(outline[:, 0], outline[:, 1], "-", color="0.5", lw=2, label="true contour")
        ax.plot(pts[:, 0], pts[:, 1], ".-", color="C3", ms=2.5, lw=0.8, label="traced")
        for k in range(0, pts.shape[0], max(1, pts.shape[0] // 6)):
            ax.add_patch(
                Rectangle((pts[k, 0] - 9, pts[k, 1] - 9), 18, 18, fill=False, ec="C0", lw=0.5)
            )
        ax.set_aspect("equal")
        ax.set_title(f"{name}: {mean:.2f} mm{'' if closed else ' (open)'}", fontsize=9)
        ax.tick_params(labelsize=7)
    axes[0].legend(fontsize=7, loc="lower left")
    fig.suptitle("Fig. 8: traced contours (squares: the 6 x 6 sensing area), mean error")
    fig.tight_layout()
    return fig


def plot_fig9(result: Fig9Result) -> Figure:
    """Correlation c against normalised arc length s, one panel per shape (paper 000, Fig. 9)."""
    n = len(result.names)
    fig, axes = plt.subplots(2, n, figsize=(3.3 * n, 6.2), sharex=True, sharey=True)
    for row, setup in enumerate((FAITHFUL, IMPROVED)):
        for col, (name, curve) in enumerate(
            zip(result.names, result.curves[setup.label], strict=True)
        ):
            ax = axes[row, col]
            for k, stored in enumerate(curve.names):
                style = "-" if stored == name else "--"
                ax.plot(curve.s, curve.correlations[:, k], style, lw=1.6 if stored == name else 1,
                        label=stored)  # fmt: skip
            s0 = curve.recognised_from_s(name)
            if s0 is not None:
                ax.axvline(s0, color="k", lw=0.6, ls=":")
            ax.set_title(f"{name}: from s={'never' if s0 is None else f'{s0:.2f}'}", fontsize=8)
            ax.set_ylim(-1.05, 1.05)
            if row == 1:
                ax.set_xlabel("normalised arc length s")
        axes[row, 0].set_ylabel(f"c, {setup.label.split(' (')[0]}")
    axes[0, 0].legend(fontsize=6, loc="lower right")
    fig.suptitle("Fig. 9: correlation with each stored contour while tracing (top: paper's rule)")
    fig.tight_layout()
    return fig


def plot_recall_vs_s(result: RecallVsSResult) -> Figure:
    """Fraction recognised against s for each shape and rule."""
    fig, ax = plt.subplots(figsize=(7, 4.5))
    s = np.asarray(result.s)
    for setup, style in ((IMPROVED, "-o"), (FAITHFUL, "--x")):
        frac = result.fraction(setup)
        for i, name in enumerate(result.names):
            ax.plot(s, frac[i], style, color=f"C{i}", ms=4,
                    label=f"{name} ({setup.label.split(' (')[0]})")  # fmt: skip
    ax.axhline(0.95, color="k", lw=0.6, ls=":")
    ax.set_xlabel("normalised arc length s")
    ax.set_ylabel("fraction recognised")
    ax.set_ylim(-0.03, 1.03)
    n = result.n_trials
    ax.set_title(f"Random rotation, translation and start point, {n} traces per shape", fontsize=10)
    ax.legend(fontsize=7, ncol=2, loc="lower right")
    fig.tight_layout()
    return fig


def plot_trace_recall(trace: Trace, curve: RecallCurve, *, rule: str) -> Figure:
    """One trace and its recall curve (``taxelkit trace --plot``)."""
    fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.6))
    p = trace.points_mm
    a.plot(p[:, 0], p[:, 1], ".-", ms=3, color="C3")
    a.plot(p[0, 0], p[0, 1], "o", color="C2", label="start")
    a.set_aspect("equal")
    a.set_xlabel("x (mm)")
    a.set_ylabel("y (mm)")
    state = "closed" if trace.closed else trace.stop_reason
    a.set_title(f"trace ({state}), {trace.n_sections} sections of 3 mm")
    a.legend(fontsize=8)
    for k, n in enumerate(curve.names):
        b.plot(curve.s, curve.correlations[:, k], label=n)
    b.set_xlabel("normalised arc length s")
    b.set_ylabel("correlation c")
    b.set_ylim(-1.05, 1.05)
    b.set_title(f"recognised: {curve.verdicts[-1]} ({rule})")
    b.legend(fontsize=8)
    fig.tight_layout()
    return fig
