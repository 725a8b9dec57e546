"""Per-segment scans of many segments laid end to end: exact running sums, first hits.

Level 3 looks at every contact segment on its own: running means over a
segment's frames, the first frame at which a condition has held for ``k``
frames. :class:`Runs` holds many segments concatenated (segment ``s`` is
rows ``starts[s] .. starts[s] + lengths[s] - 1``) and computes the same
quantities for all of them with a few NumPy calls. A running sum is
computed segment by segment in the same order of additions as
``np.cumsum`` over that segment alone (the segments side by side in a
padded block, summed along it), so every float is the one of the
per-segment form.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

__all__ = ["Runs"]

#: A padded block of segments may hold this many times the rows it uses...
_PAD_WASTE = 2.0
#: ... or this many unused rows (about the cost of one more block's NumPy calls).
_PAD_SLACK = 8192


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
        self._blocks = self._padding()

    def _padding(self) -> list[tuple[NDArray[np.intp], NDArray[np.bool_], NDArray[np.intp]]]:
        """Blocks of segments of similar lengths: rows ``(m, L)``, validity, valid rows."""
        order = np.argsort(self.lengths, kind="stable")
        lengths = self.lengths[order].tolist()
        blocks = []
        a = 0
        while a < len(order):
            b, used = a, 0
            while b < len(order):
                padded, fill = lengths[b] * (b - a + 1), used + lengths[b]
                if padded > _PAD_WASTE * fill and padded - fill > _PAD_SLACK:
                    break
                used += lengths[b]
                b += 1
            b = max(b, a + 1)
            segs = order[a:b]
            span = np.arange(lengths[b - 1])[None, :]
            valid = span < self.lengths[segs][:, None]
            rows = np.where(valid, self.starts[segs][:, None] + span, 0)
            blocks.append((rows, valid, rows[valid]))
            a = b
        return blocks

    def _padded(
        self, x: NDArray[np.float64], step: Callable[[NDArray[np.float64]], NDArray[np.float64]]
    ) -> NDArray[np.float64]:
        """``step`` applied along the last axis of each block ``(F, m, L)`` of ``x`` ``(N, F)``.

        The rows past a segment's end hold other rows' values: a running sum
        along a segment never reaches them.
        """
        xt = np.ascontiguousarray(x.reshape(x.shape[0], -1).T)  # (F, N): each sum runs along memory
        out = np.empty_like(xt)
        for rows, valid, inside in self._blocks:
            out[:, inside] = step(xt[:, rows])[:, valid]
        result: NDArray[np.float64] = out.T.reshape(x.shape)
        return result

    def cumsum(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """``np.cumsum(x_s, axis=0)`` of every segment ``x_s`` of ``x`` ``(N, ...)``, end to end."""
        return self._padded(x, lambda block: np.cumsum(block, axis=-1))

    def rolling_mean(self, x: NDArray[np.float64], w: int) -> NDArray[np.float64]:
        """:func:`~taxelkit.smart.track_geometry.rolling_mean` of every segment of ``x``."""

        def mean(block: NDArray[np.float64]) -> NDArray[np.float64]:
            c = np.cumsum(block, axis=-1)
            out = c.copy()
            out[..., w:] -= c[..., :-w]
            result: NDArray[np.float64] = out / np.minimum(np.arange(1, c.shape[-1] + 1), w)
            return result

        return self._padded(x, mean)

    def sustained(self, mask: NDArray[np.bool_], k: int) -> NDArray[np.bool_]:
        """:func:`~taxelkit.smart.track_geometry.sustained` of every segment of ``mask``."""
        c = np.cumsum(mask.astype(np.int64))  # integers: exact whatever came before
        base = np.zeros(self.lengths.size, np.int64)
        base[1:] = c[self.starts[1:] - 1]
        back = np.maximum(np.arange(self.size) - k, 0)
        before = np.where(self.local >= k, c[back], base[self.seg])
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

    def first_sustained(self, mask: NDArray[np.bool_], k: int) -> NDArray[np.intp]:
        """``first(sustained(mask, k), 0)`` of every segment (-1 for None)."""
        return self.first(self.sustained(mask, k))
