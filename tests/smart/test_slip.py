"""The slip detector: synthetic footprints, chunking, the verdict, batch = streaming."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from taxelkit.cli import run
from taxelkit.frames import TactileFrames
from taxelkit.io.recordings import write_recording
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.slip_scenarios import make_partial_slip_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart.bank import SensorBank
from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.recognise_chunks import ChunkRecogniser
from taxelkit.smart.recogniser import SmartSensor, recognise
from taxelkit.smart.slip import DEFAULT_SLIP, SLIP_KINDS, SlipConfig
from taxelkit.smart.slip_scan import SlipScanner
from taxelkit.smart.tacteme_table import OBJECTS
from taxelkit.smart.tactemes import PAPER_LEVEL3, TactemeConfig

PITCH = 1.7625
RATE_HZ = 20.0


def face_frames(cols_mm: list[float]) -> TactileFrames:
    """A 6 x 6-taxel face (about 10 mm square) whose left edge sits at ``cols_mm``, mm.

    Sub-taxel positions are drawn the way a skin sees them: a taxel is on when
    its centre lies under the face.
    """
    x = (np.arange(16) - 7.5) * PITCH
    frames = np.zeros((len(cols_mm) + 2, 16, 16), bool)
    for t, left in enumerate(cols_mm, start=2):
        on = (x >= left) & (x < left + 6 * PITCH)
        frames[t, 5:11, :] = on[None, :]
    return TactileFrames(frames, t_s=np.arange(frames.shape[0]) / RATE_HZ, pitch_mm=PITCH)


def test_a_face_held_still_does_not_slip() -> None:
    rec = recognise(face_frames([-5.0] * 40), cleaning=None)
    assert rec.slips == ()
    assert "slip" not in [e.kind for e in rec.events]


def test_a_face_dragged_is_slip_found_within_0_2_s() -> None:
    speed_mm_s = 4.0
    hold = [-8.0] * 16
    drag = [-8.0 + speed_mm_s * (k + 1) / RATE_HZ for k in range(30)]
    rec = recognise(face_frames(hold + drag + [drag[-1]] * 40), cleaning=None)
    assert len(rec.slips) == 1
    slip = rec.slips[0]
    assert slip.kind == "area slides"
    start = 2 + len(hold) - 1  # the last still frame: the drag leaves it
    assert (slip.detected_frame - start) / RATE_HZ <= 0.2 + 1e-9
    assert slip.last_frame is not None and abs(slip.last_frame - (start + 30)) <= 0.3 * RATE_HZ
    # the face only slid: nothing identified, and the reason is named
    assert rec.identified not in OBJECTS
    assert rec.verdict.reason == "slid"
    assert rec.verdict.sentence().startswith("not identified: slid")
    assert rec.to_json()["why"]["reason"] == "slid"
    assert rec.to_json()["slips"][0]["first_frame"] == slip.first_frame


def test_the_paper_pipeline_detects_no_slip() -> None:
    assert PAPER_LEVEL3.slip is None
    assert TactemeConfig().slip == DEFAULT_SLIP
    drag = [-8.0] * 16 + [-8.0 + 0.25 * k for k in range(30)]
    rec = recognise(face_frames(drag), cleaning=None, limits=None, config=PAPER_LEVEL3)
    assert rec.slips == () and rec.verdict.reason != "slid"


def test_a_point_never_slips_and_config_is_checked() -> None:
    scan = SlipScanner(int(ContactClass.POINT), SlipConfig(), k=2)
    rows = np.zeros((40, 9))
    rows[:, 0] = np.arange(40) * 0.5  # a point racing across: rolling or skidding, who knows
    rows[:, 3], rows[:, 4], rows[:, 8] = 3.0, 1.0, np.arange(40) / RATE_HZ
    assert scan.extend(np.arange(40), rows) == [] and scan.close() == []
    with pytest.raises(ValueError, match="slip_mm"):
        SlipConfig(slip_mm=0.0)


def _dragged_face_rows(n: int = 80) -> np.ndarray:
    gen = np.random.default_rng(5)
    rows = np.zeros((n, 9))
    rows[:, 0] = np.where(np.arange(n) < 30, 0.0, (np.arange(n) - 30) * 0.2)
    rows[:, :2] += gen.normal(0.0, 0.08, (n, 2))  # sub-taxel jitter of the mean centre
    rows[:, 2] = 10.0
    rows[:, 3] = 100.0 + gen.normal(0.0, 3.0, n)
    rows[:, 4], rows[:, 5] = 1.2, 6.0
    rows[:, 6:8] = np.nan
    rows[:, 8] = np.arange(n) / RATE_HZ
    return rows


@pytest.mark.parametrize("chunk", [1, 3, 7, 80])
def test_slips_do_not_depend_on_the_chunking(chunk: int) -> None:
    rows = _dragged_face_rows()
    whole = SlipScanner(int(ContactClass.AREA), SlipConfig(), k=2)
    whole.extend(np.arange(80), rows)
    parts = SlipScanner(int(ContactClass.AREA), SlipConfig(), k=2)
    for a in range(0, 80, chunk):
        parts.extend(np.arange(a, min(a + chunk, 80)), rows[a : a + chunk])
    assert whole.all_slips() and parts.all_slips() == whole.all_slips()


@pytest.fixture(scope="module")
def cube_with_slip() -> TactileFrames:
    sc = make_partial_slip_scenario("cube", rng=0)
    return frames_from_scenario(BONNEVILLE_16X16, sc, rng=0)


def test_a_line_slipping_after_its_roll_does_not_name_the_pivot(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A truncated cone rolled, then slid along its line towards its apex (20 frames/s).

    The slide draws the line's middle to the pivot: "about one end" would
    name a cone, or, here, withdraw the truncated cone that the roll's arc
    named. Decided while the slip is open, the pivot tactemes are held back.
    """
    import taxelkit.smart.levels34 as levels34

    sc = make_partial_slip_scenario("truncated-cone", rng=72, rate_hz=20.0)
    rec = frames_from_scenario(BONNEVILLE_16X16, sc, rng=72)
    held = recognise(rec)
    assert held.identified == "truncated-cone"
    events = [(e.kind, e.value) for e in held.events]
    assert ("withheld", "LCMT about one end") in events
    assert events.index(("slip", "line slides along itself")) < events.index(
        ("withheld", "LCMT about one end")
    )
    line = SLIP_KINDS[int(ContactClass.LINE)]
    monkeypatch.setitem(levels34.FAKED_BY_SLIP, line, frozenset())
    # without the rule the slide's pivot reaches elimination: no object is left
    assert recognise(rec).identified == "unknown"


