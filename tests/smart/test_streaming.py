"""Streaming twins of the batch smart sensor: incremental Level 3, mini-batches, the bank.

Every streaming path gives the events of :func:`recognise` on the same frames
(random recordings, simulated rolls with every sensor fault, any chunking),
its cost per frame does not grow with a contact's length, and its memory is
bounded.
"""

from __future__ import annotations

import itertools
import time

import numpy as np
import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from taxelkit.frames import TactileFrames
from taxelkit.motion.engines import scenario_from_engine
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.sensors import BONNEVILLE_16X16
from taxelkit.sensors.faults import fault_model
from taxelkit.smart.bank import SensorBank, SkinBank
from taxelkit.smart.cleaning import CleaningConfig, clean_images
from taxelkit.smart.cleaning_chunks import ChunkCleaner
from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.recogniser import SmartSensor, recognise
from taxelkit.smart.segment_scan import SegmentScanner
from taxelkit.smart.stream_state import ClassHistory
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.tactemes import SegmentTrack, TactemeConfig, segment_tactemes
from taxelkit.smart.track_geometry import corner_turn, spaced_points
from taxelkit.smart.track_stream import CornerScan

PITCH = 1.7625


def random_recording(seed: int, n_frames: int, rate_hz: float) -> TactileFrames:
    """Contacts of random shape (point, bar, patch) that appear, move, turn and lift."""
    rng = np.random.default_rng(seed)
    frames = np.zeros((n_frames, 16, 16), bool)
    yy, xx = np.mgrid[0:16, 0:16]
    j = int(rng.integers(0, 20))
    while j < n_frames:
        length = int(rng.integers(5, 200))
        kind = rng.integers(3)
        half_len, half_wid = [(0.8, 0.8), (4.0, 0.6), (2.5, 2.0)][kind]
        c = rng.uniform(4, 12, 2)
        v = rng.normal(0, 0.08, 2) * rng.integers(0, 2)
        th, om = rng.uniform(0, np.pi), rng.normal(0, 0.02) * rng.integers(0, 2)
        for k in range(j, min(n_frames, j + length)):
            p = c + v * (k - j)
            a = th + om * (k - j)
            du, dv = xx - p[0], yy - p[1]
            along = du * np.cos(a) + dv * np.sin(a)
            across = -du * np.sin(a) + dv * np.cos(a)
            frames[k] = (np.abs(along) <= half_len) & (np.abs(across) <= half_wid)
        j += length + int(rng.integers(0, 40))
    flips = rng.random(frames.shape) < 0.01 * rng.integers(0, 2)
    t_s = np.arange(n_frames) / rate_hz
    return TactileFrames(frames ^ flips, t_s, pitch_mm=PITCH)


def streamed(rec: TactileFrames, **options: int) -> tuple[list[object], SmartSensor]:
    sensor = SmartSensor(rec.shape[1:], pitch_mm=rec.pitch_mm, **options)  # type: ignore[arg-type]
    events = [e for f, t in zip(rec.frames, rec.t_s, strict=True) for e in sensor.push(f, t)]
    return events + sensor.flush(), sensor


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    seed=st.integers(0, 2**31),
    n_frames=st.integers(1, 600),
    rate_hz=st.sampled_from([5.0, 20.0, 100.0, 240.0]),
    batch_frames=st.sampled_from([1, 2, 7, 64, 1000]),
    evaluate_every=st.sampled_from([1, 16]),
)
# a line re-anchored on the first frame of a one-frame chunk once reset its pivot's verdicts
@example(seed=210, n_frames=77, rate_hz=20.0, batch_frames=1, evaluate_every=1)
# the one-frame path's areas rounded as n * p * p, the batch's as n * (p * p): a ratio of two
# window means at exactly 1 - area_step ended a slip in one path only
@example(seed=0, n_frames=227, rate_hz=5.0, batch_frames=1, evaluate_every=1)
def test_streaming_equals_batch_on_random_recordings(
    seed: int, n_frames: int, rate_hz: float, batch_frames: int, evaluate_every: int
) -> None:
    rec = random_recording(seed, n_frames, rate_hz)
    batch = recognise(rec)
    events, sensor = streamed(rec, batch_frames=batch_frames, evaluate_every=evaluate_every)
    assert list(sensor.result().events) == list(batch.events)
    np.testing.assert_array_equal(np.asarray(sensor.classes), batch.classes)
    assert events == list(batch.events)[: len(events)]  # in order, never ahead of the batch


