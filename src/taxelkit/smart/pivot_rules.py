"""Level 3's pivot verdict of a turning line, on a whole segment (batch).

What :func:`~taxelkit.smart.tactemes.segment_tactemes` calls once a line
has turned (LCMT): the least-squares pivot of its lines from the turn's anchor
on (:func:`~taxelkit.smart.pivots.drawn_pivot_fit`) and the three verdicts
"spins about its middle", "about one end" and "in an arc"; the batched form
is :mod:`taxelkit.smart.tactemes_batch`, the streamed one
:mod:`taxelkit.smart.pivot_stream`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.pivot_limits import (
    arc_limit_turn_deg,
    arc_ratio_limit,
    pivot_lower,
    pivot_upper,
)
from taxelkit.smart.pivots import drawn_pivot_fit
from taxelkit.smart.tacteme_config import TactemeConfig
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.track_geometry import drawn_half_mm, first, sustained, turn
from taxelkit.smart.verdict_holds import bridge_gaps, gap_rows

if TYPE_CHECKING:
    from taxelkit.smart.tactemes import SegmentTrack

__all__ = ["pivot_tacteme", "pivot_verdicts"]


def _drawn_half(track: SegmentTrack, start: int, stop: int) -> NDArray[np.float64]:
    """:func:`~taxelkit.smart.track_geometry.drawn_half_mm` of the lines ``start..stop - 1``."""
    ext = None if track.extent_mm is None else track.extent_mm[start:stop]
    return drawn_half_mm(track.half_length_mm[start:stop], ext)


def _pivot_ratios(
    track: SegmentTrack, start: int, stop: int, arc_w: int = 1, pressed: bool = False
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """:func:`~taxelkit.smart.pivots.drawn_pivot_fit` of the lines ``start..stop - 1``.

    ``pressed``: in the pressed lines' half-lengths (their areas given).
    """
    ext = None if track.extent_mm is None else track.extent_mm[start:stop]
    return drawn_pivot_fit(
        track.orientation_deg[start:stop],
        track.centre_mm[start:stop],
        track.half_length_mm[start:stop],
        ext,
        arc_w,
        area_mm2=track.area_mm2[start:stop] if pressed else None,
    )


def pivot_tacteme(
    track: SegmentTrack,
    config: TactemeConfig,
    angle: NDArray[np.float64],
    anchor: NDArray[np.intp],
    ref: NDArray[np.intp],
    j_turn: int,
    hold: int,
) -> list[tuple[int, Tacteme]]:
    """The pivot verdicts of a line that turned at ``j_turn``: ``(index, tacteme)`` each.

    ``angle``, ``anchor`` and ``ref`` are the segment's smoothed axis (deg),
    anchors and references (:func:`segment_tactemes`). Every verdict that is
    sustained somewhere in the segment is returned, at its first sustained
    index, in the order of the indices (ties in the order spins, about one
    end, in an arc): a line whose pivot reads in two places (about one end,
    later in an arc) gives both, so that no object whose row holds only one
    of them is named from it. Only the first with
    ``config.pivot_every_verdict`` False (paper 001's pipeline).
    """
    k = int(config.debounce_frames)
    n = track.frames.size
    pivots: list[tuple[int, Tacteme]] = []
    # the lines from the turn's anchor on, across later re-anchors: a rolling
    # cone's line keeps turning about the same point while its width varies
    start, stop = int(anchor[j_turn]), n
    arc_w = track.frames_for(config.smooth_s, k) if config.pivot_arc_smooth else 1
    ratio, error, arc_ratio = _pivot_ratios(track, start, stop, arc_w, config.pivot_pressed_half)
    line_mm = 2.0 * _drawn_half(track, start, stop)
    pivot_hold = track.frames_for(config.pivot_hold_s, k, minimum=hold)
    turned_now = turn(angle, ref[start] + np.zeros(n, np.intp))[start:]
    span = track.frames[start:stop] if config.hold_spans_gaps else None
    largest = np.maximum.accumulate(turned_now) if config.pivot_arc_max_turn else None
    gap = gap_rows(track.frame_interval_s(k), config.pivot_gap_s)
    for tac, verdict in pivot_verdicts(
        config, ratio, error, arc_ratio, turned_now, line_mm, track.pitch_mm, largest
    ):
        # "about one end", the verdict that names a cone, holds on the segment's own rows
        own = tac is Tacteme.LCMT_ABOUT_END
        bridged = bridge_gaps(verdict, gap)
        j = first(sustained(bridged, pivot_hold, None if own else span, hold) & verdict, 0)
        if j is not None:
            pivots.append((start + j, tac))
    found = sorted(pivots, key=lambda hit: hit[0])
    return found if config.pivot_every_verdict else found[:1]


def pivot_verdicts(
    config: TactemeConfig,
    ratio: NDArray[np.float64],
    error: NDArray[np.float64],
    arc_ratio: NDArray[np.float64],
    turned_deg: NDArray[np.float64],
    line_mm: NDArray[np.float64],
    pitch_mm: float,
    largest_deg: NDArray[np.float64] | None = None,
) -> list[tuple[Tacteme, NDArray[np.bool_]]]:
    """The three pivot verdicts at each frame: spins, about one end, in an arc.

    Parameters
    ----------
    config : TactemeConfig
    ratio, error, arc_ratio : (n,) float
        :func:`~taxelkit.smart.pivots.drawn_pivot_fit` of the lines, half-lengths.
    turned_deg : (n,) float
        Each frame's turn from the reference, deg.
    line_mm : (n,) float
        Each frame's drawn line length, mm (shorter than
        ``pivot_min_line_taxels`` pitches: no verdict).
    pitch_mm : float
    largest_deg : (n,) float, optional
        The largest turn up to each frame, deg: "in an arc" reads its limit
        there where the grid allows (:func:`~taxelkit.smart.pivot_limits.arc_limit_turn_deg`,
        ``config.pivot_arc_max_turn``); None: at ``turned_deg``.

    Returns
    -------
    list of (Tacteme, (n,) bool)
    """
    short = line_mm < config.pivot_min_line_taxels * pitch_mm
    ratio = np.where(short, np.nan, ratio)
    arc_ratio = np.where(short, np.nan, pivot_lower(arc_ratio, error, config.pivot_arc_sigmas))
    ready = turned_deg > config.pivot_turn_deg
    lo = config.pivot_end_ratio / config.pivot_band
    arc_turned = turned_deg
    if largest_deg is not None:
        arc_turned = arc_limit_turn_deg(
            turned_deg, largest_deg, line_mm, pitch_mm, config.pivot_turn_deg
        )
    arc = arc_ratio_limit(
        arc_turned,
        config.pivot_end_ratio,
        config.pivot_band,
        config.pivot_turn_deg,
        config.pivot_arc_turn_deg,
        line_mm,
        pitch_mm,
    )
    return [
        (Tacteme.LC_SPINS, ready & (ratio < config.pivot_min_ratio)),
        (
            Tacteme.LCMT_ABOUT_END,
            ready
            & (ratio >= config.pivot_min_ratio)
            & (pivot_upper(ratio, error, config.pivot_end_sigmas) <= lo),
        ),
        (Tacteme.LCMT_ARC, arc_ratio >= arc),
    ]
