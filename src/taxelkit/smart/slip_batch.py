"""Slip scanners of many whole segments at once (the batch paths' slip detection).

A :class:`~taxelkit.smart.slip_scan.SlipScanner` fed a whole segment spends
most of its time on the segment's features and on the motion between its
reference and current windows at every frame, a few dozen NumPy calls each.
:func:`batch_slip_scanners` computes both for many segments laid end to end
(one class and one frame rate: the same window lengths) and hands each
scanner its slice, so that the calls are made once per batch. The features
are element-wise (a line's axis orientation restarts at each segment); the
window motions are position-independent sums with the scanner's own exact
fallback (:mod:`taxelkit.smart.slip_motion`), so every decision, and hence
every slip, is the one the scanner makes alone (tested).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.slip import SlipConfig
from taxelkit.smart.slip_scan import SlipScanner

__all__ = ["batch_slip_scanners"]

#: Frames of all segments scanned together.
PIECE_ROWS = 32768
#: Frames whose window motions are computed in one pass (their sums stay in the cache).
DECISION_PIECE = 4096


def batch_slip_scanners(
    items: Sequence[tuple[int, NDArray[np.intp], NDArray[np.float64]]],
    config: SlipConfig,
    *,
    k: int,
    pitch_mm: Sequence[float] | float = 0.0,
) -> list[SlipScanner]:
    """Scanners of whole segments, each extended by all its frames.

    Parameters
    ----------
    items : sequence of (int, (n,) int, (n, 9) float)
        Each segment's contact class, frames and rows
        (:data:`~taxelkit.smart.segment_scan.ROW_COLUMNS`).
    config : SlipConfig
    k : int
        The debounce count (as :class:`~taxelkit.smart.slip_scan.SlipScanner`).
    pitch_mm : float or sequence of float
        Taxel pitch, mm (0: unknown): one for all segments, or one each.

    Returns
    -------
    list of SlipScanner
        ``SlipScanner(cls, config, k=k, pitch_mm=pitch)`` after
        ``extend(frames, rows)``, one per item.
    """
    pitches = np.broadcast_to(np.asarray(pitch_mm, dtype=np.float64), (len(items),)).tolist()
    scanners = [
        SlipScanner(cls, config, k=k, pitch_mm=p)
        for (cls, _, _), p in zip(items, pitches, strict=True)
    ]
    groups: dict[tuple[int, int, int, float], list[int]] = {}
    for i, (scanner, (_, frames, rows)) in enumerate(zip(scanners, items, strict=True)):
        if frames.size and scanner.prime(rows[:, 8]):
            key = (scanner.cls, scanner.cur, scanner.ref, scanner.length_mm)
            groups.setdefault(key, []).append(i)
        else:
            scanner.extend(frames, rows)
    for (_, cur, ref, _), members in groups.items():
        part: list[int] = []
        rows_in = 0
        for i in members:
            part.append(i)
            rows_in += items[i][1].size
            if rows_in >= PIECE_ROWS:
                _scan_together([scanners[j] for j in part], [items[j] for j in part], cur, ref)
                part, rows_in = [], 0
        if part:
            _scan_together([scanners[j] for j in part], [items[j] for j in part], cur, ref)
    return scanners


def _scan_together(
    scanners: list[SlipScanner],
    items: list[tuple[int, NDArray[np.intp], NDArray[np.float64]]],
    cur: int,
    ref: int,
) -> None:
    """Extend primed scanners of one class and window lengths by their whole segments."""
    lengths = np.array([frames.size for _, frames, _ in items], dtype=np.intp)
    starts = np.zeros(lengths.size, np.intp)
    np.cumsum(lengths[:-1], out=starts[1:])
    rows = np.concatenate([r for _, _, r in items])
    first = scanners[0]
    feats, u = first.segment_features(rows, starts)
    # the first scan's decisions: reference windows at each row, current windows after them
    n = rows.shape[0]
    count = n - cur - ref + 1
    changed = above = np.zeros(0, bool)
    if count > 0:
        changed, above = first.decisions(
            feats, 0, ref, ref, cur, count, first._limit_mm, piece=DECISION_PIECE
        )
    for s, (scanner, (_, frames, seg_rows)) in enumerate(zip(scanners, items, strict=True)):
        a, b = int(starts[s]), int(starts[s] + lengths[s])
        own = max(0, b - a - cur - ref + 1)  # frames with a full reference, in the segment
        scanner.extend(
            frames,
            seg_rows,
            features=(feats[a:b], None if u is None else u[b - 1].copy()),
            decided=(changed[a : a + own], above[a : a + own]),
        )