def test_a_roll_with_a_slipping_phase_is_still_identified(cube_with_slip: TactileFrames) -> None:
    rec = recognise(cube_with_slip)
    assert rec.identified == "cube"
    assert [s.kind for s in rec.slips][:1] == ["area slides"]
    kinds = [e.kind for e in rec.events]
    assert "withheld" in kinds and kinds.index("slip") < kinds.index("withheld")
    # without slip detection the drag's "AC moves" rules out every object
    assert recognise(cube_with_slip, config=TactemeConfig(slip=None)).identified == "unknown"


def test_streaming_and_chunks_give_the_batch_events(cube_with_slip: TactileFrames) -> None:
    rec = cube_with_slip
    batch = recognise(rec)
    events = [(e.kind, e.frame, e.value) for e in batch.events]
    sensor = SmartSensor(rec.shape[1:], pitch_mm=rec.pitch_mm)
    for f, t in zip(rec.frames, rec.t_s, strict=True):
        sensor.push(f, t)
    assert [(e.kind, e.frame, e.value) for e in sensor.result().events] == events
    chunks = ChunkRecogniser(rec.shape[1:], pitch_mm=rec.pitch_mm)
    for a in range(0, rec.n_frames, 13):
        chunks.push(rec.frames[a : a + 13], rec.t_s[a : a + 13])
    done = chunks.result()
    assert [(e.kind, e.frame, e.value) for e in done.events] == events
    assert done.slips == batch.slips


