"""A turning line whose pivot reads in two places gets both verdicts (batch and streamed)."""

from __future__ import annotations

import numpy as np

from taxelkit.frames import TactileFrames
from taxelkit.smart.pivot_limits import arc_limit_turn_deg
from taxelkit.smart.pivots import MIN_PRESSED_SHARE, pressed_half_mm
from taxelkit.smart.recognise_chunks import ChunkRecogniser
from taxelkit.smart.recogniser import SmartSensor, recognise
from taxelkit.smart.segment_runs import Runs
from taxelkit.smart.tactemes import PAPER_LEVEL3, TactemeConfig

PITCH = 1.7625


def end_then_arc_frames(far_mm: float) -> np.ndarray:
    """A 20 mm line turning 30 deg about its own end, then 30 deg about a point behind it.

    The second pivot lies ``far_mm`` behind the line's end (a truncated cone's
    virtual apex at ``far_mm`` = 24: pivot ratio 3.4); ``far_mm`` = 0 keeps the
    first pivot (a cone about its apex) throughout.
    """
    end = np.array([-9.0, -7.0])
    poses = [(end, 0.0, 0.0)] * 10
    poses += [(end, a, 0.0) for a in np.linspace(0.0, 30.0, 40)]
    u = np.array([np.cos(np.deg2rad(30.0)), np.sin(np.deg2rad(30.0))])
    pivot = end - far_mm * u
    poses += [(pivot, a, far_mm) for a in np.linspace(30.0, 60.0, 60)[1:]]
    poses += [poses[-1]] * 20
    return np.stack([bar(p, deg, start, 20.0) for p, deg, start in poses])


def bar(pivot: np.ndarray, deg: float, start: float, length_mm: float) -> np.ndarray:
    """The 16 x 16 taxels of a bar 1.8 mm wide at ``deg``, from ``start`` to ``start + length``.

    Distances along the bar are from ``pivot`` (mm), which the bar's axis passes through.
    """
    ax = (np.arange(16) - 7.5) * PITCH
    x, y = np.meshgrid(ax, ax)
    t = np.deg2rad(deg)
    along = (x - pivot[0]) * np.cos(t) + (y - pivot[1]) * np.sin(t)
    across = -(x - pivot[0]) * np.sin(t) + (y - pivot[1]) * np.cos(t)
    out: np.ndarray = (np.abs(across) <= 0.9) & (along >= start) & (along <= start + length_mm)
    return out


def test_a_pivot_read_at_the_end_then_far_beyond_gives_both_verdicts() -> None:
    """Both verdicts are sustained: cone and truncated cone are both ruled out, never named."""
    frames = end_then_arc_frames(24.0)
    rec = TactileFrames(frames, t_s=np.arange(frames.shape[0]) / 20.0, pitch_mm=PITCH)
    res = recognise(rec, cleaning=None)
    names = [n for n, _ in res.tactemes]
    assert "LCMT about one end" in names and "LCMT in an arc" in names
    assert names.index("LCMT about one end") < names.index("LCMT in an arc")
    assert res.identified == "unknown" and res.candidates == ()
    # the cone was named from "about one end" until "in an arc" ruled it out
    named = [e.value for e in res.events if e.kind == "identified"]
    assert named[:1] == ["cone"]
    # streamed one frame at a time, in uneven chunks and out of core: the same events
    sensor = SmartSensor((16, 16), pitch_mm=PITCH, cleaning=None)
    for f, t in zip(rec.frames, rec.t_s, strict=True):
        sensor.push(f, t)
    assert list(sensor.result().events) == list(res.events)
    chunked = SmartSensor((16, 16), pitch_mm=PITCH, cleaning=None)
    for part in np.array_split(np.arange(frames.shape[0]), 9):
        chunked.push_many(rec.frames[part], rec.t_s[part])
    assert list(chunked.result().events) == list(res.events)
    chunks = ChunkRecogniser((16, 16), pitch_mm=PITCH, cleaning=None)
    for part in np.array_split(np.arange(frames.shape[0]), 5):
        chunks.push(rec.frames[part], rec.t_s[part])
    assert list(chunks.result().events) == list(res.events)


def test_a_pivot_that_stays_at_the_end_gives_one_verdict() -> None:
    """The same turn about the end throughout: "about one end" alone, the cone named."""
    frames = end_then_arc_frames(0.0)
    rec = TactileFrames(frames, t_s=np.arange(frames.shape[0]) / 20.0, pitch_mm=PITCH)
    res = recognise(rec, cleaning=None)
    names = [n for n, _ in res.tactemes]
    assert "LCMT about one end" in names and "LCMT in an arc" not in names
    assert res.identified == "cone"


