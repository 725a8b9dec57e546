"""Batch, out-of-core and streaming recognition give the same events on rolls of all six objects.

The out-of-core path (a recording appended to HDF5, read back chunk by chunk
into :class:`~taxelkit.smart.recognise_chunks.ChunkRecogniser`) and the
streaming sensor (:class:`~taxelkit.smart.streaming.SmartSensor`, one frame
at a time and in mini-batches) must give exactly the events, verdict and
per-frame classes of :func:`~taxelkit.smart.recogniser.recognise`, on clean
contact frames and on deflections through every sensor fault; also on the
six rolls one after another in one recording, so that many segments open
and close inside one chunk.
"""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np
import pytest

from taxelkit.frames import TactileFrames
from taxelkit.io.chunked_read import open_chunks
from taxelkit.io.chunked_write import RecordingAppender
from taxelkit.motion.engines import scenario_from_engine
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.sensors import BONNEVILLE_16X16
from taxelkit.sensors.faults import fault_model
from taxelkit.smart.recognise_chunks import ChunkRecogniser
from taxelkit.smart.recogniser import SmartSensor, recognise
from taxelkit.smart.tacteme_table import OBJECTS

RATE_HZ = 240.0


@functools.lru_cache(maxsize=16)
def _simulated(name: str, seed: int) -> TactileFrames:
    sc = scenario_from_engine("kinematic", name, rng=seed, rate_hz=RATE_HZ)
    return frames_from_scenario(BONNEVILLE_16X16, sc, rng=seed)


def _roll(name: str, seed: int, faulty: bool) -> TactileFrames:
    rec = _simulated(name, seed)
    if faulty:
        return fault_model("all").apply(rec, threshold=0.03, rng=seed)
    contact = BONNEVILLE_16X16.contact_from_displacement(rec.frames)
    return TactileFrames(contact, rec.t_s, pitch_mm=rec.pitch_mm, units="contact")


def _out_of_core(rec: TactileFrames, path: Path, chunk_frames: int) -> object:
    with RecordingAppender(
        path, shape=rec.shape[1:], pitch_mm=rec.pitch_mm, dtype=rec.frames.dtype
    ) as out:
        for a in range(0, rec.n_frames, 1000):  # appended in pieces, as a live session does
            out.append(rec.frames[a : a + 1000], rec.t_s[a : a + 1000])
    with open_chunks(path) as stored:
        recogniser = ChunkRecogniser(stored.shape, pitch_mm=rec.pitch_mm, per_frame=True)
        for chunk in stored.chunks(chunk_frames):
            recogniser.push(chunk.frames, chunk.t_s)
    return recogniser.result()


def _streamed(rec: TactileFrames, batch_frames: int) -> list[object]:
    sensor = SmartSensor(rec.shape[1:], pitch_mm=rec.pitch_mm, batch_frames=batch_frames)
    events = [e for f, t in zip(rec.frames, rec.t_s, strict=True) for e in sensor.push(f, t)]
    return events + sensor.flush()


def _check_all_paths(rec: TactileFrames, tmp_path: Path, chunk_sizes: tuple[int, ...]) -> None:
    ref = recognise(rec)
    assert ref.events, "the roll must produce events for the comparison to mean anything"
    for size in chunk_sizes:
        got = _out_of_core(rec, tmp_path / f"r{size}.h5", size)
        assert got.events == ref.events, size  # type: ignore[attr-defined]
        assert got.verdict == ref.verdict, size  # type: ignore[attr-defined]
        assert got.identified == ref.identified  # type: ignore[attr-defined]
        assert got.slips == ref.slips  # type: ignore[attr-defined]
        np.testing.assert_array_equal(got.classes, ref.classes)  # type: ignore[attr-defined]
    for batch_frames in (1, 64):
        assert _streamed(rec, batch_frames) == list(ref.events), batch_frames


@pytest.mark.parametrize("faulty", [False, True], ids=["clean", "faults"])
@pytest.mark.parametrize("name", OBJECTS)
def test_batch_out_of_core_and_streaming_agree_on_a_roll(
    name: str, faulty: bool, tmp_path: Path
) -> None:
    _check_all_paths(_roll(name, 7, faulty), tmp_path, (173, 4096))


@pytest.mark.parametrize("faulty", [False, True], ids=["clean", "faults"])
def test_six_rolls_in_one_recording_agree_in_large_chunks(faulty: bool, tmp_path: Path) -> None:
    rolls = [_roll(name, 11, faulty) for name in OBJECTS]
    frames, times, t0 = [], [], 0.0
    for r in rolls:
        frames.append(r.frames)
        times.append(r.t_s - r.t_s[0] + t0)
        t0 = times[-1][-1] + 1.0 / RATE_HZ
    first = rolls[0]
    rec = TactileFrames(
        np.concatenate(frames), np.concatenate(times), pitch_mm=first.pitch_mm, units=first.units
    )
    _check_all_paths(rec, tmp_path, (3001, rec.n_frames))


def test_segments_ended_within_a_chunk_skip_the_incremental_scanner(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    import taxelkit.smart.stream_state as stream_state

    made: list[int] = []

    class Counted(stream_state.SegmentScanner):
        def __init__(self, *args: object, **kwargs: object) -> None:
            made.append(1)
            super().__init__(*args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(stream_state, "SegmentScanner", Counted)
    rec = _roll("cube", 7, False)
    whole = ChunkRecogniser(rec.shape[1:], pitch_mm=rec.pitch_mm)
    whole.push(rec.frames, rec.t_s)
    contacts = sum(e.kind == "contact" for e in whole.result().events)
    assert contacts >= 3 and len(made) <= 1  # at most the segment still open at the end
    made.clear()
    pieces = ChunkRecogniser(rec.shape[1:], pitch_mm=rec.pitch_mm)
    for a in range(0, rec.n_frames, 50):
        pieces.push(rec.frames[a : a + 50], rec.t_s[a : a + 50])
    assert len(made) > 1  # segments across chunks go through the scanner
    assert pieces.result().events == whole.result().events
