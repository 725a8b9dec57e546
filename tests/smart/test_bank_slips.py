"""The bank's slip inputs, computed for many feeds at once, are those each scanner computes alone.

Random line and face segments (``test_slip_vectorised``'s, with axes that
wrap at +-90 deg, so that a feed may start turned over against the scanner's
last axis) are fed in random pieces to two sets of scanners: one computes its
features and first decisions itself, the other takes them from
:func:`~taxelkit.smart.bank_slips.slip_inputs`, all feeds of a step together.
What each ``extend`` returns, and every slip, must be equal. Then a whole
bank with every array touched (faulty rolls of the six objects) against
``recognise`` on each array's frames.
"""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.frames import TactileFrames
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import make_scenario
from taxelkit.sensors import BONNEVILLE_16X16
from taxelkit.sensors.faults import fault_model
from taxelkit.smart import bank_slips
from taxelkit.smart.bank import SensorBank
from taxelkit.smart.bank_slips import slip_inputs
from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.recogniser import recognise
from taxelkit.smart.slip import SlipConfig
from taxelkit.smart.slip_scan import SlipScanner
from taxelkit.smart.tacteme_table import OBJECTS

from .test_slip_vectorised import random_segment

_POINT, _LINE, _AREA = (int(c) for c in (ContactClass.POINT, ContactClass.LINE, ContactClass.AREA))


def fed_together(seed: int) -> tuple[list[list[object]], list[list[object]]]:
    """Segments fed alone and through ``slip_inputs``: (alone, together) results per scanner."""
    rng = np.random.default_rng(seed)
    rate = float(rng.choice([20.0, 240.0]))
    cfg = SlipConfig(slip_mm=float(rng.choice([0.25, 0.35])), hold_s=0.07)
    segments = []
    for _ in range(int(rng.integers(3, 9))):
        cls = int(rng.choice([_POINT, _LINE, _AREA]))
        n = int(rng.integers(1, 700))
        rows = random_segment(rng, n, rate, cls == _LINE)
        if rng.random() < 0.5:  # axes near +-90 deg: they wrap, and the oriented axis turns over
            rows[:, 2] = (90.0 + rng.normal(0, 4, n) + 90.0) % 180.0 - 90.0
        steps = sorted(set(rng.integers(1, max(2, n), int(rng.integers(0, 8))).tolist()))
        segments.append((cls, np.arange(n) + int(rng.integers(0, 50)), rows, [0, *steps, n]))
    k = int(rng.integers(2, 4))
    alone = [SlipScanner(cls, cfg, k=k) for cls, *_ in segments]
    together = [SlipScanner(cls, cfg, k=k) for cls, *_ in segments]
    got_alone: list[list[object]] = [[] for _ in segments]
    got_together: list[list[object]] = [[] for _ in segments]
    for step in range(max(len(c) for *_, c in segments) - 1):
        feeds = []
        for s, (_, frames, rows, cuts) in enumerate(segments):
            if step + 1 < len(cuts):
                a, b = cuts[step], cuts[step + 1]
                feeds.append((s, frames[a:b], rows[a:b]))
                got_alone[s].append(alone[s].extend(frames[a:b], rows[a:b]))
        inputs = slip_inputs([(together[s], rows) for s, _, rows in feeds])
        for (s, frames, rows), given in zip(feeds, inputs, strict=True):
            features, decided = (None, None) if given is None else given
            got_together[s].append(
                together[s].extend(frames, rows, features=features, decided=decided)
            )
    for s in range(len(segments)):
        got_alone[s] += [alone[s].close(), alone[s].all_slips()]
        got_together[s] += [together[s].close(), together[s].all_slips()]
    return got_alone, got_together


@pytest.mark.parametrize("seed", range(30))
def test_slip_inputs_of_many_feeds_are_those_each_scanner_computes(seed: int) -> None:
    alone, together = fed_together(seed)
    assert together == alone


def test_a_line_feed_turned_over_against_its_scanner_is_turned_back(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Without the turn, a line's ends swap at such feeds and some slips differ (the test bites)."""
    monkeypatch.setattr(bank_slips, "_orient", lambda *args: None)
    assert any(a != b for a, b in (fed_together(seed) for seed in range(30)))


def rolls(n: int, n_frames: int) -> np.ndarray:
    """``n`` faulty rolls at 240 frames/s, each from clear, padded with clear frames."""
    sensor = BONNEVILLE_16X16
    out = np.zeros((n, n_frames, 16, 16), bool)
    for i in range(n):
        rng = np.random.default_rng(i)
        sc = make_scenario(OBJECTS[i % len(OBJECTS)], rng=rng, rate_hz=240.0)
        rec = fault_model("all").apply(
            frames_from_scenario(sensor, sc, rng=rng), threshold=sensor.contact_threshold_mm, rng=i
        )
        images = rec.frames > sensor.contact_threshold_mm
        start = int(rng.integers(0, 40))
        take = min(n_frames - start, images.shape[0])
        out[i, start : start + take] = images[:take]
    return out


@pytest.mark.parametrize("batch_frames", [37, 256, 700])
def test_a_bank_with_every_array_touched_gives_each_its_own_events(batch_frames: int) -> None:
    """700: the whole recording is one batch (every array's segments are computed together)."""
    frames = rolls(6, 700)
    t = np.arange(frames.shape[1]) / 240.0
    bank = SensorBank(
        6, (16, 16), pitch_mm=BONNEVILLE_16X16.array.pitch_mm, batch_frames=batch_frames
    )
    got = [e for j in range(frames.shape[1]) for e in bank.push(frames[:, j], t[j])]
    got += bank.flush()
    for i in range(6):
        want = recognise(TactileFrames(frames[i], t, pitch_mm=BONNEVILLE_16X16.array.pitch_mm))
        assert [e for k, e in got if k == i] == list(want.events), i
        assert bank.result(i).slips == want.slips, i