def test_the_paper_pipeline_keeps_only_the_first_verdict() -> None:
    """``pivot_every_verdict=False`` (as in PAPER_LEVEL3): the first reading names the cone."""
    frames = end_then_arc_frames(24.0)
    rec = TactileFrames(frames, t_s=np.arange(frames.shape[0]) / 20.0, pitch_mm=PITCH)
    cfg = TactemeConfig(pivot_every_verdict=False)
    res = recognise(rec, cleaning=None, config=cfg)
    names = [n for n, _ in res.tactemes]
    assert "LCMT about one end" in names and "LCMT in an arc" not in names
    assert res.identified == "cone"
    assert not PAPER_LEVEL3.pivot_every_verdict and TactemeConfig().pivot_every_verdict
    for batch_frames in (1, 16):
        sensor = SmartSensor(
            (16, 16), pitch_mm=PITCH, cleaning=None, config=cfg, batch_frames=batch_frames
        )
        for f, t in zip(rec.frames, rec.t_s, strict=True):
            sensor.push(f, t)
        assert list(sensor.result().events) == list(res.events), batch_frames


def arc_and_back_frames(rate_hz: float) -> np.ndarray:
    """An 11 mm line turning 22 deg about a point 12 mm behind its end, then 14 deg back.

    A truncated cone rolled a little and back: pivot ratio about 3.2, far
    outside the band; its turn exceeds what the grid gives an 11 mm line (18
    deg) for about a quarter of a second only.
    """
    pivot, start = np.array([-16.0, -4.0]), 12.0
    n = round(0.6 * rate_hz)
    angles = [0.0] * round(0.1 * rate_hz)
    angles += np.linspace(0.0, 22.0, n).tolist() + np.linspace(22.0, 8.0, n)[1:].tolist()
    angles += [8.0] * round(0.8 * rate_hz)
    return np.stack([bar(pivot, deg, start, 11.0) for deg in angles])


def test_an_arc_read_at_the_largest_turn_survives_the_line_turning_back() -> None:
    """The arc's limit reads the turn the lines spread over (pivot_arc_max_turn)."""
    for rate in (100.0, 240.0):
        frames = arc_and_back_frames(rate)
        rec = TactileFrames(frames, t_s=np.arange(frames.shape[0]) / rate, pitch_mm=PITCH)
        res = recognise(rec, cleaning=None)
        names = [n for n, _ in res.tactemes]
        assert "LCMT in an arc" in names and "LCMT about one end" not in names, rate
        assert res.identified == "truncated-cone", rate
        # read at the turn now, the arc holds too briefly: undecided
        now = TactemeConfig(pivot_arc_max_turn=False)
        old = recognise(rec, cleaning=None, config=now)
        assert "LCMT in an arc" not in [n for n, _ in old.tactemes], rate
        assert old.identified is None and set(old.candidates) == {"cone", "truncated-cone"}
        assert TactemeConfig().pivot_arc_max_turn and not PAPER_LEVEL3.pivot_arc_max_turn
        # streamed one frame at a time and in uneven chunks, and out of core: the same events
        for cfg, want in ((None, res), (now, old)):
            sensor = SmartSensor((16, 16), pitch_mm=PITCH, cleaning=None, config=cfg)
            for f, t in zip(rec.frames, rec.t_s, strict=True):
                sensor.push(f, t)
            assert list(sensor.result().events) == list(want.events), rate
            chunks = ChunkRecogniser((16, 16), pitch_mm=PITCH, cleaning=None, config=cfg)
            for part in np.array_split(np.arange(frames.shape[0]), 7):
                chunks.push(rec.frames[part], rec.t_s[part])
            assert list(chunks.result().events) == list(want.events), rate


def test_the_largest_turn_stands_only_where_the_grid_cannot_tilt_the_line_as_far() -> None:
    """A line of six 1.76 mm taxels keeps its largest turn; one of three 3.5 mm taxels does not."""
    turn_now, largest = np.array([8.0, 8.0, 8.0]), np.array([22.0, 22.0, 22.0])
    lines = np.array([11.0, 10.5, 25.0])
    # 2 atan(pitch / length) against the 20 deg full turn: 18.2, 19.0, 8.1 deg at 1.76 mm
    got = arc_limit_turn_deg(turn_now, largest, lines, PITCH, 20.0)
    assert got.tolist() == [22.0, 22.0, 22.0]
    # and 35.3, 36.9, 15.9 deg at 3.5 mm
    got = arc_limit_turn_deg(turn_now, largest, lines, 3.5, 20.0)
    assert got.tolist() == [8.0, 8.0, 22.0]
    assert arc_limit_turn_deg(turn_now, largest, lines, 0.0, 20.0).tolist() == [22.0] * 3


