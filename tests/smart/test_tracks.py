"""The region tracker: assignment by position and area, births, deaths, merges, splits."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.smart.regions import segment_frames
from taxelkit.smart.tracks import (
    LiveTrack,
    RegionTracker,
    TrackerConfig,
    TrackEvent,
    _near_enough,
    _nearest,
)


def track(images: np.ndarray, lost_frames: int = 3) -> tuple[list[list[int]], list[TrackEvent]]:
    reg = segment_frames(images, pitch_mm=1.0)
    tracker = RegionTracker(pitch_mm=1.0, lost_frames=lost_frames)
    per_frame: list[list[int]] = []
    events: list[TrackEvent] = []
    for t in range(images.shape[0]):
        idx = reg.in_frame(t)
        ids, ev = tracker.push(
            t, 0.05 * t, reg.labels[t], idx + 1, reg.centre_mm[idx], reg.area_mm2[idx]
        )
        per_frame.append(ids.tolist())
        events.extend(ev)
    return per_frame, events


def test_two_blobs_crossing_the_gate_keep_their_tracks() -> None:
    img = np.zeros((12, 20, 20), bool)
    for t in range(12):
        img[t, 2:4, 2 + t // 2 : 4 + t // 2] = True  # moving right, half a taxel a frame
        img[t, 14:17, 14 - t // 2 : 17 - t // 2] = True  # a bigger one moving left
    ids, events = track(img)
    assert all(frame == [0, 1] for frame in ids)
    assert [(e.kind, e.track, e.frame) for e in events] == [("birth", 0, 0), ("birth", 1, 0)]


def test_a_lifted_object_put_down_again_is_a_new_track() -> None:
    img = np.zeros((14, 10, 10), bool)
    img[0:4, 4:6, 4:6] = True
    img[5:6, 4:6, 4:6] = True  # one frame back after one frame away: the same track
    img[9:14, 4:6, 4:6] = True  # back after three frames: a new one
    ids, events = track(img, lost_frames=3)
    assert ids[5] == [0] and ids[9] == [1]
    kinds = [(e.kind, e.track, e.frame) for e in events]
    assert kinds == [("birth", 0, 0), ("death", 0, 8), ("birth", 1, 9)]
    assert events[1].t_s == pytest.approx(0.4)


def test_merges_and_splits_are_events_and_the_merged_track_comes_back() -> None:
    gaps = [6, 5, 4, 3, 2, 1, 0, 0, 1, 2, 3, 4, 5]  # missing taxels between the two contacts
    img = np.zeros((len(gaps), 10, 24), bool)
    for t, gap in enumerate(gaps):
        img[t, 4:6, 4:8] = True
        img[t, 4:6, 8 + gap : 12 + gap] = True
    ids, events = track(img, lost_frames=8)
    kinds = [(e.kind, e.track, e.frame, e.other) for e in events]
    # two missing taxels or fewer: one region (the merge gap is three pitches)
    assert kinds == [
        ("birth", 0, 0, None),
        ("birth", 1, 0, None),
        ("merge", 1, 4, 0),
        ("split", 1, 10, 0),
    ]
    assert ids[0] == [0, 1] and ids[5] == [0] and ids[10] == [0, 1]


def test_a_new_region_touching_a_track_that_took_another_is_a_split() -> None:
    img = np.zeros((6, 10, 16), bool)
    img[:, 4, 2:10] = True
    img[3:, 4, 5] = False  # the line breaks...
    img[3:, 4, 6] = False
    img[3:, 4, 7] = False  # ...into two pieces three taxels apart
    ids, events = track(img)
    assert [(e.kind, e.track, e.other) for e in events] == [("birth", 0, None), ("split", 1, 0)]
    assert ids[3] == [0, 1]


def test_a_jump_beyond_the_gate_is_a_new_track() -> None:
    img = np.zeros((4, 10, 20), bool)
    img[:2, 4:6, 2:4] = True
    img[2:, 4:6, 12:14] = True  # ten taxels away in one frame
    ids, events = track(img, lost_frames=5)
    assert [e.kind for e in events] == ["birth", "birth"]
    assert ids[2] == [1]
    wide = TrackerConfig(gate_pitches=12.0)
    reg = segment_frames(img, pitch_mm=1.0)
    tracker = RegionTracker(pitch_mm=1.0, lost_frames=5, config=wide)
    got = [
        tracker.push(t, t, reg.labels[t], i + 1, reg.centre_mm[i], reg.area_mm2[i])[0].tolist()
        for t in range(4)
        for i in [reg.in_frame(t)]
    ]
    assert got == [[0], [0], [0], [0]]


def test_bad_settings_are_refused() -> None:
    with pytest.raises(InputError, match="lost_frames"):
        RegionTracker(pitch_mm=1.0, lost_frames=0)
    with pytest.raises(InputError, match="gate_pitches"):
        TrackerConfig(gate_pitches=0.0)
    with pytest.raises(InputError, match="area_weight"):
        TrackerConfig(area_weight=-1.0)
    assert TrackerConfig(gate_pitches=3.0).gate_mm(1.5) == 4.5


@pytest.mark.parametrize("seed", range(20))
def test_the_shortcut_distances_compare_as_the_exact_ones(seed: int) -> None:
    """Shared taxels and far bounding boxes skip the taxel-by-taxel distances, unseen."""
    rng = np.random.default_rng(seed)
    img = rng.uniform(size=(2, 16, 16)) < rng.uniform(0.02, 0.2)
    reg = segment_frames(img, pitch_mm=1.0)
    before, now = reg.in_frame(0), reg.in_frame(1)
    if before.size == 0 or now.size == 0:
        pytest.skip("an empty frame")
    tracks = [
        LiveTrack(k, reg.centre_mm[r], float(reg.area_mm2[r]), reg.taxels_of(np.array([r]))[0], 0)
        for k, r in enumerate(before.tolist())
    ]
    taxels = reg.taxels_of(now)
    exact = _nearest(tracks, taxels)
    for beyond in (1.5, 3.0, 5.0):
        fast = _near_enough(tracks, taxels, reg.labels[1], now + 1, beyond)
        for limit in np.linspace(0.0, beyond, 13):
            assert np.array_equal(fast <= limit, exact <= limit)
        assert np.all((fast > beyond) == (exact > beyond))
