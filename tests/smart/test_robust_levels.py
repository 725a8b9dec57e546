"""The robust pipeline: limits with hysteresis, Level 3 in time, sliding lines, lift-off grace."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.frames import TactileFrames
from taxelkit.motion.engines import scenario_from_engine
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.sensors import BONNEVILLE_16X16
from taxelkit.sensors.frame_rate import frames_at_rate
from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.contact_limits import ContactLimits, LimitState, apply_limits, limit_one
from taxelkit.smart.hysteresis import schmitt
from taxelkit.smart.recogniser import SmartSensor, recognise
from taxelkit.smart.tacteme_table import OBJECTS, Tacteme
from taxelkit.smart.tactemes import PAPER_LEVEL3, TactemeConfig, debounce_counts

PITCH = 1.7625
LINE, POINT, INDET = (
    int(ContactClass.LINE),
    int(ContactClass.POINT),
    int(ContactClass.INDETERMINATE),
)


def test_schmitt_trigger_holds_its_state_inside_the_band() -> None:
    v = np.array([0.0, 5.0, 6.5, 5.5, 5.2, 4.0, 5.5, 7.0])
    np.testing.assert_array_equal(
        schmitt(v, 6.0, 5.1), [False, False, True, True, True, False, False, True]
    )
    assert schmitt(np.array([5.5]), 6.0, 5.1, start=True)[0]


def test_limits_batch_equals_one_frame_at_a_time() -> None:
    rng = np.random.default_rng(4)
    classes = rng.choice([POINT, LINE, INDET], 200).astype(np.int8)
    n = rng.integers(0, 12, 200)
    length = rng.uniform(2.0, 9.0, 200)
    elong = rng.uniform(1.0, 5.0, 200)
    area = rng.uniform(5.0, 40.0, 200)
    lim = ContactLimits()
    batch = apply_limits(classes, n, length, elong, lim, area_mm2=area)
    state = LimitState()
    one = [
        apply_limits(classes[i : i + 1], n[i : i + 1], length[i : i + 1], elong[i : i + 1], lim,
                     area_mm2=area[i : i + 1], state=state)[0]
        for i in range(200)
    ]  # fmt: skip
    np.testing.assert_array_equal(batch, one)
    scalar_state = LimitState()
    scalar = [
        limit_one(int(c), int(k), float(x), float(e), float(ar), lim, scalar_state)
        for c, k, x, e, ar in zip(classes, n, length, elong, area, strict=True)
    ]
    np.testing.assert_array_equal(batch, scalar)  # the streaming path's plain-Python twin
    assert np.all(batch[(classes == LINE) & (length < 5.1)] != LINE)
    assert np.all(
        batch[(classes == int(ContactClass.AREA)) & (area < 20.0)] != int(ContactClass.AREA)
    )


def _limits_in_pieces_and_one_at_a_time(
    classes: np.ndarray,
    n: np.ndarray,
    length: np.ndarray,
    elong: np.ndarray,
    area: np.ndarray,
    t: np.ndarray,
    lim: ContactLimits,
    step: int,
) -> np.ndarray:
    """The batch classes, checked equal to pieces of ``step`` frames and to ``limit_one``."""
    batch = apply_limits(classes, n, length, elong, lim, area_mm2=area, t_s=t)
    state = LimitState()
    pieces = [
        apply_limits(classes[i : i + step], n[i : i + step], length[i : i + step],
                     elong[i : i + step], lim, area_mm2=area[i : i + step], state=state,
                     t_s=t[i : i + step])
        for i in range(0, classes.size, step)
    ]  # fmt: skip
    np.testing.assert_array_equal(batch, np.concatenate(pieces))
    one = LimitState()
    scalar = [
        limit_one(int(c), int(k), float(x), float(e), float(ar), lim, one, float(ts))
        for c, k, x, e, ar, ts in zip(classes, n, length, elong, area, t, strict=True)
    ]
    np.testing.assert_array_equal(batch, scalar)  # the streaming path's plain-Python twin
    return batch


def test_limits_with_times_batch_equals_one_frame_at_a_time() -> None:
    rng = np.random.default_rng(5)
    m = 300
    classes = rng.choice([POINT, INDET, LINE, int(ContactClass.AREA)], m).astype(np.int8)
    n = rng.integers(0, 14, m)
    length = rng.choice([4.0, 5.3, 5.8, 6.2, 8.0], m)  # around the band 5.1-6 mm
    elong = rng.uniform(1.0, 3.0, m)
    area = rng.choice([18.0, 22.0, 24.0, 27.0, 31.0], m)  # around the band 20-26 mm^2
    t = np.cumsum(rng.choice([0.01, 0.05, 0.2], m))  # irregular intervals
    lim = ContactLimits()
    batch = _limits_in_pieces_and_one_at_a_time(classes, n, length, elong, area, t, lim, 7)
    assert np.any((classes == LINE) & (length >= 6.0) & (batch != LINE))  # a line not yet held
    # without a dwell, the times change nothing
    now = ContactLimits(area_enter_s=0.0, line_enter_s=0.0)
    np.testing.assert_array_equal(
        apply_limits(classes, n, length, elong, now, area_mm2=area, t_s=t),
        apply_limits(classes, n, length, elong, now, area_mm2=area),
    )
    with pytest.raises(InputError, match="area_enter_s"):
        ContactLimits(area_enter_s=-0.1)
    with pytest.raises(InputError, match="line_enter_s"):
        ContactLimits(line_enter_s=-0.1)


def _ball_with_a_spike(rate_hz: float) -> TactileFrames:
    """A ball's 7-taxel disc (22 mm^2, inside the area band) with 3 more taxels for one frame."""
    t = int(2.0 * rate_hz)
    frames = np.zeros((t, 16, 16), bool)
    frames[:, 7:10, 6:8] = True  # 3 x 2
    frames[:, 8, 5] = True  # 7 taxels
    frames[t // 2, 9:11, 8] = True  # two more beside it, and one below
    frames[t // 2, 10, 7] = True
    return TactileFrames(frames, t_s=np.arange(t) / rate_hz, pitch_mm=PITCH)


def _paths_agree(rec: TactileFrames, classes: np.ndarray, chunk_frames: int) -> None:
    """The streaming sensor and the chunked Levels 1-2 (the bank's, beside a clear array, in
    chunks of ``chunk_frames``) give the batch's ``classes`` (over the whole chunks)."""
    from taxelkit.smart.contact_classes import DEFAULT_CONFIDENCE, HAND_SET
    from taxelkit.smart.levels12 import DEFAULT_LIMITS, ChunkLevels12

    sensor = SmartSensor(rec.frames.shape[1:], pitch_mm=PITCH, cleaning=None)
    sensor.push_many(rec.frames, rec.t_s)
    np.testing.assert_array_equal(sensor.result().classes, classes)
    chunk = ChunkLevels12(
        2, rec.frames.shape[1:], pitch_mm=PITCH, threshold=0.5, network=HAND_SET,
        confidence=DEFAULT_CONFIDENCE, cleaning=None, limits=DEFAULT_LIMITS,
    )  # fmt: skip
    frames = np.stack([rec.frames, np.zeros_like(rec.frames)])
    times = np.stack([rec.t_s, rec.t_s])
    n = rec.frames.shape[0] // chunk_frames * chunk_frames
    got = [
        chunk.process(frames[:, a : a + chunk_frames], times[:, a : a + chunk_frames])[0]
        for a in range(0, n, chunk_frames)
    ]
    np.testing.assert_array_equal(np.concatenate(got, axis=1)[0], classes[:n])


@pytest.mark.parametrize("rate_hz", [20.0, 100.0])
def test_one_frame_over_the_area_mark_does_not_make_an_area(rate_hz: float) -> None:
    rec = _ball_with_a_spike(rate_hz)
    held = recognise(rec, cleaning=None)
    assert int(ContactClass.AREA) not in held.classes.tolist()
    assert "AC" not in [n for n, _ in held.tactemes]
    at_once = recognise(rec, cleaning=None, limits=ContactLimits(area_enter_s=0.0))
    assert int(ContactClass.AREA) in at_once.classes.tolist()  # latched by the hysteresis
    _paths_agree(rec, held.classes, rec.frames.shape[0] // 3)  # in three chunks


def _bar_with_a_flicker(rate_hz: float) -> TactileFrames:
    """A ball's disc pressed to a 3-taxel bar (5.3 mm), one frame a fourth taxel in its row."""
    t = int(2.0 * rate_hz)
    frames = np.zeros((t, 16, 16), bool)
    frames[:, 6:9, 7] = True  # three taxels in a column: inside the line's band 5.1-6 mm
    frames[t // 2, 9, 7] = True  # a flickering fourth: 7 mm, over the line's mark, one frame
    return TactileFrames(frames, t_s=np.arange(t) / rate_hz, pitch_mm=PITCH)


@pytest.mark.parametrize("rate_hz", [20.0, 240.0])
def test_one_frame_over_the_line_mark_does_not_make_a_line(rate_hz: float) -> None:
    rec = _bar_with_a_flicker(rate_hz)
    held = recognise(rec, cleaning=None)
    assert LINE not in held.classes.tolist()
    assert "LC" not in [n for n, _ in held.tactemes]
    at_once = recognise(rec, cleaning=None, limits=ContactLimits(line_enter_s=0.0))
    t = rec.frames.shape[0]
    assert np.all(at_once.classes[t // 2 : t // 2 + 5] == LINE)  # latched by the hysteresis
    _paths_agree(rec, held.classes, t // 2)  # cut at the flicker: its run carried over
    # two frames in a row over the mark make a line (a real edge is seen twice)
    frames2 = rec.frames.copy()
    frames2[t // 2 + 1, 9, 7] = True
    two = recognise(TactileFrames(frames2, rec.t_s, pitch_mm=PITCH), cleaning=None)
    assert two.classes[t // 2 + 1] == LINE and two.classes[t // 2] != LINE
    # a long line (line_confirm_mm) is no flicker: it is a line from its first frame
    long = np.zeros_like(rec.frames)
    long[t // 2 :, 8, 4:10] = True  # six taxels: 10.6 mm
    first = recognise(TactileFrames(long, rec.t_s, pitch_mm=PITCH), cleaning=None).classes
    assert first[t // 2] == LINE and first[t // 2 - 1] != LINE


def test_a_face_shrinking_to_a_bar_does_not_latch_a_line() -> None:
    # a face of 4 x 3 taxels (7 mm long, not a line) shrinks onto a rim: a 3-taxel bar
    frames = np.zeros((40, 16, 16), bool)
    frames[2:20, 6:10, 6:9] = True
    frames[20:38, 6:9, 7] = True
    rec = TactileFrames(frames, t_s=np.arange(40) / 20.0, pitch_mm=PITCH)
    robust = recognise(rec, cleaning=None)
    assert LINE not in robust.classes.tolist()
    assert "AC -> LC" not in [n for n, _ in robust.tactemes]
    old = recognise(rec, cleaning=None, limits=ContactLimits(line_enter_s=0.0))
    assert old.classes[30] == LINE  # the face's length latched the trigger
    _paths_agree(rec, robust.classes, 10)


def test_a_three_taxel_bar_is_no_edge_but_a_long_line_is() -> None:
    frames = np.zeros((30, 16, 16), bool)
    frames[2:14, 8, 6:9] = True  # three taxels: 5.3 mm
    frames[16:28, 8, 4:10] = True  # six taxels: 10.6 mm
    rec = TactileFrames(frames, t_s=np.arange(30) / 20.0, pitch_mm=PITCH)
    robust = recognise(rec, cleaning=None).classes
    paper = recognise(rec, cleaning=None, limits=None).classes
    assert paper[5] == LINE and robust[5] != LINE
    assert paper[20] == LINE and robust[20] == LINE


def test_an_edge_tipped_onto_a_vertex_does_not_hold_the_line() -> None:
    # an edge (seven taxels, 12.3 mm) tips onto a vertex that reads as a bar of three
    # taxels (5.3 mm, inside the hysteresis band) across it, then lifts
    frames = np.zeros((50, 16, 16), bool)
    frames[2:20, 6, 4:11] = True
    frames[20:40, 10:13, 12] = True
    rec = TactileFrames(frames, t_s=np.arange(50) / 20.0, pitch_mm=PITCH)
    robust = recognise(rec, cleaning=None)
    assert robust.classes[10] == LINE and LINE not in robust.classes[20:40].tolist()
    assert "LCMT" not in [n for n, _ in robust.tactemes]  # no line "turned" onto the vertex
    held = recognise(rec, cleaning=None, limits=ContactLimits(line_drop=0.0))
    assert set(held.classes[20:40].tolist()) == {LINE}  # the hysteresis held the bar
    assert "LCMT" in [n for n, _ in held.tactemes]
    _paths_agree(rec, robust.classes, 10)
    # a line that shortens by a taxel or two stays one
    short = np.zeros((30, 16, 16), bool)
    short[2:14, 8, 4:10] = True  # 10.6 mm
    short[14:28, 8, 5:8] = True  # 5.3 mm: above half of it
    rec = TactileFrames(short, t_s=np.arange(30) / 20.0, pitch_mm=PITCH)
    assert set(recognise(rec, cleaning=None).classes[14:28].tolist()) == {LINE}
    with pytest.raises(InputError, match="line_drop"):
        ContactLimits(line_drop=1.5)


def test_the_line_drop_is_the_same_in_every_limits_path() -> None:
    from taxelkit.smart.limits_rows import limits_rows

    rng = np.random.default_rng(7)
    m = 400
    classes = rng.choice([POINT, INDET, LINE], m).astype(np.int8)
    n = rng.integers(0, 14, m) * (rng.random(m) < 0.9)
    length = rng.choice([3.0, 5.3, 5.8, 7.0, 10.6, 12.3, 14.0], m)
    elong = rng.uniform(1.0, 4.0, m)
    area = rng.uniform(5.0, 30.0, m)
    t = np.cumsum(rng.choice([0.01, 0.05], m))
    lim = ContactLimits()
    batch = _limits_in_pieces_and_one_at_a_time(classes, n, length, elong, area, t, lim, 9)
    no_drop = ContactLimits(line_drop=0.0)
    off = apply_limits(classes, n, length, elong, no_drop, area_mm2=area, t_s=t)
    assert np.any(batch != off)  # the rule bites on this sequence
    rows_state = (
        np.zeros(1, bool), np.zeros(1, bool), np.zeros(1, np.int64), np.full(1, np.nan),
        np.zeros(1, np.int64), np.zeros(1),
    )  # fmt: skip
    got = []
    for i in range(0, m, 16):
        out, rows_state = limits_rows(
            classes[None, i : i + 16], n[None, i : i + 16], area[None, i : i + 16],
            elong[None, i : i + 16], 0.5 * length[None, i : i + 16], t[None, i : i + 16],
            lim, rows_state,
        )  # fmt: skip
        got.append(out[0])
    np.testing.assert_array_equal(batch, np.concatenate(got))


def test_a_two_by_two_point_is_a_point_at_a_coarse_pitch() -> None:
    frames = np.zeros((10, 8, 8), bool)
    frames[1:9, 3:5, 3:5] = True
    rec = TactileFrames(frames, t_s=np.arange(10) / 20.0, pitch_mm=2.5)  # 25 mm^2
    assert recognise(rec, cleaning=None).classes[4] == POINT
    assert recognise(rec, cleaning=None, limits=None).classes[4] != POINT


def test_a_ball_disc_on_a_fine_array_is_a_point_in_every_path() -> None:
    # a 4 x 4 block at 1 mm (16 mm^2, elongation 1): more than four taxels, less than a face
    frames = np.zeros((12, 32, 32), bool)
    frames[1:11, 14:18, 14:18] = True
    t_s = np.arange(12) / 20.0
    rec = TactileFrames(frames, t_s=t_s, pitch_mm=1.0)
    robust = recognise(rec, cleaning=None).classes
    assert robust[5] == POINT
    off = ContactLimits(point_max_area_mm2=None)
    assert recognise(rec, cleaning=None, limits=off).classes[5] != POINT
    # the streaming sensor (one frame at a time) and the bank's chunked Levels 1-2 agree
    sensor = SmartSensor((32, 32), pitch_mm=1.0, cleaning=None)
    sensor.push_many(frames, t_s)
    np.testing.assert_array_equal(sensor.result().classes, robust)
    from taxelkit.smart.contact_classes import DEFAULT_CONFIDENCE, HAND_SET
    from taxelkit.smart.levels12 import DEFAULT_LIMITS, ChunkLevels12

    chunk = ChunkLevels12(
        1, (32, 32), pitch_mm=1.0, threshold=0.5, network=HAND_SET,
        confidence=DEFAULT_CONFIDENCE, cleaning=None, limits=DEFAULT_LIMITS,
    )  # fmt: skip
    classes, _ = chunk.process(frames[None], t_s[None])
    np.testing.assert_array_equal(classes[0], robust)


def test_debounce_counts_are_time_based_but_never_under_k_frames() -> None:
    cfg = TactemeConfig()
    assert debounce_counts(cfg, 1 / 20) == (3, 4)
    assert debounce_counts(cfg, 1 / 240) == (36, 48)
    assert debounce_counts(cfg, 1 / 5) == (2, 2)
    assert debounce_counts(PAPER_LEVEL3, 1 / 240) == (3, 3)
    assert debounce_counts(cfg, None) == (2, 2)


def line_frames(centres: list[tuple[int, int]], half: int = 4) -> np.ndarray:
    """A horizontal line of 2 half + 1 taxels centred at each (row, col), one per frame."""
    out = np.zeros((len(centres) + 8, 16, 16), bool)
    for t, (r, c) in enumerate(centres, start=4):
        out[t, r, c - half : c + half + 1] = True
    return out


def test_a_line_sliding_along_itself_is_not_rolling() -> None:
    cols = [5] * 6 + [5 + k // 3 for k in range(18)] + [11] * 6
    rec = TactileFrames(
        line_frames([(8, c) for c in cols]), t_s=np.arange(38) / 20.0, pitch_mm=PITCH
    )
    paper = recognise(rec, cleaning=None, config=TactemeConfig(slip=None))
    names = [n for n, _ in paper.tactemes]
    assert "LC slides along itself" in names and "LCMP" not in names
    assert paper.identified == "unknown"
    r = recognise(rec, cleaning=None)  # the slip detector: the slide is slip, not shape
    assert [s.kind for s in r.slips] == ["line slides along itself"]
    assert ("withheld", "LC slides along itself") in [(e.kind, e.value) for e in r.events]
    assert r.identified is None and r.verdict.reason == "slid"
    rolled = [(5 + k // 3, 8) for k in range(18)]  # across itself: a cylinder's roll
    rec2 = TactileFrames(
        line_frames([(5, 8)] * 6 + rolled), t_s=np.arange(32) / 20.0, pitch_mm=PITCH
    )
    r2 = recognise(rec2, cleaning=None)
    assert r2.identified == "cylinder" and r2.slips == ()


def test_evidence_survives_a_short_loss_of_contact() -> None:
    frames = line_frames([(5, 8)] * 6 + [(5 + k // 3, 8) for k in range(18)])
    frames[14] = False  # 50 ms without contact at 20 Hz, mid-roll
    rec = TactileFrames(frames, t_s=np.arange(frames.shape[0]) / 20.0, pitch_mm=PITCH)
    robust = recognise(rec, cleaning=None)
    assert [e.kind for e in robust.events].count("lifted") == 1  # only at the end
    assert robust.identified == "cylinder"
    frames[13:16] = False  # 150 ms: the paper's k = 3 frames of no contact end it
    paper = recognise(
        TactileFrames(frames, t_s=rec.t_s, pitch_mm=PITCH), cleaning=None, config=PAPER_LEVEL3
    )
    assert [e.kind for e in paper.events].count("lifted") == 2


@pytest.mark.parametrize("name", OBJECTS)
def test_the_same_roll_at_240_100_20_and_5_frames_per_s_gives_the_same_tactemes(
    name: str,
) -> None:
    """Level 3 is defined in time and distance: resampling changes nothing the frames resolve."""
    sc = scenario_from_engine("kinematic", name, rng=300 + OBJECTS.index(name), rate_hz=240.0)
    rec = frames_from_scenario(BONNEVILLE_16X16, sc, rng=0)
    base = recognise(rec)
    assert base.identified == name
    for rate in (100.0, 20.0, 5.0):
        r = recognise(frames_at_rate(rec, rate))
        assert r.identified == name, rate
        assert {n for n, _ in r.tactemes} == {n for n, _ in base.tactemes}, rate


def test_streaming_equals_batch_at_240_frames_per_s_with_faults() -> None:
    from taxelkit.sensors.faults import fault_model

    sc = scenario_from_engine("kinematic", "cube", rng=5, rate_hz=240.0)
    rec = fault_model("all").apply(
        frames_from_scenario(BONNEVILLE_16X16, sc, rng=5), threshold=0.03, rng=5
    )
    batch = recognise(rec)
    sensor = SmartSensor((16, 16), pitch_mm=rec.pitch_mm)
    for f, t in zip(rec.frames, rec.t_s, strict=True):
        sensor.push(f, t)
    assert list(sensor.result().events) == list(batch.events)


def test_every_verdict_says_why() -> None:
    from taxelkit.smart.elimination import explain

    undecided = explain([("LC", 3), ("LCM", 9), ("LCMT", 20)])
    assert undecided.outcome is None and undecided.candidates == ("cone", "truncated-cone")
    assert {t for t, _, _ in undecided.deciders} == {"LCMT about one end", "LCMT in an arc"}
    assert "undecided between cone, truncated-cone" in undecided.sentence()
    gone = dict((o, t) for o, t, _, _ in undecided.eliminated)
    assert gone["sphere"] == "LC" and gone["cube"] == "LCM" and gone["cylinder"] == "LCMT"
    unknown = explain([("LC", 3), ("LCMP", 9), ("LCMT", 20)])
    assert unknown.outcome == "unknown" and "LCMT at frame 20" in unknown.sentence()
    rec = TactileFrames(
        line_frames([(5, 8)] * 6 + [(5 + k // 3, 8) for k in range(18)]),
        t_s=np.arange(32) / 20.0,
        pitch_mm=PITCH,
    )
    doc = recognise(rec, cleaning=None).to_json()
    assert doc["why"]["outcome"] == "cylinder" and doc["why"]["eliminated"]


@pytest.mark.parametrize("seed", [9, 33, 38])
def test_short_runs_of_a_ball_show_their_orthogonal_turn(
    seed: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Balls whose runs are barely longer than a 3 mm leg: the chord test finds the corner.

    Seeds found by searching 200 kinematic sphere scripts for rolls that the
    leg test alone leaves undecided (5 of the 200).
    """
    import taxelkit.smart.tactemes as tactemes_module

    sc = scenario_from_engine("kinematic", "sphere", rng=seed, rate_hz=20.0)
    rec = frames_from_scenario(BONNEVILLE_16X16, sc, rng=seed)
    assert recognise(rec).identified == "sphere"
    monkeypatch.setattr(tactemes_module, "_corner_turn", lambda *a, **k: None)
    assert recognise(rec).identified is None  # legs alone miss the corner


def turning_line_frames(
    turns_deg: np.ndarray, pivot_mm: tuple[float, float], from_mm: float, pitch: float = PITCH
) -> np.ndarray:
    """A 20 mm line from ``from_mm`` to ``from_mm + 20`` beyond ``pivot_mm``, turning about it."""
    ax = (np.arange(16) - 7.5) * pitch
    x, y = np.meshgrid(ax, ax)
    px, py = pivot_mm
    out = np.zeros((turns_deg.size, 16, 16), dtype=bool)
    for i, deg in enumerate(turns_deg):
        t = np.deg2rad(deg)
        u, v = np.cos(t), np.sin(t)
        along = (x - px) * u + (y - py) * v
        across = -(x - px) * v + (y - py) * u
        out[i] = (np.abs(across) <= 0.9) & (along >= from_mm) & (along <= from_mm + 20.0)
    return out


def arc_frames(turns_deg: np.ndarray) -> np.ndarray:
    """A 20 mm line rotating about a pivot 16 mm beyond its end (pivot ratio 2.6)."""
    return turning_line_frames(turns_deg, (-26.0, -5.0), 16.0)


def end_frames(turns_deg: np.ndarray) -> np.ndarray:
    """A 20 mm line rotating about its own end (a cone about its apex, pivot ratio 1)."""
    return turning_line_frames(turns_deg, (-12.0, -8.0), 0.0)


def test_a_short_turn_about_a_far_pivot_reads_as_an_arc() -> None:
    """A truncated cone that stops after 16 deg: its pivot is far, an arc already (not at 20)."""
    turns = np.concatenate([np.zeros(10), np.linspace(0.0, 16.0, 40), np.full(30, 16.0)])
    rec = TactileFrames(arc_frames(turns), t_s=np.arange(turns.size) / 20.0, pitch_mm=PITCH)
    early = recognise(rec, cleaning=None)
    names = [n for n, _ in early.tactemes]
    assert "LCMT in an arc" in names and "LCMT about one end" not in names
    assert early.identified == "truncated-cone"
    late = recognise(rec, cleaning=None, config=TactemeConfig(pivot_arc_turn_deg=20.0))
    assert "LCMT in an arc" not in [n for n, _ in late.tactemes]
    assert late.identified is None
    sensor = SmartSensor((16, 16), pitch_mm=PITCH, cleaning=None)
    for f, t in zip(rec.frames, rec.t_s, strict=True):
        sensor.push(f, t)
    assert list(sensor.result().events) == list(early.events)


def test_the_pivot_of_a_line_too_short_for_the_grid_is_not_read() -> None:
    """The same 20 mm arc with a limit of 13 pitches (23 mm): no pivot verdict, batch or stream."""
    turns = np.concatenate([np.zeros(10), np.linspace(0.0, 40.0, 60), np.full(30, 40.0)])
    rec = TactileFrames(arc_frames(turns), t_s=np.arange(turns.size) / 20.0, pitch_mm=PITCH)
    assert recognise(rec, cleaning=None).identified == "truncated-cone"  # 11 pitches: read
    cfg = TactemeConfig(pivot_min_line_taxels=13.0)
    short = recognise(rec, cleaning=None, config=cfg)
    assert not {"LCMT in an arc", "LCMT about one end"} & {n for n, _ in short.tactemes}
    assert short.identified is None
    sensor = SmartSensor((16, 16), pitch_mm=PITCH, cleaning=None, config=cfg)
    for f, t in zip(rec.frames, rec.t_s, strict=True):
        sensor.push(f, t)
    assert list(sensor.result().events) == list(short.events)
    with pytest.raises(InputError, match="pivot_min_line_taxels"):
        TactemeConfig(pivot_min_line_taxels=-1.0)


@pytest.mark.parametrize(
    ("frames_of", "verdict", "other", "name", "option"),
    [
        (end_frames, "LCMT about one end", "LCMT in an arc", "cone", "pivot_end_sigmas"),
        (arc_frames, "LCMT in an arc", "LCMT about one end", "truncated-cone", "pivot_arc_sigmas"),
    ],
)
def test_a_pivot_verdict_waits_until_the_pivot_is_certain_enough(
    frames_of: Any, verdict: str, other: str, name: str, option: str
) -> None:
    """A line turning about its end (a far pivot) reads its verdict unless its error weighs much."""
    turns = np.concatenate([np.zeros(10), np.linspace(0.0, 40.0, 60), np.full(30, 40.0)])
    rec = TactileFrames(frames_of(turns), t_s=np.arange(turns.size) / 20.0, pitch_mm=PITCH)
    for cfg, read in ((TactemeConfig(), True), (TactemeConfig(**{option: 50.0}), False)):
        res = recognise(rec, cleaning=None, config=cfg)
        assert (verdict in [n for n, _ in res.tactemes]) is read
        assert other not in [n for n, _ in res.tactemes]
        assert res.identified == (name if read else None)
        sensor = SmartSensor((16, 16), pitch_mm=PITCH, cleaning=None, config=cfg)
        for f, t in zip(rec.frames, rec.t_s, strict=True):
            sensor.push(f, t)
        assert list(sensor.result().events) == list(res.events)
    with pytest.raises(InputError, match=option):
        TactemeConfig(**{option: -0.5})


def test_the_gates_move_the_ratio_by_its_error() -> None:
    from taxelkit.smart.pivot_limits import pivot_lower, pivot_upper

    ratio, error = np.array([1.5, 2.0, np.nan]), np.array([0.2, 0.4, 0.1])
    np.testing.assert_allclose(pivot_upper(ratio, error, 0.5), [1.6, 2.2, np.nan])
    np.testing.assert_allclose(pivot_lower(ratio, error, 0.5), [1.4, 1.8, np.nan])
    assert pivot_lower(ratio, error, 0.0) is ratio and pivot_upper(ratio, error, 0.0) is ratio


def test_the_arc_limit_widens_as_the_turn_shrinks() -> None:
    from taxelkit.smart.pivot_limits import arc_ratio_limit

    turns = np.array([5.0, 10.0, 12.0, 20.0, 40.0])
    limit = arc_ratio_limit(turns, 1.32, 1.15, 20.0, 10.0)
    assert np.isinf(limit[:2]).all()  # at or below pivot_arc_turn_deg: no arc yet
    assert limit[2] == pytest.approx(1.32 * 1.15 ** (20.0 / 12.0))
    assert limit[3] == pytest.approx(1.32 * 1.15) and limit[4] == limit[3]
    # a 16 mm line on a 3.5 mm grid wobbles by up to 2 atan(3.5 / 16) = 24.7 deg: no early arc
    coarse = arc_ratio_limit(turns, 1.32, 1.15, 20.0, 10.0, np.full(5, 16.0), 3.5)
    assert np.isinf(coarse[:4]).all() and coarse[4] == limit[4]  # never stricter from 20 deg
    fine = arc_ratio_limit(turns, 1.32, 1.15, 20.0, 10.0, np.full(5, 16.0), 1.0)
    assert np.array_equal(fine, limit)  # 7.2 deg on a 1 mm grid: below the 10 deg anyway
    with pytest.raises(InputError, match="pivot_arc_turn_deg"):
        TactemeConfig(pivot_arc_turn_deg=25.0)


def test_an_edge_angle_is_read_only_where_the_grid_cannot_fake_it() -> None:
    from taxelkit.smart.track_geometry import grid_wobble_deg
    from taxelkit.smart.transitions import transition_tactemes

    line, area = int(ContactClass.LINE), int(ContactClass.AREA)
    history = [(line, 0.0), (area, 0.0), (line, 58.0)]  # a square's 90 deg read as 58
    cfg = TactemeConfig()
    names = {t.value for t in transition_tactemes(history, cfg)}
    assert "LC -> AC -> LC (60 or 120 deg)" in names  # without the grid's share: a triangle
    # a 10 mm edge on a 3.5 mm grid can tilt by atan(3.5 / 10) = 19 deg: no angle is read
    coarse = grid_wobble_deg(np.full(4, 10.0), 3.5)
    assert coarse == pytest.approx(np.rad2deg(np.arctan(0.35)))
    found = transition_tactemes(history, cfg, wobbles_deg=[coarse, 0.0, coarse])
    assert {t.value for t in found} == {"AC -> LC"}
    # the same edge on the Bonneville's 1.76 mm grid: 10 deg, the angle counts
    fine = grid_wobble_deg(np.full(4, 10.0), 1.7625)
    found = transition_tactemes(history, cfg, wobbles_deg=[fine, 0.0, fine])
    assert "LC -> AC -> LC (60 or 120 deg)" in {t.value for t in found}
    assert grid_wobble_deg(np.full(4, 10.0), 0.0) == 0.0  # pitch unknown: no share


@pytest.mark.parametrize(
    ("angle_deg", "doubt_deg", "expected"),
    [
        (72.0, 3.0, "LC -> AC -> LC (60 or 120 deg)"),
        (73.0, 3.0, None),  # within 3 deg of 75: neither a triangle nor a square
        (77.0, 3.0, None),
        (78.0, 3.0, "LC -> AC -> LC (parallel or 90 deg)"),
        (73.0, 0.0, "LC -> AC -> LC (60 or 120 deg)"),  # the paper's windows touch at 75
        (77.0, 0.0, "LC -> AC -> LC (parallel or 90 deg)"),
        (12.0, 3.0, "LC -> AC -> LC (parallel or 90 deg)"),
    ],
)
def test_an_edge_angle_midway_between_60_and_90_reads_as_neither(
    angle_deg: float, doubt_deg: float, expected: str | None
) -> None:
    angles = edge_angle_tactemes(angle_deg, TactemeConfig(edge_angle_doubt_deg=doubt_deg))
    assert angles == ({expected} if expected else set())
    assert PAPER_LEVEL3.edge_angle_doubt_deg == 0.0


def edge_angle_tactemes(
    angle_deg: float, config: TactemeConfig, wobbles_deg: list[float] | None = None
) -> set[str]:
    """The edge-angle tactemes of an edge, a face and an edge ``angle_deg`` from the first."""
    from taxelkit.smart.transitions import transition_tactemes

    line, area = int(ContactClass.LINE), int(ContactClass.AREA)
    history = [(line, 10.0), (area, 0.0), (line, 10.0 + angle_deg)]
    found = transition_tactemes(history, config, wobbles_deg=wobbles_deg)
    return {t.value for t in found} - {"AC -> LC"}


@pytest.mark.parametrize(
    ("angle_deg", "wobble_deg", "expected"),
    [
        (69.0, 6.0, "LC -> AC -> LC (60 or 120 deg)"),  # 90 - 12 = 78: a triangle
        (69.0, 13.5, None),  # 90 - 27 = 63: a square's 90 tilted twice by the grid
        (62.0, 13.5, "LC -> AC -> LC (60 or 120 deg)"),
        (80.0, 13.5, None),  # 60 + 27 = 87: a triangle's 60 tilted twice by the grid
        (88.0, 13.5, "LC -> AC -> LC (parallel or 90 deg)"),
        (80.0, 6.0, "LC -> AC -> LC (parallel or 90 deg)"),
    ],
)
def test_an_edge_angle_allows_for_the_grid_tilting_both_edges(
    angle_deg: float, wobble_deg: float, expected: str | None
) -> None:
    wobbles = [wobble_deg, 0.0, wobble_deg]
    found = edge_angle_tactemes(angle_deg, TactemeConfig(), wobbles)
    assert found == ({expected} if expected else set())
    # the paper's windows: no allowance, 69 deg is a triangle's whatever the wobbles
    paper = edge_angle_tactemes(angle_deg, PAPER_LEVEL3, wobbles)
    assert PAPER_LEVEL3.edge_angle_grid_sum is False
    assert ("LC -> AC -> LC (60 or 120 deg)" in paper) is (angle_deg < 75.0)


@pytest.mark.parametrize(
    ("across_mm", "square"),
    [(0.4, False), (3.0, False), (3.6, True), (12.0, True), (-12.0, True)],
)
def test_the_same_edge_rocked_back_onto_is_not_a_parallel_edge(
    across_mm: float, square: bool
) -> None:
    """Edge, face, edge again at 2 pitches (3.5 mm) or less across: the same edge."""
    from taxelkit.smart.transitions import transition_tactemes

    line, area = int(ContactClass.LINE), int(ContactClass.AREA)
    history = [(line, 30.0), (area, 0.0), (line, 31.0)]
    t = np.deg2rad(30.0)
    # 5 mm further along the edge and ``across_mm`` across it
    second = (
        2.0 - across_mm * np.sin(t) + 5.0 * np.cos(t),
        1.0 + across_mm * np.cos(t) + 5.0 * np.sin(t),
    )
    centres = [(2.0, 1.0), (6.0, -4.0), (float(second[0]), float(second[1]))]
    kw = {"centres": centres, "pitch_mm": 1.75}
    found = transition_tactemes(history, TactemeConfig(), **kw)
    assert ("LC -> AC -> LC (parallel or 90 deg)" in {t.value for t in found}) is square
    # pitch unknown, or the paper's rule: parallel edges are a square's wherever they lie
    for cfg, pitch in ((TactemeConfig(), 0.0), (PAPER_LEVEL3, 1.75)):
        found = transition_tactemes(history, cfg, centres=centres, pitch_mm=pitch)
        assert "LC -> AC -> LC (parallel or 90 deg)" in {t.value for t in found}
    with pytest.raises(InputError, match="edge_apart_pitches"):
        TactemeConfig(edge_apart_pitches=-1.0)


def test_a_polyhedron_rocked_back_onto_its_edge_is_not_named_a_cube() -> None:
    """Face, edge, the other face, the same edge again: no square's parallel edges."""
    left, right, bar = (np.zeros((16, 16), bool) for _ in range(3))
    left[5:12, 2:8] = right[5:12, 8:14] = bar[3:13, 7:9] = True
    empty = np.zeros((16, 16), bool)
    seq = [empty] * 4 + [left] * 6 + [bar] * 6 + [right] * 6 + [bar] * 6 + [right] * 6
    frames = np.array([*seq, *[empty] * 4])
    rec = TactileFrames(frames, t_s=np.arange(frames.shape[0]) / 10.0, pitch_mm=PITCH)
    res = recognise(rec, cleaning=None)
    names = [n for n, _ in res.tactemes]
    assert names.count("LC") == 2 and "LC -> AC -> LC (parallel or 90 deg)" not in names
    assert res.identified is None and res.candidates == ("cube", "tetrahedron")
    # without the rule the same edge read twice names a cube
    loose = recognise(rec, cleaning=None, config=TactemeConfig(edge_apart_pitches=0.0))
    assert loose.identified == "cube"
    # streamed frame by frame, the segment's pitch reaches the rule too
    sensor = SmartSensor((16, 16), pitch_mm=PITCH, cleaning=None)
    for f, t in zip(rec.frames, rec.t_s, strict=True):
        sensor.push(f, t)
    assert list(sensor.result().events) == list(res.events)


def flickering_arc_frames(turns_deg: np.ndarray) -> np.ndarray:
    """A line turning about a pivot 7.8 mm beyond its near end, its far end 8 mm short every
    other frame: its middle jumps by 4 mm, the current line's pivot ratio by about 0.5."""
    start = 7.8
    pivot = (-10.0 - start, -5.0)
    frames = turning_line_frames(turns_deg, pivot, start)
    ax = (np.arange(16) - 7.5) * PITCH
    x, y = np.meshgrid(ax, ax)
    for i in range(1, turns_deg.size, 2):
        t = np.deg2rad(turns_deg[i])
        along = (x - pivot[0]) * np.cos(t) + (y - pivot[1]) * np.sin(t)
        frames[i] &= along <= start + 12.0
    return frames


def test_the_arc_reads_the_mean_middle_of_the_recent_lines() -> None:
    """A truncated cone whose line end flickers: an arc from the lines' mean middle only."""
    turns = np.concatenate([np.zeros(20), np.linspace(0.0, 40.0, 120), np.full(60, 40.0)])
    rec = TactileFrames(
        flickering_arc_frames(turns), t_s=np.arange(turns.size) / 40.0, pitch_mm=PITCH
    )
    for cfg, arc in ((TactemeConfig(), True), (TactemeConfig(pivot_arc_smooth=False), False)):
        res = recognise(rec, cleaning=None, config=cfg)
        names = [n for n, _ in res.tactemes]
        assert ("LCMT in an arc" in names) is arc
        assert "LCMT about one end" not in names
        assert res.identified == ("truncated-cone" if arc else None)
        sensor = SmartSensor((16, 16), pitch_mm=PITCH, cleaning=None, config=cfg)
        for chunk in np.array_split(np.arange(turns.size), 7):
            sensor.push_many(rec.frames[chunk], rec.t_s[chunk])
        assert list(sensor.result().events) == list(res.events)
    assert not PAPER_LEVEL3.pivot_arc_smooth


def test_a_rare_reading_withdraws_a_name_alike_in_batch_and_streaming() -> None:
    """A learnt "pin" whose row is the cone's, with "about one end" rare: a line turning about
    its end leaves the pin alone, named at first, then doubted (not named), in every path."""
    from taxelkit.smart.object_table import PAPER_OBJECTS, ObjectRow, ObjectTable

    cone = PAPER_OBJECTS.row("cone").tactemes
    pin = ObjectRow("pin", cone, rare=frozenset({Tacteme.LCMT_ABOUT_END}))
    cfg = TactemeConfig(objects=ObjectTable((PAPER_OBJECTS.row("sphere"), pin)))
    turns = np.concatenate([np.zeros(10), np.linspace(0.0, 40.0, 60), np.full(30, 40.0)])
    rec = TactileFrames(end_frames(turns), t_s=np.arange(turns.size) / 20.0, pitch_mm=PITCH)
    res = recognise(rec, cleaning=None, config=cfg)
    kinds = [(e.kind, e.value) for e in res.events if e.kind in ("identified", "doubt")]
    assert kinds == [("identified", "pin"), ("doubt", "pin")]
    assert res.identified is None and res.candidates == ("pin",)
    assert res.verdict.rare == ("LCMT about one end",)
    for batch_frames in (1, 7):
        sensor = SmartSensor(
            (16, 16), pitch_mm=PITCH, cleaning=None, config=cfg, batch_frames=batch_frames
        )
        for f, t in zip(rec.frames, rec.t_s, strict=True):
            sensor.push(f, t)
        out = sensor.result()
        assert list(out.events) == list(res.events) and out.identified is None
    from taxelkit.smart.bank import SensorBank

    bank = SensorBank(2, (16, 16), pitch_mm=PITCH, cleaning=None, config=cfg, batch_frames=5)
    for f, t in zip(rec.frames, rec.t_s, strict=True):
        bank.push(np.stack([f, np.zeros_like(f)]), t)
    bank.flush()
    assert list(bank.result(0).events) == list(res.events) and bank.result(0).identified is None


@pytest.mark.parametrize("blip_frames", [4, 12])
def test_a_brief_contact_that_rules_out_nothing_is_passed_over(blip_frames: int) -> None:
    """A lone taxel lit after the object was lifted does not erase the verdict (``blip_s``)."""
    roll = line_frames([(5, 8)] * 6 + [(5 + k // 3, 8) for k in range(18)])
    after = np.zeros((20 + blip_frames + 10, 16, 16), bool)
    after[20 : 20 + blip_frames, 1, 0] = True  # 0.2 s (a blip) or 0.6 s (a contact) at 20 Hz
    frames = np.concatenate([roll, after])
    rec = TactileFrames(frames, t_s=np.arange(frames.shape[0]) / 20.0, pitch_mm=PITCH)
    r = recognise(rec, cleaning=None)
    assert [e.kind for e in r.events].count("lifted") == 2  # both contacts are in the events
    stream = SmartSensor((16, 16), pitch_mm=PITCH, cleaning=None)
    for f, t in zip(frames, rec.t_s, strict=True):
        stream.push(f, float(t))
    assert stream.result().identified == r.identified
    assert stream.result().verdict == r.verdict
    if blip_frames == 4:
        assert r.identified == "cylinder"
        ((first, lifted),) = r.verdict.passed_over
        assert first > roll.shape[0] and "ruled out nothing" in r.verdict.sentence()
        want = [{"first_frame": first, "lifted_frame": lifted, "last_frame": lifted}]
        assert r.verdict.to_json()["passed_over"] == want
        assert not r.verdict.still_on
    else:  # lasting 0.6 s, it is the verdict's contact, however little it shows
        assert r.identified is None and r.verdict.passed_over == ()
    cfg = TactemeConfig(blip_s=0.0)  # the last contact, however brief
    assert recognise(rec, cleaning=None, config=cfg).identified is None


@pytest.mark.parametrize("on_frames", [6, 16])
def test_a_brief_contact_still_on_at_the_end_is_passed_over(on_frames: int) -> None:
    """A lone taxel lit for the last 0.3 s of a recording, after the object was lifted, is
    cut off too brief to tell: the summary is the object's, saying so; lit for 0.8 s (0.65 s
    from its acceptance) it is the summary's contact. Batch, streaming and bank alike."""
    from taxelkit.smart.bank import SensorBank

    roll = line_frames([(5, 8)] * 6 + [(5 + k // 3, 8) for k in range(18)])
    after = np.zeros((20 + on_frames, 16, 16), bool)
    after[20:, 1, 0] = True  # lit until the recording ends
    frames = np.concatenate([roll, after])
    rec = TactileFrames(frames, t_s=np.arange(frames.shape[0]) / 20.0, pitch_mm=PITCH)
    r = recognise(rec, cleaning=None)
    kinds = [e.kind for e in r.events]
    assert kinds.count("lifted") == 1 and kinds.count("contact") == 2
    stream = SmartSensor((16, 16), pitch_mm=PITCH, cleaning=None, batch_frames=8)
    bank = SensorBank(2, (16, 16), pitch_mm=PITCH, cleaning=None, batch_frames=8)
    for f, t in zip(frames, rec.t_s, strict=True):
        stream.push(f, float(t))
        bank.push(np.stack([f, np.zeros_like(f)]), float(t))
    for other in (stream.result(), bank.result(0)):
        assert other.identified == r.identified and other.verdict == r.verdict
    if on_frames == 6:
        assert r.identified == "cylinder" and r.verdict.still_on
        ((first, last),) = r.verdict.passed_over
        assert last == frames.shape[0] - 1 and first > roll.shape[0]
        assert "still on when the recording ended" in r.verdict.sentence()
        want = [{"first_frame": first, "lifted_frame": None, "last_frame": last}]
        assert r.verdict.to_json()["passed_over"] == want and r.verdict.to_json()["still_on"]
    else:
        assert r.identified is None and r.verdict.passed_over == () and not r.verdict.still_on