def test_recognize_json_lists_each_tracks_slips(
    cube_with_slip: TactileFrames, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "cube.npz"
    write_recording(cube_with_slip, path)
    assert run(["recognize", str(path), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    (obj,) = doc["objects"]
    assert obj["identified"] == "cube" and obj["slips"]
    slip = obj["slips"][0]
    assert slip["kind"] == "area slides"
    assert slip["t_start_s"] == pytest.approx(slip["first_frame"] / RATE_HZ)
    assert slip["t_end_s"] >= slip["t_start_s"]
    assert doc["slips"][0]["first_frame"] == slip["first_frame"]
    assert run(["recognize", str(path)]) == 0
    text = capsys.readouterr().out
    assert "slip-end" in text and "withheld" in text and "slip phase(s)" in text


def _dragged_rows(rate_hz: float, speed_mm_s: float) -> np.ndarray:
    """Rows of a face held 1 s, then dragged at ``speed_mm_s``, for 2 s."""
    n = round(2.0 * rate_hz)
    t = np.arange(n) / rate_hz
    rows = np.zeros((n, 9))
    rows[:, 0] = speed_mm_s * np.clip(t - 1.0, 0.0, None)
    rows[:, 3], rows[:, 4], rows[:, 8] = 50.0, 1.0, t
    return rows


@pytest.mark.parametrize("rate_hz", [20.0, 100.0])
def test_the_hold_spans_the_same_time_at_any_rate(rate_hz: float) -> None:
    # a smooth drag at 5 mm/s: decided at the same time (within a frame at 20 frames/s)
    rows = _dragged_rows(rate_hz, 5.0)
    scan = SlipScanner(int(ContactClass.AREA), SlipConfig(), k=2)
    (slip,) = scan.extend(np.arange(rows.shape[0]), rows)
    latency_s = slip.detected_frame / rate_hz - 1.0
    assert 0.1 <= latency_s <= 0.2 + 1.0 / 20.0
    assert (scan.cur, scan.hold) == ((2, 2) if rate_hz == 20.0 else (5, 8))


class _ScriptedMotion(SlipScanner):
    """A scanner whose motion measure reads a scripted series (one value per decided frame)."""

    def __init__(self, series: list[float], config: SlipConfig) -> None:
        # the per-frame rule calls motion_mm frame by frame (the vectorised scan
        # decides as it does: tests/smart/test_slip_vectorised.py)
        super().__init__(int(ContactClass.AREA), config, k=2, reference=True)
        self.series = iter(series)

    def motion_mm(self, ref: np.ndarray, cur: np.ndarray) -> float:
        return next(self.series)


def test_one_noisy_dip_does_not_restart_the_hold() -> None:
    rows = _dragged_rows(100.0, 0.0)
    series = [0.0] * 50 + [1.0] * 3 + [0.2] + [1.0] * 200  # one dip below 0.35 mm
    tolerant = _ScriptedMotion(series, SlipConfig())
    strict = _ScriptedMotion(series, SlipConfig(hold_fraction=1.0))
    (a,) = tolerant.extend(np.arange(200), rows)
    (b,) = strict.extend(np.arange(200), rows)
    assert b.detected_frame - a.detected_frame == 4  # the strict hold restarts after the dip
    with pytest.raises(ValueError, match="hold_fraction"):
        SlipConfig(hold_fraction=0.0)


def _line_rows(rate_hz: float, *, slide_mm_s: float, turn_deg_s: float) -> np.ndarray:
    """Rows of a line (half-length 8 mm) still for 1 s, then moving for 1 s.

    Sliding: its centre moves along its axis at ``slide_mm_s``. Turning: it
    turns about its end at ``(-8, 0)`` (a cone's apex) at ``turn_deg_s`` while
    its drawn ends shift along it at ``slide_mm_s`` (the footprint of a cone
    whose apex end fades in and out).
    """
    n = int(2 * rate_hz)
    t = np.arange(n) / rate_hz
    moving = np.clip(t - 1.0, 0.0, None)
    angle = np.deg2rad(turn_deg_s * moving)
    u = np.stack([np.cos(angle), np.sin(angle)], axis=-1)
    apex = np.array([-8.0, 0.0])
    centre = apex + (8.0 + slide_mm_s * moving)[:, None] * u
    rows = np.zeros((n, 9))
    rows[:, :2] = centre
    rows[:, 2] = np.rad2deg(angle)
    rows[:, 3], rows[:, 4], rows[:, 5] = 28.0, 5.0, 8.0
    rows[:, 6], rows[:, 7], rows[:, 8] = -8.0, 8.0, t
    return rows


@pytest.mark.parametrize("rate_hz", [20.0, 100.0])
def test_a_line_sliding_along_itself_slips_and_one_turning_about_its_end_does_not(
    rate_hz: float,
) -> None:
    """The turn about an end (rolling of a cone) hides a shift along the line; a slide slips."""
    line = int(ContactClass.LINE)
    slide = _line_rows(rate_hz, slide_mm_s=5.0, turn_deg_s=0.0)
    (slip,) = SlipScanner(line, SlipConfig(), k=2).extend(np.arange(slide.shape[0]), slide)
    assert slip.kind == "line slides along itself"
    assert 1.0 <= slip.detected_frame / rate_hz <= 1.4
    cone = _line_rows(rate_hz, slide_mm_s=5.0, turn_deg_s=20.0)  # ends 0.7 mm across in 0.25 s
    frames = np.arange(cone.shape[0])
    assert SlipScanner(line, SlipConfig(), k=2).extend(frames, cone) == []
    off = SlipConfig(line_across_mm=float("inf"))  # without the test it reads as sliding
    assert SlipScanner(line, off, k=2).extend(frames, cone)
    with pytest.raises(ValueError, match="line_across_mm"):
        SlipConfig(line_across_mm=0.0)


def _rattling_line(rate_hz: float, *, slide_from_s: float | None = None) -> np.ndarray:
    """Rows of a line (half-length 8 mm) rattling between two seats a pitch apart along it.

    It changes seat after dwelling 0.05-0.4 s (seeded, the same times at
    every rate), as a body tipping between the facets of its mesh draws it;
    from ``slide_from_s`` the line also slides along itself at 5 mm/s.
    """
    n = int(4 * rate_hz)
    t = np.arange(n) / rate_hz
    switches = np.cumsum(np.random.default_rng(3).uniform(0.05, 0.4, 40))
    seat = np.searchsorted(switches, t, side="right") % 2 == 1
    along = PITCH * seat
    if slide_from_s is not None:
        along = along + 5.0 * np.clip(t - slide_from_s, 0.0, None)
    rows = np.zeros((n, 9))
    rows[:, 0] = along
    rows[:, 3], rows[:, 4], rows[:, 5] = 28.0, 5.0, 8.0
    rows[:, 6], rows[:, 7], rows[:, 8] = -8.0, 8.0, t
    return rows


@pytest.mark.parametrize("rate_hz", [20.0, 100.0])
def test_a_line_rattling_between_two_seats_does_not_slip_and_one_sliding_on_does(
    rate_hz: float,
) -> None:
    line = int(ContactClass.LINE)
    rattle = _rattling_line(rate_hz)
    frames = np.arange(rattle.shape[0])
    assert SlipScanner(line, SlipConfig(), k=2).extend(frames, rattle) == []
    # without the test the seats read as sliding (at 20 frames/s a reference of
    # 0.4 s happens to average this rattle's two seats: 0.3 s, a face's, does not)
    off = SlipConfig(line_return_s=0.0, line_reference_s=0.3)
    assert SlipScanner(line, off, k=2).extend(frames, rattle)
    slide = _rattling_line(rate_hz, slide_from_s=2.0)
    slips = SlipScanner(line, SlipConfig(), k=2).extend(frames, slide)
    assert slips and slips[0].kind == "line slides along itself"
    assert 2.0 <= slips[0].detected_frame / rate_hz <= 2.5
    with pytest.raises(ValueError, match="line_return_s"):
        SlipConfig(line_return_s=-1.0)
    with pytest.raises(ValueError, match="line_return_mm"):
        SlipConfig(line_return_mm=0.0)


def _stepping_line(rate_hz: float, speed_mm_s: float = 4.0) -> np.ndarray:
    """Rows of a line sliding along itself from 1 s, its drawn ends stepping a pitch at a time.

    A line oblique to the grid: each end moves a whole pitch when the slide
    has carried it across a taxel, the two at phases half a step apart, as
    the binary footprint of a sliding cylinder draws them.
    """
    n = int(3 * rate_hz)
    t = np.arange(n) / rate_hz
    slid = speed_mm_s * np.clip(t - 1.0, 0.0, None)
    lo = -8.0 + PITCH * np.floor(slid / PITCH + 0.5)  # steps at 0.22 s, 0.66 s, ...
    hi = 8.0 + PITCH * np.floor(slid / PITCH)  # steps at 0.44 s, 0.88 s, ...
    return line_rows_between(lo, hi, t)


def line_rows_between(lo: np.ndarray, hi: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Rows ``(n, 9)`` of a line along x drawn from ``lo`` to ``hi`` (mm) at times ``t``."""
    rows = np.zeros((t.size, 9))
    rows[:, 0] = 0.5 * (lo + hi)
    rows[:, 3], rows[:, 4], rows[:, 5] = 28.0, 5.0, 0.5 * (hi - lo)
    rows[:, 6], rows[:, 7], rows[:, 8] = 0.5 * (lo - hi), 0.5 * (hi - lo), t
    return rows


@pytest.mark.parametrize("rate_hz", [20.0, 100.0, 240.0])
def test_a_line_whose_ends_step_at_their_own_phases_slips(rate_hz: float) -> None:
    """A line's reference must hold the steps of both ends (``line_reference_s``)."""
    line = int(ContactClass.LINE)
    rows = _stepping_line(rate_hz)
    frames = np.arange(rows.shape[0])
    slips = SlipScanner(line, SlipConfig(), k=2).extend(frames, rows)
    assert slips and slips[0].kind == "line slides along itself"
    assert 1.4 <= slips[0].detected_frame / rate_hz <= 1.6  # once the second end stepped
    short = SlipConfig(line_reference_s=0.3)  # a face's: one end's step at a time
    assert SlipScanner(line, short, k=2).extend(frames, rows) == []
    with pytest.raises(ValueError, match="line_reference_s"):
        SlipConfig(line_reference_s=0.0)


def test_one_frame_jumping_along_a_line_and_back_does_not_decide_a_slip_at_20_hz() -> None:
    """Where one frame lies in every current window of the hold, it must not decide alone."""
    line = int(ContactClass.LINE)
    rows = _rattling_line(RATE_HZ)[:40]
    rows[:, 0] = 0.0
    rows[25, 0] = 2 * PITCH  # the ends jump two pitches along the line for one frame
    frames = np.arange(rows.shape[0])
    assert SlipScanner(line, SlipConfig(), k=2).extend(frames, rows) == []
    assert SlipScanner(line, SlipConfig(line_jump_back=False), k=2).extend(frames, rows) == []
    alone = SlipConfig(line_jump_back=False, line_reseat_s=0.0)  # the jump from rest reseats
    (slip,) = SlipScanner(line, alone, k=2).extend(frames, rows)
    assert slip.detected_frame == 26
    scan = SlipScanner(line, SlipConfig(), k=2)
    scan.extend(frames[:2], rows[:2])
    assert scan.hold <= scan.cur  # 20 frames/s: the hold's windows share a frame


def _rattling_bar(slip: SlipConfig) -> tuple[TactileFrames, TactemeConfig]:
    """Frames of a 9-taxel bar rattling one pitch along itself, 4 s at 20 frames/s."""
    rows = _rattling_line(RATE_HZ)
    frames = np.zeros((rows.shape[0], 16, 16), bool)
    for t, shift in enumerate(np.round(rows[:, 0] / PITCH).astype(int)):
        frames[t, 8, 3 + shift : 12 + shift] = True
    rec = TactileFrames(frames, t_s=rows[:, 8], pitch_mm=PITCH)
    return rec, TactemeConfig(slip=slip)


def test_every_path_drops_a_rattling_bars_slips_alike() -> None:
    """Batch, one frame at a time, chunks and the bank: the same slips with and without the test."""
    off = SlipConfig(line_return_s=0.0, line_reference_s=0.3)  # reads as sliding
    for slip, want_slips in ((SlipConfig(), False), (off, True)):
        rec, cfg = _rattling_bar(slip)
        batch = recognise(rec, config=cfg, cleaning=None)
        assert bool(batch.slips) == want_slips
        sensor = SmartSensor(rec.shape[1:], pitch_mm=PITCH, config=cfg, cleaning=None)
        for f, t in zip(rec.frames, rec.t_s, strict=True):
            sensor.push(f, t)
        assert sensor.result().slips == batch.slips
        chunks = ChunkRecogniser(rec.shape[1:], pitch_mm=PITCH, config=cfg, cleaning=None)
        for a in range(0, rec.n_frames, 7):
            chunks.push(rec.frames[a : a + 7], rec.t_s[a : a + 7])
        assert chunks.result().slips == batch.slips
        bank = SensorBank(2, rec.shape[1:], pitch_mm=PITCH, config=cfg, cleaning=None)
        for f, t in zip(rec.frames, rec.t_s, strict=True):
            bank.push(np.stack([f, np.zeros_like(f)]), t)
        bank.flush()
        assert bank.result(0).slips == batch.slips
