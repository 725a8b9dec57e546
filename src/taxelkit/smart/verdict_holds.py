"""A verdict held through brief dropouts: bridging short gaps before it is sustained.

A pivot verdict must hold for ``pivot_hold_s``. At high frame rates a
flickering taxel next to the line spoils one frame's line now and then (at
240 frames/s, one frame in 20-50 with 0.5 % of the taxels flickering), and a
run that must hold 120 frames in a row never does. Rows where the verdict
does not read, between two rows where it does and no more than ``gap``
rows long, are bridged: they count toward the run, but the verdict is
reported only on a row where it reads (so the streamed rule, which cannot
see past its last row, decides as the batch rule does).

:func:`bridge_gaps` is the batch form (for one segment or for many laid end
to end); :class:`Sustained` the streamed one, equal to
``first(sustained(bridge_gaps(mask, gap), k, frames, min_rows) & mask)``
whatever the chunks (tested). With ``gap`` 0 both are the plain rule, and
:class:`Sustained` is the streamed hold of every Level 3 motion
(:mod:`taxelkit.smart.track_stream` re-exports it).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = ["Sustained", "bridge_gaps", "gap_rows"]


def gap_rows(frame_interval_s: float, seconds: float) -> int:
    """Whole frames within ``seconds`` at the frame interval (0 if it is unknown)."""
    if frame_interval_s <= 0 or seconds <= 0:
        return 0
    return math.floor(seconds / frame_interval_s + 1e-9)


def bridge_gaps(
    mask: NDArray[np.bool_],
    gap: int | NDArray[np.intp],
    segment: NDArray[np.intp] | None = None,
) -> NDArray[np.bool_]:
    """``mask`` with every run of False rows of at most ``gap`` rows between two True rows set.

    Parameters
    ----------
    mask : (n,) bool
    gap : int or (n,) int
        Longest gap bridged, rows; per row, the gap after that row is read
        at its True row before it.
    segment : (n,) int, optional
        Segment of each row (segments laid end to end): no gap is bridged
        across two segments.

    Returns
    -------
    (n,) bool
        ``mask`` itself where nothing is bridged.
    """
    t = np.flatnonzero(mask)
    if t.size < 2 or (np.ndim(gap) == 0 and int(gap) <= 0):
        return mask
    before, after = t[:-1], t[1:]
    limit = gap if np.ndim(gap) == 0 else np.asarray(gap)[before]
    missing = after - before - 1
    sel = (missing > 0) & (missing <= limit)
    if segment is not None:
        sel &= segment[before] == segment[after]
    if not np.any(sel):
        return mask
    delta = np.zeros(mask.size + 1, np.int64)
    delta[before[sel] + 1] += 1  # the bridged runs are disjoint: no index twice
    delta[after[sel]] -= 1
    out: NDArray[np.bool_] = mask | (np.cumsum(delta[:-1]) > 0)
    return out


class Sustained:
    """The first row where a mask arriving in chunks has held, bridging gaps of ``gap`` rows.

    ``first(sustained(bridge_gaps(mask, gap), k, frames, min_rows) & mask)``
    of :func:`~taxelkit.smart.track_geometry.sustained`, fed a chunk at a
    time: the open run's rows, its first frame and the False rows since its
    last True row are carried.

    Parameters
    ----------
    k : int
        Rows (or, with ``spans``, frames of the recording) the mask must hold.
    spans : bool
        The run must span ``k`` of the frames numbered, those left out
        between its rows counted, and ``min_rows`` rows.
    min_rows : int
    gap : int
        Longest run of False rows bridged (0: the plain rule).
    """

    def __init__(self, k: int, spans: bool = False, min_rows: int = 1, gap: int = 0) -> None:
        self.k, self.spans, self.min_rows, self.gap = int(k), spans, int(min_rows), int(gap)
        self.found: int | None = None
        self.reset()

    def reset(self) -> None:
        """No run is open."""
        self.run = 0  # rows of the open run (bridged rows counted); 0: none open
        self.start = -1  # with spans: the number of the open run's first row
        self.since = 0  # False rows since the open run's last True row

    def push(self, mask: NDArray[np.bool_], index: NDArray[np.intp]) -> int | None:
        """Feed the mask of rows numbered ``index``; return the first hit's number (kept)."""
        m = int(mask.size)
        if self.found is not None or m == 0:
            return self.found
        t = np.flatnonzero(mask)
        if t.size == 0:
            self.since += m
            if self.since > self.gap:
                self.reset()
            return None
        # each True row's run: it continues the one before it across at most `gap` rows
        prev = np.empty(t.size, np.int64)
        prev[1:] = t[:-1]
        prev[0] = -1 - self.since if self.run else -(self.gap + 2) - m  # none open: too far
        new = t - prev - 1 > self.gap
        head = np.maximum.accumulate(np.where(new, np.arange(t.size), 0))  # the run's first
        carried = ~new[0] & (head == 0)  # runs on from before this chunk
        first_pos = t[head]
        rows = np.where(carried, self.run + self.since + t + 1, t - first_pos + 1)
        if self.spans:
            first_no = np.where(carried, self.start, index[first_pos])
            held = (index[t] - first_no + 1 >= self.k) & (rows >= self.min_rows)
        else:
            held = rows >= self.k
        hits = np.flatnonzero(held)
        if hits.size:
            self.found = int(index[t[hits[0]]])
        self.run = int(rows[-1])
        if self.spans:
            self.start = int(first_no[-1])
        self.since = m - 1 - int(t[-1])
        if self.since > self.gap:
            self.reset()
        return self.found
