"""Tracking a chunk of frames at once: the frames in which nothing can happen skip the step.

:func:`~taxelkit.smart.tracks.step` links one frame's regions to the live
tracks with a few dozen NumPy calls, about 0.1 ms a frame. In most frames of a
recording nothing happens: every object on the sensor is still there, each
region overlapping its own region of the frame before. Such a frame is
*continuing* when

* it holds as many regions as the frame before (at most ``max_regions``),
  each overlapping (sharing a taxel with) exactly one region of the frame
  before and each of those overlapping exactly one of it; and
* for two regions or more, that pairing is the cheapest assignment by the
  tracker's cost (centroid distance plus ``area_weight`` times the change of
  ``sqrt(area)``, every pairing of the regions tried) by more than
  ``margin_mm``; or
* it and the frame before hold no region.

If, before a continuing frame, every live track took a region in the frame
before (none unseen or merged), :func:`~taxelkit.smart.tracks.step` would pair
the regions exactly so (an overlap is within any gate) and report no event,
so :func:`track_chunk` only carries each track to its region and calls the
step on the other frames. A stretch of frames with no region while tracks
are alive (an object lifted) is passed at once too: each track goes unseen
for the stretch and dies on the frame the step would end it. The tracks,
their events and every region's track are those of the step called on every
frame (tested), at a fraction of the cost (``benchmarks/bench_segment_track.py``).
"""

from __future__ import annotations

import itertools

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.regions import Regions
from taxelkit.smart.tracks import RegionTracker, TrackEvent

__all__ = ["continuing_frames", "track_chunk"]

#: Most regions a continuing frame may hold (the pairings tried grow as its factorial).
MAX_REGIONS = 4
#: Least margin, mm, by which the overlap pairing must be the cheapest assignment.
MARGIN_MM = 1e-2


def continuing_frames(
    regions: Regions,
    *,
    area_weight: float,
    max_regions: int = MAX_REGIONS,
    margin_mm: float = MARGIN_MM,
) -> tuple[NDArray[np.bool_], NDArray[np.intp], NDArray[np.intp]]:
    """The frames of a stack in which the regions only continue those of the frame before.

    Parameters
    ----------
    regions : Regions
        The stack's regions (:func:`~taxelkit.smart.regions.segment_frames`).
    area_weight : float
        The tracker's weight of the change of ``sqrt(area)``, mm per mm.
    max_regions : int
        Most regions of a continuing frame.
    margin_mm : float
        Least margin of the overlap pairing over every other pairing, mm.

    Returns
    -------
    continuing : (T,) bool
        Continuing frames (the module docstring); frame 0 never is.
    previous : (n,) int
        For each region of a continuing frame, the region of the frame before
        that it continues (-1 elsewhere).
    starts : (T + 1,) int
        Frame ``t``'s regions are ``starts[t]:starts[t + 1]``.
    """
    labels = regions.labels
    t = labels.shape[0]
    n = regions.n_regions
    starts = np.searchsorted(regions.frame, np.arange(t + 1)).astype(np.intp)
    m = np.diff(starts)
    continuing = np.zeros(t, bool)
    previous = np.full(n, -1, np.intp)
    if t < 2:
        return continuing, previous, starts
    continuing[1:] = (m[1:] == 0) & (m[:-1] == 0)
    flat = labels.reshape(t, -1)
    both = (flat[:-1] > 0) & (flat[1:] > 0)  # (T - 1, taxels): on in a frame and the next
    ok = np.zeros(t, bool)
    # one region after one region (most frames): continuing when they overlap
    one_one = np.flatnonzero((m[1:] == 1) & (m[:-1] == 1) & both.any(axis=1)) + 1
    ok[one_one] = True
    previous[starts[one_one]] = starts[one_one - 1]
    # more regions: each must overlap exactly one of the other frame's
    pairs = np.flatnonzero((np.maximum(m[1:], m[:-1]) >= 2) & (m[1:] == m[:-1]))
    pairs = pairs[m[pairs + 1] <= max_regions]
    if pairs.size:
        sel = both[pairs]
        key = np.unique((flat[pairs][sel].astype(np.int64) - 1) * n + (flat[pairs + 1][sel] - 1))
        before, after = key // n, key % n  # overlapping regions of consecutive frames
        one = (np.bincount(before, minlength=n)[before] == 1) & (
            np.bincount(after, minlength=n)[after] == 1
        )
        before, after = before[one], after[one]
        paired = np.bincount(regions.frame[after], minlength=t)
        frames = pairs + 1
        ok[frames[paired[frames] == m[frames]]] = True
        previous[after] = before
    for k in range(2, max_regions + 1):
        frames = np.flatnonzero(ok & (m == k))
        if frames.size:
            ok[frames] = _cheapest(regions, starts, previous, frames, k, area_weight, margin_mm)
    continuing |= ok
    keep = continuing[regions.frame]
    previous[~keep] = -1
    return continuing, previous, starts


def _cheapest(
    regions: Regions,
    starts: NDArray[np.intp],
    previous: NDArray[np.intp],
    frames: NDArray[np.intp],
    k: int,
    area_weight: float,
    margin_mm: float,
) -> NDArray[np.bool_]:
    """Whether, in each of ``frames`` (``k`` regions each), the overlap pairing is the cheapest."""
    local = np.arange(k)
    cur = starts[frames][:, None] + local  # (F, k) this frame's regions
    before = starts[frames - 1][:, None] + local  # (F, k) the frame before's
    chosen = previous[cur] - starts[frames - 1][:, None]  # (F, k) the pairing, local
    c = regions.centre_mm
    dist = np.hypot(*(c[cur][:, :, None, :] - c[before][:, None, :, :]).transpose(3, 0, 1, 2))
    root = np.sqrt(regions.area_mm2)
    cost = dist + area_weight * np.abs(root[cur][:, :, None] - root[before][:, None, :])
    perms = np.array(list(itertools.permutations(range(k))), dtype=np.intp)  # (k!, k)
    totals = cost[:, local[None, :], perms].sum(axis=2)  # (F, k!)
    mine = (perms[None, :, :] == chosen[:, None, :]).all(axis=2)
    own = np.where(mine, totals, 0.0).sum(axis=1)
    others = np.where(mine, np.inf, totals).min(axis=1)
    out: NDArray[np.bool_] = own < others - margin_mm
    return out


