"""Levels 3-4 of the smart sensor on hand-made contact images."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.frames import TactileFrames
from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.elimination import Eliminator
from taxelkit.smart.recogniser import SmartSensor, recognise
from taxelkit.smart.tacteme_table import ALL_ROWS, OBJECTS, Tacteme
from taxelkit.smart.tactemes import PAPER_LEVEL3, TactemeConfig, accepted_runs

N = 16
PITCH = 28.2 / 16


def blank() -> np.ndarray:
    return np.zeros((N, N), bool)


def point(r: int, c: int) -> np.ndarray:
    f = blank()
    f[r : r + 2, c : c + 2] = True
    return f


def line_v(c: int, r0: int = 3, r1: int = 13) -> np.ndarray:
    f = blank()
    f[r0:r1, c] = True
    return f


def area(r0: int = 4, r1: int = 12, c0: int = 4, c1: int = 12) -> np.ndarray:
    f = blank()
    f[r0:r1, c0:c1] = True
    return f


def fig3_sequence() -> np.ndarray:
    """The paper's Fig. 3 story: nothing, area, a spurious line, point, line moving parallel."""
    frames = [blank()] * 3 + [area()] * 4 + [line_v(7)] + [point(7, 7)] * 6
    frames += [line_v(c) for c in (3, 3, 3, 4, 4, 5, 6, 7, 8, 9, 10)]
    return np.stack(frames)


def test_fig3_story_identifies_the_cylinder_and_ignores_the_spurious_line() -> None:
    rec = recognise(
        TactileFrames(fig3_sequence(), pitch_mm=PITCH), cleaning=None, config=PAPER_LEVEL3
    )
    names = [n for n, _ in rec.tactemes]
    assert names[:3] == ["AC", "PC", "LC"]
    assert "LCMP" in names
    assert rec.identified == "cylinder"
    assert rec.classes[7] == ContactClass.LINE  # the spurious image was classified ...
    frames_of_lc = [f for n, f in rec.tactemes if n == "LC"]
    assert frames_of_lc == [16]  # ... but LC starts only after 3 line images (frames 14-16)


def test_debounce_skips_indeterminate_and_short_runs() -> None:
    n, i, p, ln = (
        ContactClass.NONE,
        ContactClass.INDETERMINATE,
        ContactClass.POINT,
        ContactClass.LINE,
    )
    seq = np.array([n, p, p, i, p, ln, p, p, ln, ln, i, ln, n, n, n], dtype=np.int8)
    runs = accepted_runs(seq, 3)
    assert [(c, a) for c, a, _ in runs] == [(p, 4), (ln, 11), (n, 14)]
    # the point segment holds all point frames, the spurious line at 5 excluded
    assert runs[0][2].tolist() == [1, 2, 4, 6, 7]
    assert next((c, a) for c, a, _ in accepted_runs(seq, 2)) == (p, 2)


def test_batch_and_streaming_give_the_same_events() -> None:
    frames = fig3_sequence()
    batch = recognise(TactileFrames(frames, pitch_mm=PITCH))
    sensor = SmartSensor((N, N), pitch_mm=PITCH, evaluate_every=1)
    streamed = [e for f in frames for e in sensor.push(f)]
    assert streamed == list(batch.events)  # every event on its own frame
    np.testing.assert_array_equal(sensor.result().classes, batch.classes)
    assert sensor.result().identified == batch.identified
    lazy = SmartSensor((N, N), pitch_mm=PITCH)  # default: looks every 16 frames
    early = [e for f in frames for e in lazy.push(f)]
    assert list(lazy.result().events) == list(batch.events)
    assert early == list(batch.events)[: len(early)]  # never out of order, only later


def test_elimination_identifies_reports_unknown_and_keeps_candidates() -> None:
    e = Eliminator()
    e.apply(Tacteme.LC, 0)
    assert "sphere" not in e.candidates and e.outcome is None
    e.apply(Tacteme.LCMP, 1)
    assert e.outcome == "cylinder"
    e.apply(Tacteme.AC_MOVES, 2)  # the "cylinder" slid: nothing fits any more
    assert e.outcome == "unknown"


def test_sliding_face_is_never_identified() -> None:
    frames = [blank()] * 2 + [area(4, 10, c, c + 6) for c in range(2, 10) for _ in range(2)]
    rec = recognise(
        TactileFrames(np.stack(frames), pitch_mm=PITCH), config=TactemeConfig(slip=None)
    )
    assert "AC moves" in [n for n, _ in rec.tactemes]  # paper 001: nothing fits a slide
    assert rec.identified == "unknown"
    slid = recognise(TactileFrames(np.stack(frames), pitch_mm=PITCH))
    assert slid.slips and ("withheld", "AC moves") in [(e.kind, e.value) for e in slid.events]
    assert slid.identified not in OBJECTS
    assert slid.verdict.reason == "slid"
    assert slid.verdict.sentence().startswith("not identified: slid")