def test_runs_cummax_is_each_segments_own_running_maximum() -> None:
    """Segments laid end to end never carry a maximum into the next one."""
    x = np.array([3.0, 1.0, 4.0, 0.5, 2.0, 1.0, 7.0])
    got = Runs(np.array([3, 0, 2, 2])).cummax(x)
    assert got.tolist() == [3.0, 3.0, 4.0, 0.5, 2.0, 1.0, 7.0]


def blurred_line(pivot: np.ndarray, deg: float, start: float, length: float) -> np.ndarray:
    """A pressed line ``start..start + length`` mm from ``pivot``, its footprint 1.75 mm wider.

    The skin spreads the footprint by about as much beyond each end as across
    the line: 1.75 mm each way, about a Bonneville pitch.
    """
    spread = 1.75
    ax = (np.arange(16) - 7.5) * PITCH
    x, y = np.meshgrid(ax, ax)
    t = np.deg2rad(deg)
    along = (x - pivot[0]) * np.cos(t) + (y - pivot[1]) * np.sin(t)
    across = -(x - pivot[0]) * np.sin(t) + (y - pivot[1]) * np.cos(t)
    lo, hi = start - spread, start + length + spread
    out: np.ndarray = (np.abs(across) <= spread) & (along >= lo) & (along <= hi)
    return out


def short_roll(q: float, length_mm: float = 12.0, rate_hz: float = 20.0) -> TactileFrames:
    """A cone (``q`` 0) or truncated cone (top / bottom radius ``q``) rolling 50 deg.

    Its pressed line is ``length_mm`` long and its (virtual) apex lies
    ``length q / (1 - q)`` beyond the line's near end: ``1 + 2q / (1 - q)``
    pressed half-lengths from its middle (2.08 for ``q`` 0.35).
    """
    beyond = length_mm * q / (1.0 - q)
    pivot = np.array([-4.0 - beyond - length_mm / 2.0, -6.0])
    angles = [0.0] * round(0.2 * rate_hz) + np.linspace(0.0, 50.0, round(2.5 * rate_hz)).tolist()
    angles += [50.0] * round(0.5 * rate_hz)
    frames = np.stack([blurred_line(pivot, a, beyond, length_mm) for a in angles])
    return TactileFrames(frames, t_s=np.arange(len(angles)) / rate_hz, pitch_mm=PITCH)


def test_pressed_half_takes_the_half_width_off_the_drawn_half() -> None:
    """A line k taxels long, one wide: its drawn half less half a pitch; a short fat one floors."""
    k = np.array([4.0, 8.0, 12.0])
    drawn = 0.5 * k * PITCH
    area = k * PITCH * PITCH
    np.testing.assert_allclose(pressed_half_mm(drawn, area), drawn - 0.5 * PITCH)
    # a footprint three taxels wide: three times the half-width
    np.testing.assert_allclose(pressed_half_mm(drawn, 3.0 * area), drawn - 1.5 * PITCH)
    fat = pressed_half_mm(np.array([2.0]), np.array([16.0]))  # 4 mm x 4 mm
    np.testing.assert_allclose(fat, MIN_PRESSED_SHARE * 2.0)


def test_a_short_truncated_cone_reads_in_an_arc_from_its_pressed_line() -> None:
    """The narrowest frustum the scenarios draw, a 12 mm line: an arc from the pressed line.

    Measured in drawn half-lengths (the skin's spread lengthens the line by
    3.5 mm) its pivot ratio of 2.08 reads about 1.45, inside the old band;
    the cone of the same line still turns about one end. Batch and streamed
    give the same events.
    """
    drawn = TactemeConfig(pivot_pressed_half=False, pivot_end_ratio=1.40, pivot_band=1.10)
    frustum, cone = short_roll(0.35), short_roll(0.0)
    res = recognise(frustum, cleaning=None)
    assert "LCMT in an arc" in [n for n, _ in res.tactemes]
    assert res.identified == "truncated-cone"
    old = recognise(frustum, cleaning=None, config=drawn)
    assert old.identified is None and set(old.candidates) == {"cone", "truncated-cone"}
    assert recognise(cone, cleaning=None).identified == "cone"
    assert recognise(cone, cleaning=None, config=drawn).identified == "cone"
    assert TactemeConfig().pivot_pressed_half and not PAPER_LEVEL3.pivot_pressed_half
    for rec in (frustum, cone):
        want = recognise(rec, cleaning=None)
        sensor = SmartSensor((16, 16), pitch_mm=PITCH, cleaning=None)
        for f, t in zip(rec.frames, rec.t_s, strict=True):
            sensor.push(f, t)
        assert list(sensor.result().events) == list(want.events)
        chunks = ChunkRecogniser((16, 16), pitch_mm=PITCH, cleaning=None)
        for part in np.array_split(np.arange(rec.frames.shape[0]), 4):
            chunks.push(rec.frames[part], rec.t_s[part])
        assert list(chunks.result().events) == list(want.events)
