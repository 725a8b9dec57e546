"""The slip scanners' part of many open segments' feeds, computed at once (for the bank).

After each batch, a :class:`~taxelkit.smart.bank.SensorBank` feeds every
touched array's open segment its new frames; each segment's
:class:`~taxelkit.smart.slip_scan.SlipScanner` then spends most of its time on
the frames' features and on the motion between its reference and current
windows at every frame, a few dozen NumPy calls per array.
:func:`slip_inputs` computes both for all the feeds of one class and frame
rate laid end to end (as :mod:`taxelkit.smart.slip_batch` does for whole
segments), and each scanner takes its slice
(:meth:`SlipScanner.extend <taxelkit.smart.slip_scan.SlipScanner.extend>`'s
``features`` and ``decided``):

* the features are element-wise, but for a line's axis, oriented like the
  previous frame's: each feed is oriented from its own first frame, then
  turned over as a whole where that frame disagrees with the scanner's last
  axis (the axis negated, the two ends swapped: the same floats);
* each scanner's window motions run over its kept frames then the new ones;
  they are position-independent sums with the scanner's own exact fallback
  (:mod:`taxelkit.smart.slip_motion`), so every decision is the one the
  scanner makes alone (tested).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.segment_head import SlipInputs
from taxelkit.smart.slip_batch import DECISION_PIECE
from taxelkit.smart.slip_features import N_FEATURES
from taxelkit.smart.slip_scan import SlipScanner

__all__ = ["slip_inputs"]

_END1, _END2 = slice(7, 9), slice(9, 11)  # a line's two ends (slip_features' columns)


def slip_inputs(
    feeds: Sequence[tuple[SlipScanner | None, NDArray[np.float64]]],
) -> list[SlipInputs | None]:
    """The slip scanners' features and first decisions of many feeds.

    Parameters
    ----------
    feeds : sequence of (SlipScanner or None, (m, 9) float)
        Each feed's slip scanner and rows
        (:data:`~taxelkit.smart.segment_scan.ROW_COLUMNS`), before
        ``extend``. A fresh scanner has its frame rate fixed from the rows
        (:meth:`~taxelkit.smart.slip_scan.SlipScanner.prime`, which changes
        nothing else).

    Returns
    -------
    list of SlipInputs or None
        ``(features, decided)`` for each feed's ``SlipScanner.extend``; None
        where the scanner computes them itself (no scanner, an inactive
        class, a frame rate not yet fixed, or the per-frame reference scan).
    """
    out: list[SlipInputs | None] = [None] * len(feeds)
    groups: dict[tuple[int, int, int, float], list[int]] = {}
    for s, (scanner, rows) in enumerate(feeds):
        if scanner is None or scanner.reference or not rows.shape[0]:
            continue
        if not scanner.prime(rows[:, 8]):  # a new segment's rate is fixed from these rows
            continue
        groups.setdefault((scanner.cls, scanner.cur, scanner.ref, scanner.length_mm), []).append(s)
    for members in groups.values():
        scanners = [feeds[s][0] for s in members]
        for s, inputs in zip(
            members,
            _together(scanners, [feeds[s][1] for s in members]),  # type: ignore[arg-type]
            strict=True,
        ):
            out[s] = inputs
    return out


def _together(scanners: list[SlipScanner], rows: list[NDArray[np.float64]]) -> list[SlipInputs]:
    """Inputs of ready scanners of one class and window lengths, fed ``rows`` each."""
    first = scanners[0]
    c, r = first.cur, first.ref
    lengths = np.array([x.shape[0] for x in rows], dtype=np.intp)
    starts = np.zeros(lengths.size, np.intp)
    np.cumsum(lengths[:-1], out=starts[1:])
    feats, u = first.segment_features(np.concatenate(rows), starts)
    if u is not None:
        _orient(feats, u, starts, lengths, [s.last_axis for s in scanners])
    # each scanner's kept frames, then its new ones: the window motions over them all
    kept = [s.kept_features for s in scanners]
    pieces: list[NDArray[np.float64]] = []
    for s, held in enumerate(kept):
        pieces += [held, feats[starts[s] : starts[s] + lengths[s]]]
    x = np.concatenate(pieces) if pieces else np.zeros((0, N_FEATURES))
    count = x.shape[0] - c - r + 1
    changed = above = np.zeros(0, bool)
    if count > 0:
        changed, above = first.decisions(
            x, 0, r, r, c, count, first._limit_mm, piece=DECISION_PIECE
        )
    out: list[SlipInputs] = []
    g = 0  # where the scanner's kept frames begin in x
    for s, held in enumerate(kept):
        n_old, n = held.shape[0], held.shape[0] + int(lengths[s])
        p0 = max(n_old, c + r - 1)  # as SlipScanner._scan_chunk
        k0 = g + p0 - c - r + 1
        own = max(0, n - p0)
        a, b = int(starts[s]), int(starts[s] + lengths[s])
        out.append(
            (
                (feats[a:b], None if u is None else u[b - 1].copy()),
                (changed[k0 : k0 + own], above[k0 : k0 + own]),
            )
        )
        g += n
    return out


def _orient(
    feats: NDArray[np.float64],
    u: NDArray[np.float64],
    starts: NDArray[np.intp],
    lengths: NDArray[np.intp],
    last: list[NDArray[np.float64] | None],
) -> None:
    """Turn over, in place, the feeds whose first axis disagrees with their scanner's last one.

    ``feats`` ``(m, 15)`` and ``u`` ``(m, 2)`` are :func:`slip_features` of
    the feeds laid end to end, each oriented from its own first frame;
    ``last``: each scanner's last oriented axis (None: a new segment).
    """
    have = [s for s, v in enumerate(last) if v is not None]
    if not have:
        return
    prev = np.stack([last[s] for s in have])  # type: ignore[misc]
    firsts = u[starts[have]]
    # the comparison slip_features makes on the frame after ``prev``
    flip = np.flatnonzero(np.einsum("ij,ij->i", firsts, prev) < 0.0)
    for k in flip.tolist():
        s = have[k]
        a, b = int(starts[s]), int(starts[s] + lengths[s])
        u[a:b] *= -1.0
        feats[a:b, _END1], feats[a:b, _END2] = feats[a:b, _END2].copy(), feats[a:b, _END1].copy()