def test_lift_off_reports_the_candidates_left() -> None:
    frames = [blank()] + [point(7, 7)] * 5 + [blank()] * 4
    rec = recognise(TactileFrames(np.stack(frames), pitch_mm=PITCH))
    assert rec.identified is None
    assert set(rec.candidates) == set(OBJECTS)  # a still point rules nothing out
    assert rec.events[-1].kind == "lifted"


def test_every_tacteme_has_a_row_and_a_reason() -> None:
    assert {r.tacteme for r in ALL_ROWS} == set(Tacteme)
    assert all(r.reason and r.eliminates <= set(OBJECTS) for r in ALL_ROWS)


def test_recognise_rejects_a_bare_array_without_pitch() -> None:
    from taxelkit.errors import InputError

    with pytest.raises(InputError, match="pitch_mm"):
        recognise(fig3_sequence())
    with pytest.raises(InputError, match="debounce_frames"):
        TactemeConfig(debounce_frames=0)


def _jumping_line(step: int) -> np.ndarray:
    """A line that jumps ``step`` columns every three frames (a cube tipping edge to edge)."""
    frames = [blank()] * 2 + [line_v(c) for c in range(1, 15, step) for _ in range(3)]
    return np.stack([*frames, blank(), blank()])


@pytest.mark.parametrize("rate_hz", [1.0, 2.0])
def test_sparse_frames_between_which_the_contact_jumped_give_no_motion(rate_hz: float) -> None:
    frames = _jumping_line(4)  # 4 pitches, 7 mm, from frame to frame
    t_s = np.arange(len(frames)) / rate_hz
    rec = TactileFrames(frames, t_s, pitch_mm=PITCH)
    followed = recognise(rec, cleaning=None, config=TactemeConfig(max_motion_gap_s=0.0))
    assert "LCMP" in [n for n, _ in followed.tactemes]  # read as a cylinder rolling
    assert followed.identified == "cylinder" and followed.verdict.unread_gap_s is None
    sparse = recognise(rec, cleaning=None)
    assert not {"LCM", "LCMP"} & {n for n, _ in sparse.tactemes}
    assert sparse.identified is None
    assert sparse.verdict.unread_gap_s == pytest.approx(1.0 / rate_hz)
    assert "too far apart to follow its motion" in sparse.verdict.sentence()
    assert sparse.verdict.to_json()["unread_gap_s"] == pytest.approx(1.0 / rate_hz)
    # streamed, one frame at a time or in chunks: the same events
    for batch in (1, 5):
        sensor = SmartSensor((N, N), pitch_mm=PITCH, cleaning=None, batch_frames=batch)
        for f, t in zip(frames, t_s, strict=True):
            sensor.push(f, float(t))
        assert list(sensor.result().events) == list(sparse.events)
        assert sensor.result().verdict.unread_gap_s == sparse.verdict.unread_gap_s


def test_sparse_frames_that_follow_the_contact_and_dense_frames_keep_their_motion() -> None:
    slow = _jumping_line(1)  # a pitch per three frames at one frame a second (paper 001's rate)
    rec = recognise(TactileFrames(slow, pitch_mm=PITCH), cleaning=None)
    assert rec.identified == "cylinder" and rec.verdict.unread_gap_s is None
    jumps = _jumping_line(4)  # the same jumps at 20 frames/s: the rule does not apply
    dense = TactileFrames(jumps, np.arange(len(jumps)) / 20.0, pitch_mm=PITCH)
    off = TactemeConfig(max_motion_gap_s=0.0)
    assert (
        recognise(dense, cleaning=None).events == recognise(dense, cleaning=None, config=off).events
    )


def test_a_line_that_jumped_between_sparse_frames_gives_no_edge_angle() -> None:
    def line_h(r: int) -> np.ndarray:
        f = blank()
        f[r, 3:13] = True
        return f

    frames = [blank()] * 2 + [line_v(3)] * 3 + [line_v(10)] * 3  # two edges read as one line
    frames += [area()] * 3 + [line_h(8)] * 3 + [blank()] * 2
    rec = TactileFrames(np.stack(frames), pitch_mm=PITCH)  # one frame a second
    square = "LC -> AC -> LC (parallel or 90 deg)"
    off = recognise(rec, cleaning=None, config=TactemeConfig(max_motion_gap_s=0.0))
    assert square in [n for n, _ in off.tactemes]
    on = recognise(rec, cleaning=None)
    names = [n for n, _ in on.tactemes]
    assert square not in names and "AC -> LC" in names  # the transition, without its angle
