"""Tracking a chunk at once gives what the tracker's step gives frame by frame."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.smart.regions import segment_frames
from taxelkit.smart.tracks import AREA_WEIGHT, RegionTracker, TrackerConfig, TrackEvent
from taxelkit.smart.tracks_batch import continuing_frames, track_chunk


def _per_frame(images: np.ndarray, lost: int) -> tuple[list[int], list[TrackEvent], RegionTracker]:
    reg = segment_frames(images, pitch_mm=1.0)
    tracker = RegionTracker(pitch_mm=1.0, lost_frames=lost)
    ids: list[int] = []
    events: list[TrackEvent] = []
    for t in range(images.shape[0]):
        idx = reg.in_frame(t)
        got, ev = tracker.push(
            t,
            0.05 * t,
            reg.labels[t],
            idx + 1,
            reg.centre_mm[idx],
            reg.area_mm2[idx],
            reg.taxels_of(idx),
        )
        ids.extend(got.tolist())
        events.extend(ev)
    return ids, events, tracker


def _chunked(
    images: np.ndarray, lost: int, chunk: int
) -> tuple[list[int], list[TrackEvent], RegionTracker]:
    tracker = RegionTracker(pitch_mm=1.0, lost_frames=lost)
    ids: list[int] = []
    events: list[TrackEvent] = []
    for a in range(0, images.shape[0], chunk):
        part = images[a : a + chunk]
        reg = segment_frames(part, pitch_mm=1.0)
        got, ev = track_chunk(tracker, reg, 0.05 * np.arange(a, a + part.shape[0]), first_frame=a)
        ids.extend(got.tolist())
        events.extend(ev)
    return ids, events, tracker


def _blobs(seed: int, frames: int = 160, size: int = 20) -> np.ndarray:
    """Up to four square blobs wandering, touching, crossing, leaving and coming back."""
    rng = np.random.default_rng(seed)
    img = np.zeros((frames, size, size), bool)
    for _ in range(4):
        pos = rng.uniform(2, size - 4, 2)
        vel = rng.uniform(-0.4, 0.4, 2)
        half = int(rng.integers(1, 3))
        on = rng.uniform() < 0.8
        for t in range(frames):
            if rng.uniform() < 0.02:
                on = not on  # lifted or put down
            pos = np.clip(pos + vel + rng.normal(0, 0.1, 2), 0, size - 1)
            vel = np.where((pos <= 0) | (pos >= size - 1), -vel, vel)
            if on:
                r, c = np.round(pos).astype(int)
                img[t, max(0, r - half) : r + half + 1, max(0, c - half) : c + half + 1] = True
    img ^= rng.uniform(size=img.shape) < 0.004  # a few stray taxels
    return img


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("chunk", [1, 9, 1000])
def test_a_chunk_at_once_tracks_as_the_step_frame_by_frame(seed: int, chunk: int) -> None:
    images = _blobs(seed)
    ids, events, tracker = _per_frame(images, lost=3)
    got, got_events, batch_tracker = _chunked(images, lost=3, chunk=chunk)
    assert got == ids
    assert got_events == events
    assert len(events) > 4  # births, deaths, merges or splits happened
    state = [(tr.track, tr.last_frame, tr.frames_seen, tr.unseen) for tr in tracker.tracks]
    assert [
        (tr.track, tr.last_frame, tr.frames_seen, tr.unseen) for tr in batch_tracker.tracks
    ] == state
    for a, b in zip(tracker.tracks, batch_tracker.tracks, strict=True):
        assert np.array_equal(a.centre_mm, b.centre_mm) and a.area_mm2 == b.area_mm2
        assert np.array_equal(a.taxels, b.taxels)


def test_frames_where_regions_only_move_on_are_continuing() -> None:
    img = np.zeros((6, 12, 12), bool)
    for t in range(6):
        img[t, 2:4, 2 + t : 4 + t] = True  # one blob moving a taxel a frame (overlapping)
    img[3, 9:11, 9:11] = True  # a second blob appears in frame 3 only
    reg = segment_frames(img, pitch_mm=1.0)
    cont, prev, starts = continuing_frames(reg, area_weight=AREA_WEIGHT)
    assert cont.tolist() == [False, True, True, False, False, True]
    assert prev[starts[1]] == starts[0] and prev[starts[3]] == -1


def test_a_pairing_that_is_not_the_cheapest_is_left_to_the_step() -> None:
    """Each region overlaps its own predecessor, but the areas make the swap cheaper."""
    img = np.zeros((2, 8, 16), bool)
    img[0, 2:6, 2:7] = True  # A: 20 taxels
    img[0, 2:4, 12] = True  # B: 2 taxels
    img[1, 2:4, 2] = True  # A': 2 taxels, on A
    img[1, 2:6, 10:15] = True  # B': 20 taxels, on B
    config = TrackerConfig(area_weight=10.0, gate_pitches=12.0)
    reg = segment_frames(img, pitch_mm=1.0)
    assert not continuing_frames(reg, area_weight=10.0)[0][1]
    assert continuing_frames(reg, area_weight=10.0, margin_mm=-np.inf)[0][1]  # paired, though
    tracker = RegionTracker(pitch_mm=1.0, lost_frames=3, config=config)
    got, events = track_chunk(tracker, reg, np.array([0.0, 0.05]), first_frame=0)
    assert got.tolist() == [0, 1, 1, 0]  # the step swapped them
    assert [e.kind for e in events] == ["birth", "birth"]


def test_empty_frames_after_empty_frames_are_continuing() -> None:
    img = np.zeros((4, 8, 8), bool)
    img[1, 3:5, 3:5] = True
    cont, _, _ = continuing_frames(segment_frames(img, pitch_mm=1.0), area_weight=AREA_WEIGHT)
    assert cont.tolist() == [False, False, False, True]


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("lost", [1, 3, 6])
def test_stretches_with_nothing_on_the_array_go_as_frame_by_frame(seed: int, lost: int) -> None:
    """Tracks go unseen and die on their turn in empty stretches, whatever their length."""
    rng = np.random.default_rng(100 + seed)
    images = _blobs(seed)
    for start in rng.integers(0, images.shape[0] - 8, 12):
        images[start : start + int(rng.integers(1, 9))] = False
    ids, events, tracker = _per_frame(images, lost=lost)
    got, got_events, batch_tracker = _chunked(images, lost=lost, chunk=1000)
    assert got == ids and got_events == events
    assert any(e.kind == "death" for e in events)
    assert [(tr.track, tr.unseen, tr.frames_seen) for tr in batch_tracker.tracks] == [
        (tr.track, tr.unseen, tr.frames_seen) for tr in tracker.tracks
    ]
