"""Levels 1-4 per track: one object gives today's result, several give one verdict each."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.frames import TactileFrames
from taxelkit.motion.engines import scenario_from_engine
from taxelkit.motion.multi_scenes import frames_from_multi_scene, multi_scene
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart.objects import ObjectRecogniser, ObjectRecognition, recognise_objects
from taxelkit.smart.recogniser import recognise
from taxelkit.smart.tacteme_table import OBJECTS

_TRACKER_KINDS = ("birth", "death", "merge", "split")


def roll(name: str, seed: int) -> TactileFrames:
    sc = scenario_from_engine("kinematic", name, rng=seed)
    return frames_from_scenario(BONNEVILLE_16X16, sc, rng=seed)


def recogniser_events(res: ObjectRecognition) -> list[tuple[str, int, object]]:
    return [(e.kind, e.frame, e.value) for e in res.events if e.kind not in _TRACKER_KINDS]


def assert_summary_agrees_with_events(res: ObjectRecognition) -> None:
    for obj in res.objects:
        mine = [e for e in res.events if e.track == obj.track]
        verdicts = [e for e in mine if e.kind in ("candidates", "identified", "unknown")]
        if obj.identified not in (None, "unknown"):
            assert any(e.kind == "identified" and e.value == obj.identified for e in verdicts)
        cands = [e.value for e in mine if e.kind in ("candidates", "lifted")]
        if cands and obj.identified is None:
            assert tuple(cands[-1]) == obj.candidates  # type: ignore[arg-type]


@pytest.mark.parametrize("name", OBJECTS)
def test_one_object_on_the_sensor_gives_todays_result(name: str) -> None:
    rec = roll(name, 3)
    today = recognise(rec)
    res = recognise_objects(rec)
    assert recogniser_events(res) == [(e.kind, e.frame, e.value) for e in today.events]
    accepted = [o for o in res.objects if o.accepted]
    assert len(accepted) == 1
    assert accepted[0].identified == today.identified == name
    assert accepted[0].candidates == today.candidates
    assert [(n, f) for n, f, _ in accepted[0].tactemes] == list(today.tactemes)
    assert_summary_agrees_with_events(res)


@pytest.mark.parametrize("fault", ["dead", "stuck"])
def test_one_object_seen_through_dead_or_stuck_taxels_gives_todays_events(fault: str) -> None:
    from taxelkit.sensors.faults import fault_model

    rec = fault_model(fault).apply(roll("cube", 1), threshold=0.03, rng=np.random.default_rng(1))
    today = recognise(rec)
    res = recognise_objects(rec)
    assert recogniser_events(res) == [(e.kind, e.frame, e.value) for e in today.events]
    assert [o.identified for o in res.objects if o.accepted] == [today.identified]


def test_each_contact_of_an_object_lifted_and_put_down_is_its_own_track() -> None:
    rec = roll("cylinder", 3)
    res = recognise_objects(rec, threshold=0.3)  # light: the roll is seen as three contacts
    today = recognise(rec, threshold=0.3)
    assert recogniser_events(res) == [(e.kind, e.frame, e.value) for e in today.events]
    assert len(res.objects) == 3
    said = [o.identified for o in res.objects]
    assert said == [None, "cylinder", None]
    assert today.identified is None  # the whole-array verdict covers the last contact only
    assert_summary_agrees_with_events(res)
    first = res.objects[1]
    assert first.first_t_s == pytest.approx(rec.t_s[first.first_frame])
    assert first.last_t_s == pytest.approx(rec.t_s[first.last_frame])
    for name, frame, t in first.tactemes:
        assert t == pytest.approx(rec.t_s[frame]), name


def two_objects(seed: int = 4) -> tuple[TactileFrames, tuple[str, ...]]:
    scene = multi_scene(["cube", "cone"], rng=seed)
    return frames_from_multi_scene(scene, rng=seed).recording, scene.names


def test_two_objects_get_one_verdict_each() -> None:
    rec, names = two_objects()
    res = recognise_objects(rec, keep_map=True)
    accepted = [o for o in res.objects if o.accepted]
    assert sorted(str(o.identified) for o in accepted) == sorted(names)
    assert_summary_agrees_with_events(res)
    assert res.track_map is not None and res.track_map.shape == rec.frames.shape
    doc = res.to_json()
    assert {"objects", "track_events", "n_frames"} <= set(doc)
    assert {"track", "first_frame", "last_frame", "first_t_s", "last_t_s", "identified"} <= set(
        doc["objects"][0]
    )


@pytest.mark.parametrize("chunk", [1, 7, 64])
def test_streaming_in_chunks_gives_the_batch_result(chunk: int) -> None:
    rec, _ = two_objects(seed=6)
    batch = recognise_objects(rec)
    stream = ObjectRecogniser(rec.frames.shape[1:], pitch_mm=rec.pitch_mm)
    found = []
    for a in range(0, rec.n_frames, chunk):
        found.extend(stream.push(rec.frames[a : a + chunk], rec.t_s[a : a + chunk]))
    res = stream.result()
    assert res.events == batch.events
    assert [o.to_json() for o in res.objects] == [o.to_json() for o in batch.objects]
    assert sorted(found, key=repr) == sorted(res.events, key=repr)


def test_a_live_result_lists_the_tracks_so_far_and_pushing_goes_on() -> None:
    rec, _ = two_objects(seed=6)
    stream = ObjectRecogniser(rec.frames.shape[1:], pitch_mm=rec.pitch_mm)
    half = rec.n_frames // 2
    stream.push(rec.frames[:half], rec.t_s[:half])
    early = stream.result()
    stream.push(rec.frames[half:], rec.t_s[half:])
    assert stream.result().events == recognise_objects(rec).events
    assert len(early.objects) >= 1


def test_blank_and_single_frame_recordings() -> None:
    blank = recognise_objects(np.zeros((3, 4, 4), bool), pitch_mm=1.0)
    assert blank.objects == () and blank.events == ()
    one = np.zeros((1, 6, 6), bool)
    one[0, 2:4, 2:4] = True
    res = recognise_objects(one, pitch_mm=1.0, cleaning=None)  # (cleaning: stuck from the start)
    assert [e.kind for e in res.events] == ["birth"]
    assert not res.objects[0].accepted


def test_events_are_grouped_by_track_with_the_trackers_placed_by_frame() -> None:
    from taxelkit.smart.object_results import TrackedEvent, interleaved

    found = [
        TrackedEvent(1, "contact", 12, 0.6),
        TrackedEvent(0, "contact", 3, 0.15),
        TrackedEvent(0, "tacteme", 9, 0.45, "LCM"),  # found late: stays after the later one
        TrackedEvent(0, "tacteme", 7, 0.35, "AC"),
        TrackedEvent(1, "identified", 30, 1.5, "cube"),
    ]
    tracker = [
        TrackedEvent(0, "birth", 2, 0.1),
        TrackedEvent(1, "birth", 10, 0.5),
        TrackedEvent(0, "merge", 8, 0.4, 1),
        TrackedEvent(0, "death", 8, 0.4),
        TrackedEvent(2, "birth", 40, 2.0),
    ]
    out = [(e.track, e.kind, e.frame) for e in interleaved(found, tracker)]
    assert out == [
        (0, "birth", 2),
        (0, "contact", 3),
        (0, "merge", 8),
        (0, "tacteme", 9),
        (0, "tacteme", 7),
        (0, "death", 8),
        (1, "birth", 10),
        (1, "contact", 12),
        (1, "identified", 30),
        (2, "birth", 40),
    ]
