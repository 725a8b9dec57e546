"""Levels 1-2 and foreseen tactemes in a worker process: the one-core result bit for bit."""

from __future__ import annotations

import functools
import multiprocessing as mp
import os
from pathlib import Path

import numpy as np
import pytest

from taxelkit.errors import InputError, RecordingError
from taxelkit.frames import TactileFrames
from taxelkit.io.chunked_write import RecordingAppender
from taxelkit.io.file_chunks import FileChunks
from taxelkit.io.recordings import write_recording
from taxelkit.motion.engines import scenario_from_engine
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.sensors import BONNEVILLE_16X16
from taxelkit.sensors.faults import fault_model
from taxelkit.smart.recognise_chunks import ChunkRecogniser, levels12_of, recognise_chunks
from taxelkit.smart.recognise_pipeline import recognise_pipelined
from taxelkit.smart.tactemes import PAPER_LEVEL3
from taxelkit.smart.whole_segments import WholeSegments


def _rolls(faulty: bool) -> TactileFrames:
    """Three rolls one after another at 100 frames/s: contact frames, or deflections with faults."""
    parts = []
    for k, name in enumerate(("cylinder", "cube", "truncated-cone")):
        sc = scenario_from_engine("kinematic", name, rng=k, rate_hz=100.0)
        rec = frames_from_scenario(BONNEVILLE_16X16, sc, rng=k)
        if faulty:
            rec = fault_model("all").apply(rec, threshold=0.03, rng=k)
        else:
            contact = BONNEVILLE_16X16.contact_from_displacement(rec.frames)
            rec = TactileFrames(contact, rec.t_s, pitch_mm=rec.pitch_mm, units="contact")
        parts.append(rec)
    t, offset = [], 0.0
    for rec in parts:
        t.append(rec.t_s - rec.t_s[0] + offset)
        offset = t[-1][-1] + 0.5
    frames = np.concatenate([r.frames for r in parts])
    return TactileFrames(
        frames, np.concatenate(t), pitch_mm=parts[0].pitch_mm, units=parts[0].units
    )


def _assert_same(got: object, ref: object) -> None:
    for field in ("events", "tactemes", "identified", "candidates", "verdict", "slips"):
        assert getattr(got, field) == getattr(ref, field), field
    for field in ("class_code", "first_frame", "last_frame", "first_s", "last_s"):
        a, b = getattr(got.segments, field), getattr(ref.segments, field)  # type: ignore[attr-defined]
        np.testing.assert_array_equal(a, b)
    np.testing.assert_array_equal(got.classes, ref.classes)  # type: ignore[attr-defined]


@pytest.mark.parametrize(("faulty", "suffix"), [(False, ".h5"), (True, ".npz")])
def test_pipelined_equals_chunked(tmp_path: Path, faulty: bool, suffix: str) -> None:
    rec = _rolls(faulty)
    path = tmp_path / f"rolls{suffix}"
    if suffix == ".h5":  # contact frames appended: stored packed, read packed by the worker
        with RecordingAppender(path, shape=rec.shape[1:], pitch_mm=rec.pitch_mm) as out:
            out.append(rec.frames, rec.t_s)
    else:  # deflections in mm through every fault: the float path and the threshold
        write_recording(rec, path)
    source = FileChunks(path, chunk_frames=97)
    ref = recognise_chunks(source(), per_frame=True)
    assert ref.events and ref.identified is not None  # a comparison that means something
    got = recognise_pipelined(source, per_frame=True)
    _assert_same(got, ref)
    assert not mp.active_children()  # the worker has ended


def test_pipelined_takes_the_options_and_the_pitch(tmp_path: Path) -> None:
    rec = _rolls(False)
    path = write_recording(rec, tmp_path / "rolls.h5")
    options = {"cleaning": None, "limits": None, "config": PAPER_LEVEL3}
    ref = recognise_chunks(FileChunks(path, chunk_frames=256)(), pitch_mm=2.0, **options)
    got = recognise_pipelined(FileChunks(path, chunk_frames=256), pitch_mm=2.0, **options)
    _assert_same(got, ref)


def test_pipelined_raises_the_workers_errors(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="no chunk"):
        recognise_pipelined(functools.partial(iter, ()))
    bad = tmp_path / "bad.npz"
    np.savez(bad, frames=np.zeros((4, 8, 8), bool), t_s=np.array([0.0, 0.1, 0.1, 0.2]))
    with pytest.raises(RecordingError, match="increas"):
        recognise_pipelined(FileChunks(bad))
    with pytest.raises(RecordingError):
        recognise_pipelined(FileChunks(tmp_path / "missing.h5"))
    with pytest.raises(RuntimeError, match="exit code 3"):  # the worker dies without a word
        recognise_pipelined(functools.partial(os._exit, 3))
    assert not mp.active_children()


class _Foreseen(ChunkRecogniser):
    """Levels 3-4 given the tactemes :class:`WholeSegments` computed beforehand; counts them."""

    def __init__(self, *args: object, line_share: float, **options: object) -> None:
        super().__init__(*args, **options)  # type: ignore[arg-type]
        self.whole = WholeSegments(self.config, self.pitch_mm, line_share)
        self.given = self.unasked = 0

    def _next(self, kind: str, data: np.ndarray, t: np.ndarray) -> list[object]:  # type: ignore[override]
        classes, rows = levels12_of(self._levels12, kind, data, t)
        known = self.whole.tactemes(classes[0], rows[0], t)
        self.given += len(known)
        events = self.push_levels12(classes, rows, t, precomputed=known)
        self.unasked += len(known)  # what the stream did not take
        return events  # type: ignore[return-value]


@pytest.mark.parametrize(("faulty", "size", "share"), [(False, 400, 1.0), (True, 1000, 0.5)])
def test_whole_segments_foresees_the_segments_the_stream_closes(
    faulty: bool, size: int, share: float
) -> None:
    rec = _rolls(faulty)
    shape = rec.shape[1:]
    ref = ChunkRecogniser(shape, pitch_mm=rec.pitch_mm, per_frame=True)
    got = _Foreseen(shape, pitch_mm=rec.pitch_mm, per_frame=True, line_share=share)
    for a in range(0, rec.n_frames, size):
        ref.push(rec.frames[a : a + size], rec.t_s[a : a + size])
        got.push(rec.frames[a : a + size], rec.t_s[a : a + size])
    assert got.given >= 3  # segments were foreseen and computed beforehand ...
    assert got.unasked == 0  # ... each one the stream then asked for
    _assert_same(got.result(), ref.result())


def test_line_share_picks_that_share_of_the_lines() -> None:
    rec = _rolls(False)
    counts = {}
    for share in (0.0, 0.5, 1.0):
        got = _Foreseen(rec.shape[1:], pitch_mm=rec.pitch_mm, line_share=share)
        got.push(rec.frames, rec.t_s)
        counts[share] = got.given
    assert counts[0.0] < counts[0.5] < counts[1.0]
