"""The vectorised fast paths give exactly what the rules they replace give.

Each fast path (a line's drawn ends from each row's first and last taxel,
the bit-sliced neighbour count, the bank's groups of arrays) is checked
against a plain reference on random input: equal, not close.
"""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.frames import TactileFrames
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import make_scenario
from taxelkit.sensors import BONNEVILLE_16X16
from taxelkit.sensors.faults import fault_model
from taxelkit.smart import levels12
from taxelkit.smart.bank import SensorBank
from taxelkit.smart.cleaning import _backend, _crowded
from taxelkit.smart.contact_classes import DEFAULT_CONFIDENCE, HAND_SET, ContactClass
from taxelkit.smart.line_extents import line_extents
from taxelkit.smart.recogniser import recognise

PITCH = 1.7625


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


@pytest.mark.parametrize("cols", [5, 8, 16, 24, 64, 100])
def test_packed_rows_per_frame_tests_and_masks(cols: int) -> None:
    """``any_per_frame`` and ``per_frame`` of the packed backends: NumPy's per-frame answers."""
    rng = np.random.default_rng(cols)
    images = rng.random((300, 7, cols)) < rng.choice([0.0, 0.002, 0.3], (300, 1, 1))
    ops = _backend(cols)
    words = ops.pack(images)
    expected = images.reshape(300, -1).any(axis=1)
    np.testing.assert_array_equal(ops.any_per_frame(words), expected)
    np.testing.assert_array_equal(ops.any_per_frame(words[::2]), expected[::2])  # a view
    flags = rng.random(300) < 0.5
    masked = ops.unpack(words & ops.per_frame(flags, words), cols)
    np.testing.assert_array_equal(masked, images & flags[:, None, None])


@pytest.mark.parametrize("cleaning", [True, False])
def test_levels12_of_equal_frames_computed_once_are_those_of_every_frame(
    monkeypatch: pytest.MonkeyPatch, cleaning: bool
) -> None:
    """Runs of equal frames (a contact held still) measured once: the same classes and rows."""
    sensor, thr = BONNEVILLE_16X16, BONNEVILLE_16X16.contact_threshold_mm
    frames = []
    for k, name in enumerate(["cube", "cylinder", "cone"]):
        rec = frames_from_scenario(sensor, make_scenario(name, rng=k, rate_hz=240.0), rng=k)
        f = rec.frames[:600] > thr
        if k == 2:
            f = fault_model("all").apply(rec, threshold=thr, rng=k).frames[:600] > thr
        frames.append(np.pad(f, ((0, 600 - f.shape[0]), (0, 0), (0, 0))))
    images = np.stack(frames)  # (3, 600, 16, 16)
    t_s = np.broadcast_to(np.arange(600) / 240.0, (3, 600))
    options = {"cleaning": levels12.DEFAULT_CLEANING if cleaning else None}
    got, steps = [], range(0, 600, 150)
    for worth in (1.0, 0.0):  # every run of equal frames measured once; every frame measured
        monkeypatch.setattr(levels12, "_REPEATS_WORTH", worth)
        lv = levels12.ChunkLevels12(
            3, (16, 16), pitch_mm=PITCH, threshold=thr, network=HAND_SET,
            confidence=DEFAULT_CONFIDENCE, limits=levels12.DEFAULT_LIMITS, **options,
        )  # fmt: skip
        got.append([lv.process(images[:, a : a + 150], t_s[:, a : a + 150]) for a in steps])
    for (cls_a, rows_a), (cls_b, rows_b) in zip(*got, strict=True):
        np.testing.assert_array_equal(cls_a, cls_b)
        np.testing.assert_array_equal(rows_a, rows_b)
    classes = np.concatenate([c for c, _ in got[0]], axis=1)
    assert np.count_nonzero(classes == ContactClass.LINE) > 100  # lines (their extents) among them


@pytest.mark.parametrize("cleaning", [True, False])
def test_bank_buffers_bool_frames_packed_with_the_same_events(cleaning: bool) -> None:
    """Bool frames (buffered packed) and the same frames as 0/1 floats: the same events."""
    sensor, thr = BONNEVILLE_16X16, BONNEVILLE_16X16.contact_threshold_mm
    frames = np.zeros((4, 700, 16, 16), bool)
    for k, name in enumerate(["cube", "cylinder", "cone"]):
        rec = frames_from_scenario(sensor, make_scenario(name, rng=k, rate_hz=100.0), rng=k)
        if k == 1:
            rec = fault_model("all").apply(rec, threshold=thr, rng=k)
        take = min(rec.n_frames, 700 - 40 * k)
        frames[k + (k > 0), 40 * k : 40 * k + take] = rec.frames[:take] > thr
    options = {"cleaning": levels12.DEFAULT_CLEANING if cleaning else None}
    got = []
    for kind in (bool, float):
        bank = SensorBank(4, (16, 16), pitch_mm=PITCH, threshold=0.5, batch_frames=64, **options)
        events = [x for j in range(700) for x in bank.push(frames[:, j].astype(kind), j / 100.0)]
        got.append((events + bank.flush(), [np.asarray(bank.classes(i)) for i in range(4)]))
    assert got[0][0] == got[1][0]
    assert sum(1 for _, e in got[0][0] if e.kind == "tacteme") > 4
    for a, b in zip(got[0][1], got[1][1], strict=True):
        np.testing.assert_array_equal(a, b)
