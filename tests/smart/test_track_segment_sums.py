"""Whole segments' centres, line lengths and rates from the batch: the floats of each alone."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.tactemes import SegmentTrack, TactemeConfig
from taxelkit.smart.track_segment import TrackSegment, track_segments

from .test_slip_vectorised import random_segment


def _track(rng: np.random.Generator, n: int, scale: float, measured: bool) -> SegmentTrack:
    rows = random_segment(rng, n, 60.0, line=True)
    rows[:, 0:2] *= scale  # centres far from and near the origin
    ext = rows[:, 6:8].copy() if measured else None
    if ext is not None:
        ext[rng.random(n) < 0.3] = np.nan  # extents not measured in some frames
    t_s = np.cumsum(rng.uniform(0.01, 0.03, n))
    return SegmentTrack(
        np.arange(n) + 5,
        rows[:, 0:2],
        rows[:, 2],
        rows[:, 3],
        rows[:, 4],
        rows[:, 5],
        t_s,
        ext,
        pitch_mm=float(rng.choice([0.0, 1.7625])),
    )


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    sizes=st.lists(st.integers(1, 300), min_size=1, max_size=6),
    scale=st.sampled_from([1e-3, 1.0, 37.0, 1e4]),
)
def test_batch_centres_lengths_and_rates_equal_each_segment_alone(
    seed: int, sizes: list[int], scale: float
) -> None:
    rng = np.random.default_rng(seed)
    config = TactemeConfig()
    line = int(ContactClass.LINE)
    tracks = [_track(rng, n, scale, bool(rng.random() < 0.7)) for n in sizes]
    batch = track_segments([(line, t, None) for t in tracks], config)
    for seg, track in zip(batch, tracks, strict=True):
        alone = TrackSegment(line, track, config)
        for stop in (1, 2, 3, 7, 64, seg.size, seg.size + 5):
            assert seg.mean_centre_mm(stop) == alone.mean_centre_mm(stop)
            c = track.centre_mm[:stop].mean(axis=0)  # the rule as written
            assert seg.mean_centre_mm(stop) == (float(c[0]), float(c[1]))
            assert seg.grid_wobble_deg(stop) == alone.grid_wobble_deg(stop)
        for seconds in (0.0, 0.05, 0.3, 1.0):
            for k in (2, 3, 5):
                got = seg.frames_for(seconds, k)
                assert got == seg.frames_for(seconds, k) == track.frames_for(seconds, k)
                assert seg.frames_for(seconds, k, minimum=1) == track.frames_for(
                    seconds, k, minimum=1
                )
