"""Per-segment scans of many segments laid end to end: exact running sums, first hits.

Level 3 looks at every contact segment on its own: running means over a
segment's frames, the first frame at which a condition has held for ``k``
frames. :class:`Runs` holds many segments concatenated (segment ``s`` is
rows ``starts[s] .. starts[s] + lengths[s] - 1``) and computes the same
quantities for all of them with a few NumPy calls. A running sum is
accumulated segment by segment (one call each, the only per-segment cost),
in the same order of additions as ``np.cumsum`` over that segment alone, so
every float is the one of the per-segment form.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["Runs"]


class Runs:
    """Segments of given lengths, concatenated.

    Parameters
    ----------
    lengths : (S,) int
        Rows of each segment (at least 1).

    Attributes
    ----------
    starts : (S,) int
        First row of each segment.
    seg : (N,) int
        Segment of each row.
    local : (N,) int
        Index of each row within its segment.
    """

    def __init__(self, lengths: NDArray[np.intp]) -> None:
        self.lengths = np.asarray(lengths, dtype=np.intp)
        self.size = int(self.lengths.sum())
        self.starts = np.zeros(self.lengths.size, np.intp)
        np.cumsum(self.lengths[:-1], out=self.starts[1:])
        self.seg = np.repeat(np.arange(self.lengths.size), self.lengths)
        self.local = np.arange(self.size) - self.starts[self.seg]
        ends = self.starts + self.lengths
        self._bounds = list(zip(self.starts.tolist(), ends.tolist(), strict=True))

    def cumsum(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``np.cumsum(x_s, axis=0)`` of every segment ``x_s`` of ``x`` ``(N, ...)``, end to end.

        One accumulation per segment, row after row (each column's sums in
        order, as along a column alone): the segments' sums never mix, so the
        floats are those of each segment alone.
        """
        rows = x.reshape(x.shape[0], -1)  # (N, F)
        out = np.empty_like(rows)
        for a, b in self._bounds:
            np.cumsum(rows[a:b], axis=0, out=out[a:b])
        result: NDArray[np.float64] = out.reshape(x.shape)
        return result

    def cummax(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``np.maximum.accumulate`` of every segment of ``x`` ``(N,)``, end to end (exact)."""
        out = np.empty_like(x)
        for a, b in self._bounds:
            np.maximum.accumulate(x[a:b], out=out[a:b])
        return out

    def rolling_mean(self, x: NDArray[np.float64], w: int) -> NDArray[np.float64]:
        """:func:`~taxelkit.smart.track_geometry.rolling_mean` of every segment of ``x``."""
        c = self.cumsum(x)  # laid out as x (columns contiguous stay so)
        shape = (-1,) + (1,) * (x.ndim - 1)
        back = np.zeros_like(c)  # the sum w rows back
        if w < c.shape[0]:
            back[w:] = c[: c.shape[0] - w]
        # rows less than w into their segment keep their sum (less 0.0: the same float)
        out = c - np.where((self.local >= w).reshape(shape), back, 0.0)
        n = np.minimum(self.local + 1, w).reshape(shape)
        result: NDArray[np.float64] = out / n
        return result

    def sustained(
        self,
        mask: NDArray[np.bool_],
        k: int,
        frames: NDArray[np.intp] | None = None,
        min_rows: int = 1,
    ) -> NDArray[np.bool_]:
        """:func:`~taxelkit.smart.track_geometry.sustained` of every segment of ``mask``.

        ``frames`` ``(N,)``: the rows' frame numbers (a run holds once it spans
        ``k`` frames of the recording and ``min_rows`` rows); None: ``k`` rows.
        """
        if frames is not None:
            idx = np.arange(self.size)
            z = np.where(mask, 0, idx + 1)
            z[self.starts] = np.where(mask[self.starts], self.starts, self.starts + 1)
            first_row = np.minimum(np.maximum.accumulate(z), max(self.size - 1, 0))
            spans: NDArray[np.bool_] = (
                mask & (frames - frames[first_row] + 1 >= k) & (idx - first_row + 1 >= min_rows)
            )
            return spans
        c = np.cumsum(mask, dtype=np.int64)  # integers: exact whatever came before
        base = np.zeros(self.lengths.size, np.int64)
        base[1:] = c.take(self.starts[1:] - 1)
        back = np.zeros_like(c)  # the count k rows back (0 before the first row)
        if k < c.size:
            back[k:] = c[: c.size - k]
        before = np.where(self.local >= k, back, base.take(self.seg))
        out: NDArray[np.bool_] = (c - before) >= k
        return out

    def first(self, mask: NDArray[np.bool_]) -> NDArray[np.intp]:
        """Index within its segment of each segment's first True row of ``mask``; -1 if none."""
        hits = np.flatnonzero(mask)
        out = np.full(self.lengths.size, -1, np.intp)
        if hits.size:
            segs = self.seg[hits]
            lead = np.ones(hits.size, bool)
            lead[1:] = segs[1:] != segs[:-1]
            out[segs[lead]] = self.local[hits[lead]]
        return out

    def first_sustained(
        self,
        mask: NDArray[np.bool_],
        k: int,
        frames: NDArray[np.intp] | None = None,
        min_rows: int = 1,
    ) -> NDArray[np.intp]:
        """``first(sustained(mask, k, frames, min_rows), 0)`` of every segment (-1 for None)."""
        return self.first(self.sustained(mask, k, frames, min_rows))


def _spans(lengths: NDArray[np.intp]) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Segment and index within it of each row of spans ``lengths`` ``(S,)`` (0 allowed)."""
    seg = np.repeat(np.arange(lengths.size), lengths)
    first = np.cumsum(lengths) - lengths
    return seg, np.arange(seg.size) - first[seg]


def run_anchors(
    runs: Runs,
    area: NDArray[np.float64],
    elongation: NDArray[np.float64],
    k: int,
    tolerance: float,
) -> NDArray[np.intp]:
    """:func:`~taxelkit.smart.track_geometry.anchors` of every segment, ``(N,)`` local indices.

    The per-segment search, one anchor of every segment at a time: a round
    compares the rows after each segment's reference with it (the same
    divisions as the per-segment form) and moves its anchor to the first
    that departs; segments hold a few anchors, so the rounds are few.
    """
    starts, lengths = runs.starts, runs.lengths
    out = np.empty(runs.size, np.intp)
    active = np.arange(lengths.size)
    a = np.zeros(lengths.size, np.intp)  # each active segment's anchor
    while active.size:
        st, n = starts[active], lengths[active]
        r = np.minimum(a + k - 1, n - 1)  # the anchor's reference
        seg, local = _spans(n - r - 1)  # the rows after it
        rows = (st + r + 1)[seg] + local
        ref = (st + r)[seg]
        dev = (np.abs(area.take(rows) / area.take(ref) - 1.0) > tolerance) | (
            np.abs(elongation.take(rows) / elongation.take(ref) - 1.0) > tolerance
        )
        hits = np.flatnonzero(dev)
        nxt = n.copy()
        if hits.size:
            lead = np.ones(hits.size, bool)
            lead[1:] = seg[hits[1:]] != seg[hits[:-1]]
            first = hits[lead]
            nxt[seg[first]] = r[seg[first]] + 1 + local[first]
        fill_seg, fill_local = _spans(nxt - a)
        out[(st + a)[fill_seg] + fill_local] = a[fill_seg]
        more = nxt < n
        active, a = active[more], nxt[more]
    return out
