"""The vectorised fast paths give exactly what the rules they replace give.

Each fast path (the slip scanner's motions of a whole chunk, a line's drawn
ends from each row's first and last taxel, the bit-sliced neighbour count,
the bank's groups of arrays) is checked against a plain reference on random
input: equal, not close.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from taxelkit.frames import TactileFrames
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import make_scenario
from taxelkit.sensors import BONNEVILLE_16X16
from taxelkit.sensors.faults import fault_model
from taxelkit.smart import levels12
from taxelkit.smart.bank import SensorBank
from taxelkit.smart.cleaning import _backend, _crowded
from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.recogniser import recognise
from taxelkit.smart.slip import SLIP_KINDS, Slip, SlipConfig
from taxelkit.smart.slip_motion import window_means
from taxelkit.smart.slip_scan import SlipScanner
from taxelkit.smart.track_geometry import line_extents

PITCH = 1.7625


class PerFrameSlipScanner(SlipScanner):
    """The slip rule one frame at a time, as first written (the reference)."""

    def _scan(self, x: np.ndarray, fr: np.ndarray, base: int, first: int) -> list[Slip]:
        c, r, e = self.cur, self.ref, self.end
        cur_m, ref_m, end_m = window_means(x, c), window_means(x, r), window_means(x, e)
        out: list[Slip] = []
        for p in range(first, x.shape[0]):
            i = base + p
            if self._open is None:
                lo = i - c - r + 1
                if lo < self._anchor:
                    continue
                motion = self.motion_mm(ref_m[lo - base], cur_m[p - c + 1])
                if math.isnan(motion):
                    self._anchor, self._count = i - c + 1, 0
                    continue
                self._count = self._count + 1 if motion > self._limit_mm else 0
                if self._count >= self.hold:
                    q = max(0, p - self.hold - c + 2)
                    self._open_i = base + q
                    self._open = Slip(SLIP_KINDS[self.cls], int(fr[q]), int(fr[p]))
                    self._count = 0
                    out.append(self._open)
            elif p - 2 * e + 1 >= 0 and i - e + 1 >= self._open_i:
                step = self.motion_mm(end_m[p - 2 * e + 1], end_m[p - e + 1])
                if not step > self.config.still_mm:
                    done = Slip(
                        self._open.kind,
                        self._open.first_frame,
                        self._open.detected_frame,
                        max(self._open.first_frame, int(fr[p - e - e // 2])),
                        int(fr[p]),
                    )
                    self._replace(out, done)
                    self._open, self._anchor = None, i - e + 1
        return out


def footprint_rows(seed: int, n: int, rate_hz: float, cls: int) -> np.ndarray:
    """Rows (segment_scan.ROW_COLUMNS) of a footprint that rests, slides, turns and resizes."""
    rng = np.random.default_rng(seed)
    rows = np.zeros((n, 9))
    pos, theta, area = rng.uniform(-5, 5, 2), rng.uniform(-90, 90), rng.uniform(20, 80)
    vel, spin, phase_end, moving = np.zeros(2), 0.0, 0, True
    for k in range(n):
        if k >= phase_end:  # rest and slide (or turn) by turns, 0.2-1.5 s each
            moving = not moving
            phase_end = k + int(rng.uniform(0.2, 1.5) * rate_hz)
            vel = rng.normal(0, 6.0, 2) / rate_hz * moving
            spin = rng.normal(0, 40.0) / rate_hz * moving * rng.integers(0, 2)
        if rng.random() < 0.01:  # tipped, pressed: the area jumps
            area *= rng.uniform(0.6, 1.5)
        pos = pos + vel
        theta = (theta + spin + 90.0) % 180.0 - 90.0
        half = 6.0 + rng.normal(0, 0.2)
        elong = 4.0 if cls == ContactClass.LINE else rng.uniform(1.0, 2.5)
        lo, hi = -half + rng.normal(0, 0.3), half + rng.normal(0, 0.3)
        if cls != ContactClass.LINE or rng.random() < 0.05:
            lo = hi = np.nan  # ends not measured
        at = pos + rng.normal(0, 0.05, 2)  # the centre jitters, it does not wander
        rows[k] = [*at, theta, area + rng.normal(0, 1.0), elong, half, lo, hi, k / rate_hz]
    return rows


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    seed=st.integers(0, 2**31),
    n=st.integers(1, 900),
    rate_hz=st.sampled_from([20.0, 100.0, 240.0]),
    cls=st.sampled_from([int(ContactClass.AREA), int(ContactClass.LINE)]),
    chunk=st.sampled_from([1, 5, 64, 1000]),
    slip_mm=st.sampled_from([0.05, 0.35]),
)
def test_slip_scanner_equals_the_per_frame_rule(
    seed: int, n: int, rate_hz: float, cls: int, chunk: int, slip_mm: float
) -> None:
    rows = footprint_rows(seed, n, rate_hz, cls)
    config = SlipConfig(slip_mm=slip_mm, line_slip_mm=2 * slip_mm)
    fast, slow = SlipScanner(cls, config, k=3), PerFrameSlipScanner(cls, config, k=3)
    got, want = [], []
    for a in range(0, n, chunk):
        frames = np.arange(a, min(n, a + chunk)) + 7
        got += fast.extend(frames, rows[a : a + chunk])
        want += slow.extend(frames, rows[a : a + chunk])
    assert got == want
    assert fast.close() == slow.close() and fast.all_slips() == slow.all_slips()


def test_the_slip_scanner_finds_slips_to_compare() -> None:
    """The random footprints above do slip (the equality test is not vacuous)."""
    found = 0
    for seed in range(10):
        rows = footprint_rows(seed, 600, 100.0, int(ContactClass.AREA))
        scan = SlipScanner(int(ContactClass.AREA), SlipConfig(), k=3)
        scan.extend(np.arange(600), rows)
        found += len(scan.all_slips())
    assert found >= 5


def extents_per_taxel(images: np.ndarray, centre: np.ndarray, angle: np.ndarray) -> np.ndarray:
    """Every contact taxel projected on the axis: the lowest and highest, widened."""
    rows, cols = images.shape[1:]
    u = (np.arange(cols) - 0.5 * (cols - 1)) * PITCH
    v = (np.arange(rows) - 0.5 * (rows - 1)) * PITCH
    t = np.deg2rad(angle)
    cos, sin = np.cos(t)[:, None, None], np.sin(t)[:, None, None]
    proj = (u[None, None, :] - centre[:, 0, None, None]) * cos + (
        v[None, :, None] - centre[:, 1, None, None]
    ) * sin
    low = np.min(proj, axis=(1, 2), where=images, initial=np.inf) - 0.5 * PITCH
    high = np.max(proj, axis=(1, 2), where=images, initial=-np.inf) + 0.5 * PITCH
    return np.stack([low, high], axis=1)


@pytest.mark.parametrize("shape", [(16, 16), (8, 8), (12, 8), (8, 12), (32, 32), (4, 16)])
def test_line_extents_equal_every_taxels_projection(shape: tuple[int, int]) -> None:
    rng = np.random.default_rng(sum(shape))
    n = 3000
    images = rng.random((n, *shape)) < rng.random((n, 1, 1)) * 0.4
    images[:, 0, 0] |= ~images.reshape(n, -1).any(axis=1)  # every image has contact
    centre = rng.normal(0, 4, (n, 2))
    angle = rng.uniform(-90, 90, n)
    angle[:100] = rng.choice([0.0, 90.0, -90.0, 45.0, 180.0], 100)  # cos or sin exactly 0
    np.testing.assert_array_equal(
        line_extents(images, centre, angle, PITCH), extents_per_taxel(images, centre, angle)
    )


@pytest.mark.parametrize("cols", [5, 8, 16, 33, 100])
def test_crowded_is_two_or_more_of_the_eight_neighbours(cols: int) -> None:
    rng = np.random.default_rng(cols)
    images = rng.random((300, 12, cols)) < rng.random((300, 1, 1))
    padded = np.pad(images, ((0, 0), (1, 1), (1, 1)))
    count = sum(
        padded[:, 1 + dy : 13 + dy, 1 + dx : cols + 1 + dx].astype(int)
        for dy in (-1, 0, 1)
        for dx in (-1, 0, 1)
        if dy or dx
    )
    ops = _backend(cols)
    got = ops.unpack(_crowded(ops, ops.pack(images)), cols)
    np.testing.assert_array_equal(got, count >= 2)


def test_bank_groups_of_arrays_give_each_array_its_own_events(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """Arrays cleaned and measured a few at a time (quiet, rolling, faulty) as if alone."""
    monkeypatch.setattr(levels12, "GROUP_FRAMES", 3 * 32)  # three arrays a group
    sensor, thr = BONNEVILLE_16X16, BONNEVILLE_16X16.contact_threshold_mm
    recs = []
    for k in range(4):
        sc = make_scenario(["cube", "cylinder", "cone", "sphere"][k], rng=k, rate_hz=100.0)
        rec = frames_from_scenario(sensor, sc, rng=k)
        if k % 2:
            rec = fault_model("all").apply(rec, threshold=thr, rng=k)
        recs.append(rec)
    n_frames = max(r.n_frames for r in recs) + 10
    order = [None, 0, None, 1, 2, None, None, 3, None, 0]  # quiet arrays between
    frames = np.zeros((len(order), n_frames, 16, 16))
    for i, k in enumerate(order):
        if k is not None:
            start = 3 * i
            take = min(recs[k].n_frames, n_frames - start)
            frames[i, start : start + take] = recs[k].frames[:take]
    t_s = np.arange(n_frames) / 100.0
    bank = SensorBank(len(order), (16, 16), pitch_mm=PITCH, threshold=thr, batch_frames=32)
    got = [x for j in range(n_frames) for x in bank.push(frames[:, j], t_s[j])] + bank.flush()
    for i in range(len(order)):
        want = recognise(TactileFrames(frames[i], t_s, pitch_mm=PITCH), threshold=thr)
        assert [e for k, e in got if k == i] == list(want.events), i
        np.testing.assert_array_equal(np.asarray(bank.classes(i)), want.classes)
    assert sum(1 for _, e in got if e.kind == "tacteme") > 8
