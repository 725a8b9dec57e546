"""The chunked recogniser gives the batch recogniser's events for any chunking."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from taxelkit.frames import TactileFrames
from taxelkit.motion.engines import scenario_from_engine
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart.cleaning import CleaningConfig, clean_images
from taxelkit.smart.cleaning_chunks import ChunkCleaner
from taxelkit.smart.recognise_chunks import (
    ChunkRecogniser,
    class_segments,
    recognise_chunks,
)
from taxelkit.smart.recogniser import recognise
from taxelkit.smart.tactemes import PAPER_LEVEL3


def _rolled(name: str, seed: int) -> TactileFrames:
    scenario = scenario_from_engine("kinematic", name, rng=seed, rate_hz=20.0, lift_gap_s=0.0)
    return frames_from_scenario(BONNEVILLE_16X16, scenario, rng=seed, add_noise=True)


def _in_chunks(rec: TactileFrames, size: int, **options: object) -> object:
    recogniser = ChunkRecogniser(rec.shape[1:], pitch_mm=rec.pitch_mm, per_frame=True, **options)
    for a in range(0, rec.n_frames, size):
        recogniser.push(rec.frames[a : a + size], rec.t_s[a : a + size])
    return recogniser.result()


@pytest.mark.parametrize("name", ["cube", "cone", "tetrahedron", "sliding"])
@pytest.mark.parametrize("faithful", [False, True])
def test_chunked_recognition_equals_batch(name: str, faithful: bool) -> None:
    rec = _rolled(name, 3)
    options: dict[str, object] = (
        {"cleaning": None, "limits": None, "config": PAPER_LEVEL3} if faithful else {}
    )
    ref = recognise(rec, **options)  # type: ignore[arg-type]
    for size in (1, 2, 5, 64, rec.n_frames):
        got = _in_chunks(rec, size, **options)
        assert got.events == ref.events, size  # type: ignore[attr-defined]
        assert got.verdict == ref.verdict  # type: ignore[attr-defined]
        assert got.identified == ref.identified  # type: ignore[attr-defined]
        assert np.array_equal(got.classes, ref.classes)  # type: ignore[attr-defined]
        assert np.array_equal(got.segments.per_frame(), ref.classes)  # type: ignore[attr-defined]


def test_recognise_chunks_json_has_segments_and_optional_per_frame() -> None:
    rec = _rolled("cube", 0)
    pieces = [
        TactileFrames(rec.frames[a : a + 50], rec.t_s[a : a + 50], pitch_mm=rec.pitch_mm)
        for a in range(0, rec.n_frames, 50)
    ]
    got = recognise_chunks(pieces)
    doc = got.to_json()
    assert "classes" not in doc
    assert doc["n_frames"] == rec.n_frames
    segments = doc["class_segments"]
    assert segments[0]["first_frame"] == 0 and segments[-1]["last_frame"] == rec.n_frames - 1
    assert all(a["last_frame"] + 1 == b["first_frame"] for a, b in itertools.pairwise(segments))
    assert all(a["class"] != b["class"] for a, b in itertools.pairwise(segments))
    assert segments[0]["first_s"] == rec.t_s[0]
    assert got.to_json(per_frame=True)["classes"] == recognise(rec).class_names()


def test_class_segments_of_runs() -> None:
    seg = class_segments([2, 2, 0, 0, 0, 3], np.arange(6) * 0.25, first_frame=10)
    assert seg.class_code.tolist() == [2, 0, 3]
    assert seg.first_frame.tolist() == [10, 12, 15]
    assert seg.last_frame.tolist() == [11, 14, 15]
    assert seg.first_s.tolist() == [0.0, 0.5, 1.25]


def test_timestamps_must_increase_across_chunks() -> None:
    recogniser = ChunkRecogniser((4, 4), pitch_mm=1.0)
    recogniser.push(np.zeros((3, 4, 4), bool), [0.0, 1.0, 2.0])
    with pytest.raises(ValueError, match="increase across chunks"):
        recogniser.push(np.zeros((1, 4, 4), bool), [2.0])


@pytest.mark.parametrize("shape", [(16, 16), (9, 12), (12, 70)])
def test_chunk_cleaner_equals_batch_cleaning(shape: tuple[int, int]) -> None:
    rng = np.random.default_rng(5)
    n = 1500
    images = rng.random((n, *shape)) < 0.03
    images[:, 2, 3] = True  # stuck from the start
    images[200:900, 5, 5] = True  # stuck for a while, then released
    images[950:953, 5, 5] = True
    images[100:400, 3:6, 3:7] = True  # a real contact
    t_s = np.arange(n) * 0.004  # stuck_s is then 375 frames
    ref = clean_images(images, t_s, config=CleaningConfig())
    for size in (1, 7, 250, n):
        cleaner = ChunkCleaner(1, shape)  # one array of the bank's cleaner
        parts = [
            cleaner.push(images[None, a : a + size], t_s[None, a : a + size])[0]
            for a in range(0, n, size)
        ]
        assert np.array_equal(np.concatenate(parts), ref), size


@pytest.mark.parametrize("name", ["cube", "sphere", "cone", "truncated-cone", "tetrahedron"])
def test_streaming_chunks_emit_the_events_of_recognise_as_they_happen(name: str) -> None:
    rec = _rolled(name, 4)
    ref = recognise(rec)
    for size in (1, 3, 50, rec.n_frames):
        recogniser = ChunkRecogniser(rec.shape[1:], pitch_mm=rec.pitch_mm, streaming=True)
        events = []
        for a in range(0, rec.n_frames, size):
            events.extend(recogniser.push(rec.frames[a : a + size], rec.t_s[a : a + size]))
            assert recogniser.last_classes.size == min(size, rec.n_frames - a)
        got = recogniser.result()
        assert got.events == ref.events and got.verdict == ref.verdict, size
        assert tuple(events) == ref.events[: len(events)]
        if size == 1:  # these rolls end lifted: every event came out of push
            assert tuple(events) == ref.events


def test_streaming_forgets_old_contacts_but_not_the_verdict() -> None:
    rec = _rolled("cube", 1)
    repeats = 60  # enough contacts to drop old events
    recogniser = ChunkRecogniser(rec.shape[1:], pitch_mm=rec.pitch_mm, streaming=True)
    emitted = 0
    for k in range(repeats):
        emitted += len(recogniser.push(rec.frames, rec.t_s + k * (rec.t_s[-1] + 1.0)))
    got = recogniser.result()
    assert emitted > 1024 > len(got.events)
    ref = recognise(rec)
    assert got.identified == ref.identified == "cube"
    assert got.candidates == ref.candidates
    shift = (repeats - 1) * rec.n_frames  # the last roll's frames
    assert [(o, t, f - shift) for o, t, f, _ in got.verdict.eliminated] == [
        (o, t, f) for o, t, f, _ in ref.verdict.eliminated
    ]