@pytest.mark.parametrize("batch_frames", [1, 5, 256])
def test_streaming_equals_batch_on_a_faulty_roll_in_mini_batches(batch_frames: int) -> None:
    sc = scenario_from_engine("kinematic", "cone", rng=5, rate_hz=240.0)
    rec = fault_model("all").apply(
        frames_from_scenario(BONNEVILLE_16X16, sc, rng=5), threshold=0.03, rng=5
    )
    batch = recognise(rec)
    events, sensor = streamed(rec, batch_frames=batch_frames)
    assert events == list(batch.events)
    assert list(sensor.result().events) == list(batch.events)


def cleaned_in_chunks(
    cleaner: ChunkCleaner, images: np.ndarray, t: np.ndarray, cuts: list[int]
) -> np.ndarray:
    """Images ``(N, T, ...)`` through ``cleaner`` in chunks of the lengths ``cuts`` (cycled)."""
    n_arrays, n = images.shape[:2]
    got, a, k = [], 0, 0
    while a < n:
        b = min(n, a + cuts[k % len(cuts)])
        got.append(cleaner.push(images[:, a:b], np.broadcast_to(t[a:b], (n_arrays, b - a))))
        a, k = b, k + 1
    return np.concatenate(got, axis=1)


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31), cuts=st.lists(st.integers(1, 97), min_size=1, max_size=8))
def test_chunk_cleaner_equals_the_batch_cleaning_in_any_chunks(seed: int, cuts: list[int]) -> None:
    rng = np.random.default_rng(seed)
    n = 300
    images = rng.random((2, n, 9, 11)) < 0.08
    images[:, :, 4, 5] = True  # a stuck taxel, on from the start
    images[0, 100:, 2:5, 2:6] = True  # a contact
    images[1, 50:200, 6, 8] = True  # an isolated taxel held on, then released
    t = np.arange(n) / 20.0
    cfg = CleaningConfig(stuck_s=2.0)
    want = np.stack([clean_images(images[i], t, config=cfg) for i in range(2)])
    cleaner = ChunkCleaner(2, (9, 11), config=cfg)
    np.testing.assert_array_equal(cleaned_in_chunks(cleaner, images, t, cuts), want)


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**31), cuts=st.lists(st.integers(1, 60), min_size=1, max_size=6))
def test_chunk_cleaner_settles_clear_arrays_as_the_batch_cleaning(
    seed: int, cuts: list[int]
) -> None:
    # arrays clear for a while (a fresh array's clear chunks are not cleaned), then touched
    rng = np.random.default_rng(seed)
    n = 240
    images = np.zeros((4, n, 8, 8), bool)
    start = rng.integers(1, 120, 3)
    images[0, start[0] :, 3, 3] = True  # an isolated taxel on from then on: held, masked
    images[1, start[1] :, 1:4, 2:6] = True  # a contact held still
    images[2, start[2] :] = rng.random((n - start[2], 8, 8)) < 0.1  # flicker
    images[2, start[2] + 30 : start[2] + 50] = False  # a clear stretch after contact
    t = np.arange(n) / 20.0
    cfg = CleaningConfig(stuck_s=2.0)
    want = np.stack([clean_images(images[i], t, config=cfg) for i in range(4)])
    cleaner = ChunkCleaner(4, (8, 8), config=cfg)
    np.testing.assert_array_equal(cleaned_in_chunks(cleaner, images, t, cuts), want)
    assert not cleaner.busy[3]  # never touched: at rest after its first chunk


@pytest.mark.parametrize("cfg", [TactemeConfig(), TactemeConfig(corner_step_mm=0.5)])
def test_scanner_equals_segment_tactemes_in_chunks_of_any_size(cfg: TactemeConfig) -> None:
    for seed in range(6):
        rec = random_recording(seed, 400, 60.0)
        rows = np.zeros((400, 9))
        rng = np.random.default_rng(seed)
        rows[:, 0:2] = np.cumsum(rng.normal(0, 0.15, (400, 2)), axis=0)
        rows[:, 2] = np.cumsum(rng.normal(0, 1.0, 400))
        rows[:, 3] = 10.0 + rng.normal(0, 0.5, 400)
        rows[:, 4] = 3.0 + rng.normal(0, 0.1, 400)
        rows[:, 5] = 5.0 + rng.normal(0, 0.2, 400)
        rows[:, 6], rows[:, 7] = -rows[:, 5], rows[:, 5]
        rows[:, 8] = rec.t_s
        frames = np.arange(400)
        track = SegmentTrack(
            frames, rows[:, 0:2], rows[:, 2], rows[:, 3], rows[:, 4], rows[:, 5], rows[:, 8],
            rows[:, 6:8],
        )  # fmt: skip
        for cls in (ContactClass.POINT, ContactClass.LINE, ContactClass.AREA):
            want = segment_tactemes(cls, track, cfg)
            for step in (1, 3, 50, 400):
                scan = SegmentScanner(cls, cfg)
                got = [
                    x
                    for a in range(0, 400, step)
                    for x in scan.extend(frames[a : a + step], rows[a : a + step])
                ]
                got += scan.close()
                assert sorted(got, key=lambda x: x[1]) == want, (seed, cls, step)


