"""A pivot verdict held through brief dropouts (``TactemeConfig.pivot_gap_s``)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.smart.segment_runs import Runs
from taxelkit.smart.tactemes import TactemeConfig
from taxelkit.smart.track_geometry import first, sustained
from taxelkit.smart.verdict_holds import Sustained, bridge_gaps, gap_rows


def _bridged_by_loop(mask: np.ndarray, gap: int) -> np.ndarray:
    out = mask.copy()
    on = np.flatnonzero(mask)
    for a, b in itertools.pairwise(on):
        if 0 < b - a - 1 <= gap:
            out[a + 1 : b] = True
    return out


def test_bridge_gaps_fills_only_short_gaps_between_true_rows() -> None:
    mask = np.array([0, 1, 0, 1, 0, 0, 1, 0, 0, 0, 1, 0], bool)
    assert bridge_gaps(mask, 0) is mask
    np.testing.assert_array_equal(bridge_gaps(mask, 1), [0, 1, 1, 1, 0, 0, 1, 0, 0, 0, 1, 0])
    np.testing.assert_array_equal(bridge_gaps(mask, 2), [0, 1, 1, 1, 1, 1, 1, 0, 0, 0, 1, 0])
    # segments laid end to end: nothing bridged across their boundary
    seg = np.array([0] * 5 + [1] * 7)
    np.testing.assert_array_equal(bridge_gaps(mask, 3, seg), [0, 1, 1, 1, 0, 0, 1, 1, 1, 1, 1, 0])
    rng = np.random.default_rng(4)
    for _ in range(200):
        m = rng.random(int(rng.integers(0, 60))) < rng.uniform(0.2, 0.9)
        g = int(rng.integers(0, 4))
        np.testing.assert_array_equal(bridge_gaps(m, g), _bridged_by_loop(m, g))


def test_the_streamed_hold_is_the_batch_hold_whatever_the_chunks() -> None:
    """Sustained == first(sustained(bridge_gaps(mask), k, frames, min_rows) & mask)."""
    rng = np.random.default_rng(11)
    for case in range(400):
        n = int(rng.integers(1, 120))
        mask = rng.random(n) < rng.uniform(0.5, 0.98)
        frames = np.cumsum(rng.integers(1, 3, n)) + 7  # some frames left out
        k, gap = int(rng.integers(1, 25)), int(rng.integers(0, 4))
        min_rows = int(rng.integers(1, 6))
        spans = bool(case % 2)
        held = sustained(bridge_gaps(mask, gap), k, frames if spans else None, min_rows) & mask
        j = first(held, 0)
        expected = None if j is None else int(frames[j])
        stream = Sustained(k, spans, min_rows, gap)
        cuts = np.sort(rng.integers(0, n + 1, int(rng.integers(0, 6))))
        got = None
        for a, b in zip(np.r_[0, cuts], np.r_[cuts, n], strict=True):
            got = stream.push(mask[a:b], frames[a:b])
        assert got == expected, (case, k, gap, spans)


def test_gap_zero_is_the_plain_rule_and_segments_do_not_share_runs() -> None:
    rng = np.random.default_rng(2)
    lengths = rng.integers(1, 40, 30)
    runs = Runs(lengths)
    mask = rng.random(int(lengths.sum())) < 0.8
    plain = runs.first_sustained(mask, 9)
    bridged = bridge_gaps(mask, np.zeros(mask.size, np.intp), runs.seg)
    np.testing.assert_array_equal(runs.first(runs.sustained(bridged, 9) & mask), plain)
    wide = bridge_gaps(mask, np.full(mask.size, 2, np.intp), runs.seg)
    for s, (a, n) in enumerate(zip(runs.starts, lengths, strict=True)):
        alone = first(sustained(bridge_gaps(mask[a : a + n], 2), 9) & mask[a : a + n], 0)
        got = runs.first(runs.sustained(wide, 9) & mask)[s]
        assert got == (-1 if alone is None else alone)


def test_the_gap_is_whole_frames_of_the_rate() -> None:
    assert [gap_rows(1 / r, 0.01) for r in (5, 20, 100, 240)] == [0, 0, 1, 2]
    assert gap_rows(0.0, 0.01) == 0 and gap_rows(1 / 240, 0.0) == 0
    with pytest.raises(InputError, match="pivot_gap_s"):
        TactemeConfig(pivot_gap_s=-0.01)


def test_a_flickering_cone_at_240_frames_per_second_is_named_batch_and_streamed() -> None:
    """A line turning about a point just beyond its end, 0.5 % of the taxels flickering.

    Without the bridge (the default) the flickered frames break every 0.5 s
    run of "about one end" (the estimate is near its limit); with
    ``pivot_gap_s`` 0.01 the cone is named, and the streamed sensor gives the
    batch's events.
    """
    from taxelkit.frames import TactileFrames
    from taxelkit.sensors.faults import Flicker, fault_model
    from taxelkit.smart.bank import SensorBank
    from taxelkit.smart.recogniser import SmartSensor, recognise

    from .test_robust_levels import PITCH, turning_line_frames

    turns = np.concatenate([np.zeros(60), np.linspace(0.0, 40.0, 480), np.full(240, 40.0)])
    rec = TactileFrames(
        turning_line_frames(turns, (-12.0, -8.0), 3.0), t_s=np.arange(turns.size) / 240.0,
        pitch_mm=PITCH,
    )  # fmt: skip
    for seed in (2, 6):
        seen = fault_model([Flicker(0.005)]).apply(
            rec, threshold=0.5, rng=np.random.default_rng(seed)
        )
        assert recognise(seen, threshold=0.5).identified is None
        cfg = TactemeConfig(pivot_gap_s=0.01)
        res = recognise(seen, threshold=0.5, config=cfg)
        assert res.identified == "cone"
        sensor = SmartSensor((16, 16), pitch_mm=PITCH, threshold=0.5, config=cfg)
        bank = SensorBank(1, (16, 16), pitch_mm=PITCH, threshold=0.5, config=cfg, batch_frames=50)
        for f, t in zip(seen.frames, seen.t_s, strict=True):
            sensor.push(f, t)
            bank.push(f[None], t)
        assert list(sensor.result().events) == list(res.events)
        assert list(bank.result(0).events) == list(res.events)