def _settled(tracker: RegionTracker, regions_before: int) -> bool:
    """Whether every live track took one of the ``regions_before`` regions of the last frame."""
    return len(tracker.tracks) == regions_before and all(
        tr.unseen == 0 and tr.merged_into is None for tr in tracker.tracks
    )


def track_chunk(
    tracker: RegionTracker,
    regions: Regions,
    t_s: NDArray[np.float64],
    *,
    first_frame: int,
) -> tuple[NDArray[np.intp], list[TrackEvent]]:
    """Link the regions of a chunk of frames, as ``tracker.push`` frame by frame would.

    Parameters
    ----------
    tracker : RegionTracker
        Its state after the frame before the chunk; updated in place.
    regions : Regions
        The chunk's regions, ``T`` frames.
    t_s : (T,) float, s
    first_frame : int
        Number of the chunk's first frame in the stream.

    Returns
    -------
    track_of : (n,) int
        The track of each region.
    events : list of TrackEvent
        In order.
    """
    continuing, previous, starts = continuing_frames(
        regions, area_weight=tracker.config.area_weight
    )
    n_frames = int(t_s.size)
    track_of = np.full(regions.n_regions, -1, np.intp)
    events: list[TrackEvent] = []
    stops = np.flatnonzero(~continuing)  # each run of continuing frames ends at the next
    seen = np.flatnonzero(np.diff(starts))  # frames with a region
    settled = False
    i = 0
    while i < n_frames:
        if starts[i] == starts[i + 1] and tracker.tracks:  # nothing seen, tracks alive
            at = int(np.searchsorted(seen, i))
            j = int(seen[at]) if at < seen.size else n_frames
            events.extend(_unseen(tracker, i, j, t_s, first_frame))
            settled = not tracker.tracks
            i = j
            continue
        if continuing[i] and settled:
            at = int(np.searchsorted(stops, i))
            j = int(stops[at]) if at < stops.size else n_frames
            _inherit(track_of, previous, int(starts[i - 1]), int(starts[i]), int(starts[j]))
            _carry(tracker, regions, starts, track_of, j - 1, first_frame, j - i)
            i = j
            continue
        idx = np.arange(starts[i], starts[i + 1])
        ids, found = tracker.push(
            first_frame + i,
            float(t_s[i]),
            regions.labels[i],
            idx + 1,
            regions.centre_mm[idx],
            regions.area_mm2[idx],
            regions.taxels_of(idx),
        )
        track_of[idx] = ids
        events.extend(found)
        settled = _settled(tracker, int(idx.size))
        i += 1
    return track_of, events


def _unseen(
    tracker: RegionTracker, i: int, j: int, t_s: NDArray[np.float64], first_frame: int
) -> list[TrackEvent]:
    """Frames ``i:j`` hold no region: each live track goes unseen, and dies on its turn.

    What :func:`~taxelkit.smart.tracks.step` does frame by frame (no region:
    no merge, no split): the deaths in order of frame, then of the tracks' order.
    """
    deaths: list[tuple[int, int, int]] = []
    kept = []
    for order, tr in enumerate(tracker.tracks):
        dies = i + tracker.lost_frames - tr.unseen - 1  # the frame its unseen count is reached
        if dies < j:
            deaths.append((dies, order, tr.track))
        else:
            tr.unseen += j - i
            kept.append(tr)
    tracker.tracks = kept
    return [
        TrackEvent("death", track, first_frame + f, float(t_s[f])) for f, _, track in sorted(deaths)
    ]


def _inherit(
    track_of: NDArray[np.intp], previous: NDArray[np.intp], lo: int, first: int, end: int
) -> None:
    """Regions ``first:end`` (a run of continuing frames) take the tracks of their roots.

    Each follows ``previous`` back to the frame before the run (regions
    ``lo:first``, whose tracks are known), by pointer doubling.
    """
    if end == first:
        return
    ptr = np.arange(end - lo)
    ptr[first - lo :] = previous[first:end] - lo
    while True:
        nxt = ptr[ptr]
        if np.array_equal(nxt, ptr):
            break
        ptr = nxt
    track_of[first:end] = track_of[lo + ptr[first - lo :]]


def _carry(
    tracker: RegionTracker,
    regions: Regions,
    starts: NDArray[np.intp],
    track_of: NDArray[np.intp],
    last: int,
    first_frame: int,
    count: int,
) -> None:
    """Leave each live track on its region of frame ``last``, seen in ``count`` more frames."""
    by_track = {tr.track: tr for tr in tracker.tracks}
    for r in range(int(starts[last]), int(starts[last + 1])):
        tr = by_track[int(track_of[r])]
        tr.centre_mm = regions.centre_mm[r].copy()
        tr.area_mm2 = float(regions.area_mm2[r])
        tr.taxels = regions.taxel_rc[regions.taxel_start[r] : regions.taxel_start[r + 1]]
        tr.last_frame = first_frame + last
    for tr in tracker.tracks:
        tr.frames_seen += count