def test_class_history_is_runs_that_read_as_a_list() -> None:
    h = ClassHistory()
    for c in [0, 0, 2, 2, 2, 1]:
        h.append(c)
    h.extend_array(np.array([1, 1, 3], dtype=np.int8))
    h.extend_constant(0, 4)
    assert list(h) == [0, 0, 2, 2, 2, 1, 1, 1, 3, 0, 0, 0, 0]
    assert len(h) == 13 and h[-1] == 0 and h[2] == 2 and h[-5] == 3
    assert h.runs() == [(0, 0, 1), (2, 2, 4), (1, 5, 7), (3, 8, 8), (0, 9, 12)]
    assert np.asarray(h).dtype == np.int8
    with pytest.raises(IndexError):
        h[13]


def test_a_held_contact_costs_the_same_per_frame_at_its_end_as_at_its_start() -> None:
    rng = np.random.default_rng(0)
    core = np.zeros((16, 16), bool)
    core[5:10, 5:11] = True
    sensor = SmartSensor((16, 16), pitch_mm=PITCH, batch_frames=512)
    sensor.push_many(np.zeros((10, 16, 16), bool))
    window, n = 10_000, 200_000
    costs = []
    for _ in range(n // window):
        block = core[None] | ((rng.random((window, 16, 16)) < 0.2) & np.roll(core, 1, 0)[None])
        t0 = time.process_time()  # this process's CPU: other work on the machine does not count
        sensor.push_many(block)
        costs.append(time.process_time() - t0)
    assert len(sensor.classes.runs()) <= 3  # one contact, held
    seg = sensor._stream._seg
    assert seg is not None and seg.size == n
    assert min(costs[-3:]) <= 3.0 * max(min(costs[:3]), 1e-4)  # generous: a flat cost


def test_a_point_held_still_keeps_its_path_scan_bounded() -> None:
    scan = CornerScan(3.0, (60.0, 120.0))
    rng = np.random.default_rng(1)
    for k in range(40):  # a point resting with rounding jitter, 40 x 1000 frames
        pts = 2.0 + rng.normal(0, 1e-10, (1000, 2))
        assert scan.push(pts, np.arange(k * 1000, (k + 1) * 1000)) is None
    assert scan._arc.size <= CornerScan.MAX_ROWS


@pytest.mark.parametrize("evaluate_every", [1, 100])
def test_bank_gives_each_array_the_events_of_its_own_recording(evaluate_every: int) -> None:
    recs = [random_recording(s, 300, 20.0) for s in range(5)]
    frames = np.stack([r.frames for r in recs])
    t = recs[0].t_s
    bank = SensorBank(5, (16, 16), pitch_mm=PITCH, batch_frames=32, evaluate_every=evaluate_every)
    events: list[list[object]] = [[] for _ in range(5)]
    for j in range(300):
        for i, e in bank.push(frames[:, j], t[j]):
            events[i].append(e)
    for i, e in bank.flush():
        events[i].append(e)
    for i, rec in enumerate(recs):
        want = recognise(rec)
        assert events[i] == list(want.events), i
        assert list(bank.result(i).events) == list(want.events)
        np.testing.assert_array_equal(np.asarray(bank.classes(i)), want.classes)


def test_bank_takes_a_timestamp_per_array_and_many_frames_at_once() -> None:
    recs = [random_recording(s, 200, rate) for s, rate in ((7, 20.0), (8, 100.0))]
    bank = SensorBank(2, (16, 16), pitch_mm=PITCH, batch_frames=4)
    got = bank.push_many(np.stack([r.frames for r in recs]), np.stack([r.t_s for r in recs]))
    got += bank.flush()
    for i, rec in enumerate(recs):
        assert [e for k, e in got if k == i] == list(recognise(rec).events)
    with pytest.raises(Exception, match="t_s"):
        bank.push(np.zeros((2, 16, 16), bool), np.zeros(3))


def test_skin_bank_groups_arrays_by_shape_and_keeps_their_numbers() -> None:
    small = np.zeros((60, 8, 8), bool)
    small[5:40, 3:5, 2:6] = True
    big = random_recording(3, 60, 20.0).frames
    skin = SkinBank([((16, 16), PITCH), ((8, 8), 2.5)], batch_frames=8)
    got = [x for j in range(60) for x in skin.push([big[j], small[j]], j / 20.0)] + skin.flush()
    t = np.arange(60) / 20.0
    want_small = recognise(TactileFrames(small, t, pitch_mm=2.5)).events
    assert [e for i, e in got if i == 1] == list(want_small)
    assert [e for i, e in got if i == 0] == list(
        recognise(TactileFrames(big, t, pitch_mm=PITCH)).events
    )
    assert skin.where(1) == (1, 0)


def test_a_line_rolling_across_re_anchors_carries_its_roll_when_streamed() -> None:
    n, cfg = 400, TactemeConfig()
    rows = np.zeros((n, 9))
    rows[:, 1] = np.arange(n) * 0.02  # a line along x rolls across itself, 1.2 mm/s at 60 Hz
    rows[:, 3] = np.where((np.arange(n) // 60) % 2 == 0, 10.0, 15.0)  # its area swings
    rows[:, 4] = rows[:, 5] = 5.0
    rows[:, 6], rows[:, 7] = -5.0, 5.0
    rows[:, 8] = np.arange(n) / 60.0
    frames = np.arange(n)
    track = SegmentTrack(
        frames, rows[:, 0:2], rows[:, 2], rows[:, 3], rows[:, 4], rows[:, 5], rows[:, 8],
        rows[:, 6:8],
    )  # fmt: skip
    want = segment_tactemes(ContactClass.LINE, track, cfg)
    assert [t for t, _ in want] == [Tacteme.LCMP]  # no stretch alone rolls far enough
    for step in (1, 7, 64, n):
        scan = SegmentScanner(ContactClass.LINE, cfg)
        got = [
            x
            for a in range(0, n, step)
            for x in scan.extend(frames[a : a + step], rows[a : a + step])
        ]
        assert got + scan.close() == want, step


def _cornered_path(rate_hz: float, rng: np.random.Generator) -> np.ndarray:
    """A point rolling 8 mm at 5 mm/s, resting 1 s with taxel-sized jitter, then 4 mm at 90 deg."""
    dt = 1.0 / rate_hz
    run1 = np.stack([np.zeros(int(1.6 * rate_hz)), np.arange(int(1.6 * rate_hz)) * 5.0 * dt], 1)
    rest = run1[-1] + rng.normal(0.0, 0.25, (int(rate_hz), 2))
    run2 = run1[-1] + np.stack(
        [np.arange(1, int(0.8 * rate_hz)) * 5.0 * dt, np.zeros(int(0.8 * rate_hz) - 1)], 1
    )
    raw = np.concatenate([run1, rest, run2])
    w = max(1, round(0.15 * rate_hz))  # smoothed as Level 3 smooths a centre
    kernel = np.ones(w) / w
    return np.stack([np.convolve(raw[:, k], kernel, mode="valid") for k in (0, 1)], 1)


@pytest.mark.parametrize("rate_hz", [20.0, 100.0, 240.0])
def test_a_corner_after_a_rest_is_seen_at_every_rate_once_the_path_is_thinned(
    rate_hz: float,
) -> None:
    """Jitter at rest lengthens the path by an amount that depends on the rate (the chords
    into the corner then read too short); thinned to 0.5 mm steps it does not."""
    path = _cornered_path(rate_hz, np.random.default_rng(int(rate_hz)))
    window = (60.0, 120.0)
    found = corner_turn(path, 0, 3.0, window, 0.5)
    assert found is not None
    assert abs(found / rate_hz - 2.6) <= 1.0  # seen on the second run, not during the rest
    assert corner_turn(path, 0, 3.0, window, 0.0) is None  # unthinned, the rest hides it
    for step in (0.0, 0.5):
        want = corner_turn(path, 0, 3.0, window, step)
        for size in (1, 7, 64):
            scan = CornerScan(3.0, window, step)
            got = None
            for a in range(0, path.shape[0], size):
                got = scan.push(path[a : a + size], np.arange(a, min(a + size, path.shape[0])))
                if got is not None:
                    break
            assert got == want, (step, size)


def test_spaced_points_keeps_rows_a_step_apart_and_carries_on() -> None:
    rng = np.random.default_rng(3)
    pts = np.cumsum(rng.normal(0.0, 0.2, (500, 2)), axis=0)
    rows = spaced_points(pts, 0.5)
    assert rows[0] == 0
    gaps = np.hypot(*np.diff(pts[rows], axis=0).T)
    assert np.all(gaps >= 0.5)
    for a, b in itertools.pairwise(rows.tolist()):  # nothing skipped that was far enough
        between = pts[a + 1 : b]
        assert np.all(np.hypot(*(between - pts[a]).T) < 0.5)
    head = spaced_points(pts[:200], 0.5)
    tail = spaced_points(pts[200:], 0.5, (float(pts[head[-1], 0]), float(pts[head[-1], 1])))
    np.testing.assert_array_equal(np.concatenate([head, tail + 200]), rows)
    np.testing.assert_array_equal(spaced_points(pts, 0.0), np.arange(500))
