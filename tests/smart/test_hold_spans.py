"""Holds count the recording's frames a verdict spans (``TactemeConfig.hold_spans_gaps``)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.segment_runs import Runs
from taxelkit.smart.segment_scan import SegmentScanner
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.tactemes import PAPER_LEVEL3, SegmentTrack, TactemeConfig, segment_tactemes
from taxelkit.smart.tactemes_batch import batch_tactemes
from taxelkit.smart.track_geometry import first, sustained
from taxelkit.smart.track_stream import Sustained


def gappy_frames(rng: np.random.Generator, n: int) -> np.ndarray:
    """``n`` increasing frame numbers with random gaps (frames a segment left out)."""
    return 100 + np.cumsum(rng.choice([1, 1, 1, 2, 4, 9], n))


def test_a_run_holds_once_it_spans_the_frames_the_segment_left_out() -> None:
    mask = np.array([True, True, True, False, True, True])
    frames = np.array([10, 14, 18, 19, 20, 30])
    # rows 0-2 span frames 10-18: 9 frames; row 2 is the first to span 9
    np.testing.assert_array_equal(
        sustained(mask, 9, frames), [False, False, True, False, False, True]
    )
    np.testing.assert_array_equal(sustained(mask, 3), [False, False, True, False, False, False])
    assert first(sustained(mask, 12, frames), 0) is None  # the run broke at frame 19
    # and seen on at least min_rows of the segment's rows
    np.testing.assert_array_equal(
        sustained(mask, 9, frames, min_rows=3), [False, False, True, False, False, False]
    )


@pytest.mark.parametrize("seed", range(10))
def test_on_consecutive_frames_spans_are_counts(seed: int) -> None:
    rng = np.random.default_rng(seed)
    n, k = int(rng.integers(1, 300)), int(rng.integers(1, 30))
    mask = rng.random(n) < rng.uniform(0.3, 0.95)
    frames = 7 + np.arange(n)
    np.testing.assert_array_equal(sustained(mask, k, frames), sustained(mask, k))
    runs = Runs(np.array([n]))
    np.testing.assert_array_equal(runs.sustained(mask, k, frames), sustained(mask, k))


@pytest.mark.parametrize("seed", range(10))
def test_segments_end_to_end_and_streamed_chunks_hold_where_each_alone_does(seed: int) -> None:
    rng = np.random.default_rng(seed)
    lengths = rng.integers(1, 120, int(rng.integers(1, 8)))
    k, min_rows = int(rng.integers(1, 25)), int(rng.integers(1, 6))
    masks = [rng.random(n) < rng.uniform(0.4, 0.97) for n in lengths.tolist()]
    frames = [gappy_frames(rng, n) for n in lengths.tolist()]
    runs = Runs(lengths)
    together = runs.sustained(np.concatenate(masks), k, np.concatenate(frames), min_rows)
    alone = [sustained(m, k, f, min_rows) for m, f in zip(masks, frames, strict=True)]
    np.testing.assert_array_equal(together, np.concatenate(alone))
    for m, f, hits in zip(masks, frames, alone, strict=True):
        want = first(hits, 0)
        cuts = sorted(set(rng.integers(0, m.size + 1, 5).tolist()))
        stream = Sustained(k, spans=True, min_rows=min_rows)
        got = None
        for a, b in zip([0, *cuts], [*cuts, m.size], strict=True):
            got = stream.push(m[a:b], f[a:b])
        assert got == (None if want is None else int(f[want]))


def rolling_line_with_gaps(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Frames and rows (ROW_COLUMNS) of a line rolling across itself at 60 frames/s,
    seen on about one frame in three (the others left out of its segment)."""
    n_all = 240
    keep = np.flatnonzero(rng.random(n_all) < 0.33)
    keep = np.union1d(keep, np.arange(6))  # its first frames fix the rate
    j = keep.astype(float)
    rows = np.zeros((keep.size, 9))
    rows[:, 1] = np.maximum(j - 15, 0) * 3.0 / 60.0  # 3 mm/s across itself
    rows[:, 2] = rng.normal(0, 0.3, keep.size)
    rows[:, 3] = 38.0
    rows[:, 4] = 6.0
    rows[:, 5] = 5.0
    rows[:, 6], rows[:, 7] = -5.5, 5.5
    rows[:, 8] = j / 60.0
    return keep, rows


def three_paths(frames: np.ndarray, rows: np.ndarray, cfg: TactemeConfig) -> list:
    """A line's tactemes per track, in the batch and streamed (asserted equal)."""
    track = SegmentTrack(
        frames, rows[:, 0:2], rows[:, 2], rows[:, 3], rows[:, 4], rows[:, 5], rows[:, 8],
        rows[:, 6:8], 1.7625,
    )  # fmt: skip
    cls = int(ContactClass.LINE)
    want = segment_tactemes(cls, track, cfg)
    assert batch_tactemes([(cls, track)], cfg) == [want]
    for step in (1, 7, frames.size):
        scan = SegmentScanner(cls, cfg, 1.7625)
        got = [
            x
            for a in range(0, frames.size, step)
            for x in scan.extend(frames[a : a + step], rows[a : a + step])
        ]
        assert got + scan.close() == want, step
    return want


@pytest.mark.parametrize("seed", range(4))
def test_a_line_seen_on_one_frame_in_three_reads_parallel_after_its_hold_in_time(
    seed: int,
) -> None:
    frames, rows = rolling_line_with_gaps(np.random.default_rng(seed))
    cfg = TactemeConfig()
    spans = dict(three_paths(frames, rows, cfg))
    counts = dict(three_paths(frames, rows, dataclasses.replace(cfg, hold_spans_gaps=False)))
    # a motion holds on as many rows as before (its hold is the least evidence asked)
    assert spans[Tacteme.LCM] == counts[Tacteme.LCM]
    # LCMP holds 0.3 s (18 frames at 60 frames/s) on at least a motion's 9 rows: about
    # 27 frames here, where 18 of the segment's rows spanned about 54
    assert Tacteme.LCMP in spans and Tacteme.LCMP in counts
    assert counts[Tacteme.LCMP] >= spans[Tacteme.LCMP] + 12
    assert PAPER_LEVEL3.hold_spans_gaps is False


@pytest.mark.parametrize("rate_hz", [20.0, 240.0])
def test_recorded_segments_with_gaps_stream_as_they_batch(
    rate_hz: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    from taxelkit.smart.segment_scan import rows_from_track

    from .test_level3_batch import recorded_segments

    items = recorded_segments(range(2), rate_hz, monkeypatch)
    gappy = [(c, t) for c, t in items if t.frames.size > 1 and np.any(np.diff(t.frames) > 1)]
    assert len(gappy) >= 3  # segments that left frames out
    cfg = TactemeConfig()
    rows_count = dataclasses.replace(cfg, hold_spans_gaps=False)
    # some segment's tactemes move with the holds (1 at 20 frames/s, 2 at 240)
    assert any(segment_tactemes(c, t, cfg) != segment_tactemes(c, t, rows_count) for c, t in gappy)
    for cls, track in gappy:
        want = segment_tactemes(cls, track, cfg)
        rows = rows_from_track(track)
        for step in (5, 64):
            scan = SegmentScanner(cls, cfg, track.pitch_mm)
            got = [
                x
                for a in range(0, track.frames.size, step)
                for x in scan.extend(track.frames[a : a + step], rows[a : a + step])
            ]
            assert sorted(got + scan.close(), key=lambda x: x[1]) == want
