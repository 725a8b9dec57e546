"""Level 3 of many segments at once equals Level 3 of each segment alone.

:func:`~taxelkit.smart.tactemes_batch.batch_tactemes` against
:func:`~taxelkit.smart.tactemes.segment_tactemes`, and
:func:`~taxelkit.smart.slip_batch.batch_slip_scanners` against a
:class:`~taxelkit.smart.slip_scan.SlipScanner` fed each segment, on the
segments of simulated rolls (every sensor imperfection, several frame rates)
and on randomised slipping segments; :class:`~taxelkit.smart.segment_runs.Runs`
against NumPy on each segment.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import make_scenario
from taxelkit.sensors.faults import fault_model
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart import levels34, pivot_stream, recogniser
from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.recogniser import SmartSensor
from taxelkit.smart.segment_runs import Runs
from taxelkit.smart.segment_scan import rows_from_track
from taxelkit.smart.slip import SlipConfig
from taxelkit.smart.slip_batch import batch_slip_scanners
from taxelkit.smart.slip_scan import SlipScanner
from taxelkit.smart.tacteme_table import OBJECTS
from taxelkit.smart.tactemes import SegmentTrack, TactemeConfig, segment_tactemes
from taxelkit.smart.tactemes_batch import batch_tactemes
from taxelkit.smart.track_geometry import orthogonal_turn, rolling_mean, sustained

from .test_slip_vectorised import random_segment


def recorded_segments(
    seeds: range, rate_hz: float, monkeypatch: pytest.MonkeyPatch
) -> list[tuple[int, SegmentTrack]]:
    """The (class, track) of every contact segment of rolls of the six objects, faults 'all'."""
    found: list[tuple[int, SegmentTrack]] = []

    def capture(items, config):  # type: ignore[no-untyped-def]
        found.extend((cls, track) for cls, track, _ in items)
        return real(items, config)

    real = levels34.track_segments
    monkeypatch.setattr(recogniser, "track_segments", capture)
    thr = BONNEVILLE_16X16.contact_threshold_mm
    for seed in seeds:
        for obj in OBJECTS:
            rng = np.random.default_rng(seed)
            sc = make_scenario(obj, rng=rng, rate_hz=rate_hz)
            rec = frames_from_scenario(BONNEVILLE_16X16, sc, rng=rng)
            rec = fault_model("all").apply(rec, threshold=thr, rng=seed)
            recogniser.recognise(rec)
    return found


@pytest.mark.parametrize("rate_hz", [10.0, 60.0, 240.0])
def test_batch_tactemes_equal_each_segment_alone(
    rate_hz: float, monkeypatch: pytest.MonkeyPatch
) -> None:
    items = recorded_segments(range(3), rate_hz, monkeypatch)
    assert {cls for cls, _ in items} >= {int(ContactClass.LINE), int(ContactClass.AREA)}
    for config in (TactemeConfig(), TactemeConfig(face_shapes=True, smooth_s=0.3)):
        alone = [segment_tactemes(cls, track, config) for cls, track in items]
        assert sum(map(len, alone)) > 10  # the rolls show motion tactemes
        assert batch_tactemes(items, config) == alone
        shuffled = np.random.default_rng(0).permutation(len(items))
        together = batch_tactemes([items[i] for i in shuffled], config)
        assert together == [alone[i] for i in shuffled]  # neighbours change nothing


def test_batch_tactemes_of_short_and_unclassified_segments() -> None:
    rng = np.random.default_rng(1)
    items = []
    for n, cls in [(1, 2), (2, 3), (3, 4), (5, 1), (40, 0), (1, 4), (7, 3)]:
        t = np.arange(n) / 20.0
        items.append(
            (
                cls,
                SegmentTrack(
                    np.arange(n) + 100,
                    rng.normal(0, 2, (n, 2)),
                    rng.uniform(-90, 90, n),
                    rng.uniform(5, 30, n),
                    rng.uniform(1, 3, n),
                    rng.uniform(1, 5, n),
                    t,
                    None,
                    1.7625,
                ),
            )
        )
    config = TactemeConfig(debounce_frames=3)
    assert batch_tactemes(items, config) == [segment_tactemes(c, t, config) for c, t in items]


@pytest.mark.parametrize("seed", range(6))
def test_batch_slip_scanners_equal_each_scanner_alone(seed: int) -> None:
    rng = np.random.default_rng(seed)
    cfg = SlipConfig(hold_s=float(rng.choice([0.0, 0.07])), line_across_mm=1.0)
    items = []
    for _ in range(25):
        line = bool(rng.integers(2))
        n = int(rng.integers(1, 400))
        rate = float(rng.choice([20.0, 240.0]))
        rows = random_segment(rng, n, rate, line)
        frames = np.cumsum(rng.integers(1, 3, n)) + int(rng.integers(0, 1000))
        cls = int(rng.choice([ContactClass.LINE, ContactClass.AREA, ContactClass.POINT]))
        items.append((cls, frames, rows))
    k = 2 + seed % 2
    together = batch_slip_scanners(items, cfg, k=k)
    opened = 0
    for scanner, (cls, frames, rows) in zip(together, items, strict=True):
        alone = SlipScanner(cls, cfg, k=k)
        alone.extend(frames, rows)
        opened += len(alone.all_slips())
        assert scanner.all_slips() == alone.all_slips()
        assert scanner.close() == alone.close()
    assert opened > 0  # the segments do slip


def test_track_segments_read_the_rows_of_the_track(monkeypatch: pytest.MonkeyPatch) -> None:
    items = recorded_segments(range(1), 60.0, monkeypatch)
    config = TactemeConfig()
    given = levels34.track_segments([(c, t, rows_from_track(t)) for c, t in items], config)
    derived = levels34.track_segments([(c, t, None) for c, t in items], config)
    for a, b, (cls, track) in zip(given, derived, items, strict=True):
        alone = levels34.TrackSegment(cls, track, config)
        assert a.tactemes() == b.tactemes() == alone.tactemes()
        assert a.slips() == b.slips() == alone.slips()
        for stop in (None, 0, 1, 2, 3, 7, a.size, a.size + 5):
            expected = alone.mean_axis_deg(stop)
            assert a.mean_axis_deg(stop) == expected or np.isnan(expected)
            assert np.isnan(a.mean_axis_deg(stop)) == np.isnan(expected)


def test_runs_match_numpy_on_each_segment() -> None:
    rng = np.random.default_rng(3)
    lengths = rng.integers(1, 300, 40)
    lengths[[3, 7]] = 2000  # long ones: blocks of their own
    runs = Runs(lengths)
    x = rng.normal(0, 1e3, (int(lengths.sum()), 3)) * rng.choice([1e-6, 1.0, 1e6], (1, 3))
    mask = rng.random(int(lengths.sum())) < 0.7
    roll = runs.rolling_mean(x, 5)
    csum = runs.cumsum(x[:, 0])
    held = runs.sustained(mask, 4)
    first = runs.first_sustained(mask, 4)
    for s, (a, n) in enumerate(zip(runs.starts.tolist(), lengths.tolist(), strict=True)):
        seg = slice(a, a + n)
        np.testing.assert_array_equal(roll[seg], rolling_mean(x[seg], 5))  # the same floats
        np.testing.assert_array_equal(csum[seg], np.cumsum(x[seg, 0]))
        np.testing.assert_array_equal(held[seg], sustained(mask[seg], 4))
        hits = np.flatnonzero(sustained(mask[seg], 4))
        assert first[s] == (hits[0] if hits.size else -1)


def legs_turn(
    centre: np.ndarray, start: int, leg: float, window: tuple[float, float]
) -> int | None:
    """:func:`~taxelkit.smart.track_geometry.orthogonal_turn` as written: point by point."""
    pts = centre.tolist()
    lo, hi = np.cos(np.deg2rad(window[1])), np.cos(np.deg2rad(window[0]))
    bx, by = pts[start]
    legs: list[tuple[float, float]] = []
    for j in range(start + 1, len(pts)):
        x, y = pts[j]
        dx, dy = x - bx, y - by
        d = math.hypot(dx, dy)
        if d < leg:
            continue
        legs.append((dx / d, dy / d))
        bx, by = x, y
        for back in (2, 3):
            if len(legs) >= back:
                c = legs[-back][0] * legs[-1][0] + legs[-back][1] * legs[-1][1]
                if lo <= c <= hi:
                    return j
    return None


@pytest.mark.parametrize("seed", range(4))
def test_orthogonal_turn_is_the_rule_point_by_point(seed: int) -> None:
    rng = np.random.default_rng(seed)
    turns = 0
    for _ in range(300):
        n = int(rng.integers(2, 600))
        steps = rng.normal(0, rng.choice([0.01, 0.1, 0.5]), (n, 2)) + rng.normal(0, 0.1, 2)
        path = np.cumsum(steps, axis=0)
        if rng.random() < 0.3:  # on a grid: points exactly a leg away
            path = np.round(path / 0.5) * 0.5
        if rng.random() < 0.05:
            path[rng.integers(n)] = np.nan
        start, leg = int(rng.integers(0, n)), float(rng.choice([0.5, 1.0, 3.0]))
        expected = legs_turn(path, start, leg, (60.0, 120.0))
        assert orthogonal_turn(path, start, leg, (60.0, 120.0)) == expected
        turns += expected is not None
    assert turns > 20


@pytest.mark.parametrize("kept", [0, 7, 100_000])
def test_a_line_pivot_kept_back_until_the_turn_reads_the_same(
    kept: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Cones and truncated cones rolled and streamed: pivot frames fed now or at the turn."""
    thr = BONNEVILLE_16X16.contact_threshold_mm
    recs = []
    for seed in range(4):
        for obj in ("cone", "truncated-cone"):
            rng = np.random.default_rng(seed)
            sc = make_scenario(obj, rng=rng, rate_hz=60.0)
            recs.append(
                fault_model("all").apply(
                    frames_from_scenario(BONNEVILLE_16X16, sc, rng=rng), threshold=thr, rng=seed
                )
            )

    def streamed() -> list:
        out = []
        for rec in recs:
            sensor = SmartSensor(rec.shape[1:], pitch_mm=rec.pitch_mm, batch_frames=23)
            for f, t in zip(rec.frames, rec.t_s.tolist(), strict=True):
                sensor.push(f, t)
            out.append(sensor.result().events)
        return out

    monkeypatch.setattr(pivot_stream, "KEPT_ROWS", 0)  # every frame into the sums at once
    eager = streamed()
    assert any(e.value in ("LCMT about one end", "LCMT in an arc") for ev in eager for e in ev)
    monkeypatch.setattr(pivot_stream, "KEPT_ROWS", kept)
    assert streamed() == eager
