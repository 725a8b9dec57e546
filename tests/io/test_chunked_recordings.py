"""Reading recordings chunk by chunk, and appending long recordings to HDF5."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

from taxelkit.errors import FileTooLargeError, InvalidRecordingError, OutputExistsError
from taxelkit.frames import TactileFrames
from taxelkit.io.chunked_read import open_chunks
from taxelkit.io.chunked_write import RecordingAppender
from taxelkit.io.limits import read_limit
from taxelkit.io.recordings import read_recording, write_recording


def _recording(dtype: str) -> TactileFrames:
    rng = np.random.default_rng(2)
    frames = rng.random((60, 5, 7))
    data = frames < 0.3 if dtype == "bool" else frames.astype(dtype)
    return TactileFrames(data, 1.0 + np.cumsum(rng.random(60)), pitch_mm=2.5, sensor="s")


def _joined(parts: list[TactileFrames]) -> TactileFrames:
    first = parts[0]
    return TactileFrames(
        np.concatenate([p.frames for p in parts]),
        np.concatenate([p.t_s for p in parts]),
        pitch_mm=first.pitch_mm,
        units=first.units,
        sensor=first.sensor,
    )


@pytest.mark.parametrize("suffix", [".h5", ".npz", ".csv"])
@pytest.mark.parametrize("dtype", ["bool", "float32"])
def test_chunks_rebuild_the_recording(tmp_path: Path, suffix: str, dtype: str) -> None:
    rec = _recording(dtype)
    path = write_recording(rec, tmp_path / f"r{suffix}")
    for size in (1, 7, 60, 100):
        with open_chunks(path) as opened:
            assert opened.n_frames == 60 and opened.shape == (5, 7)
            parts = list(opened.chunks(size))
        assert max(p.n_frames for p in parts) <= size
        assert _joined(parts).equals(rec)


@pytest.mark.parametrize("fortran", [False, True])
def test_uncompressed_npz_is_memory_mapped(tmp_path: Path, fortran: bool) -> None:
    rec = _recording("float64")
    frames = np.asfortranarray(rec.frames) if fortran else rec.frames
    np.savez(tmp_path / "r.npz", frames=frames, t_s=rec.t_s, pitch_mm=2.5, sensor="s")
    with open_chunks(tmp_path / "r.npz") as opened:
        assert isinstance(opened._frames, np.memmap) != fortran  # column-major: read whole
        assert _joined(list(opened.chunks(9))).equals(rec)


def test_a_large_file_is_read_in_chunks_under_the_read_limit(tmp_path: Path) -> None:
    rec = _recording("float64")
    path = write_recording(rec, tmp_path / "r.h5")
    with read_limit(0.001):  # 1 kB: the whole file is refused, a chunk of 2 frames is not
        with pytest.raises(FileTooLargeError, match="read limit"):
            read_recording(path)
        with open_chunks(path) as opened:
            assert _joined(list(opened.chunks(2))).equals(rec)


def test_timestamps_going_back_across_chunks_are_refused(tmp_path: Path) -> None:
    path = tmp_path / "r.h5"
    with h5py.File(path, "w") as root:
        root["frames"] = np.zeros((4, 2, 2), bool)
        root["t_s"] = [0.0, 1.0, 0.5, 2.0]
    with open_chunks(path) as opened, pytest.raises(InvalidRecordingError, match="t_s"):
        list(opened.chunks(2))


def test_appender_writes_packed_contact_frames(tmp_path: Path) -> None:
    rng = np.random.default_rng(0)
    frames = rng.random((500, 5, 13)) < 0.2
    t_s = np.arange(500) * 0.01
    path = tmp_path / "long.h5"
    with RecordingAppender(path, shape=(5, 13), pitch_mm=2.0, chunk_frames=64) as out:
        for a in range(0, 500, 37):
            out.append(frames[a : a + 37], t_s[a : a + 37])
        assert out.n_frames == 500
    rec = read_recording(path)
    assert np.array_equal(rec.frames, frames) and np.array_equal(rec.t_s, t_s)
    assert rec.units == "contact" and rec.pitch_mm == 2.0
    with h5py.File(path) as root:
        assert root["frames_packed"].shape == (500, 5, 2)
    with open_chunks(path) as opened:
        assert np.array_equal(np.concatenate([c.frames for c in opened.chunks(100)]), frames)
    with pytest.raises(OutputExistsError):
        RecordingAppender(path, shape=(5, 13), pitch_mm=2.0)


def test_appender_keeps_float_frames(tmp_path: Path) -> None:
    frames = np.random.default_rng(1).random((30, 3, 3)).astype(np.float32)
    with RecordingAppender(
        tmp_path / "f.h5", shape=(3, 3), pitch_mm=1.0, dtype=np.float32, chunk_frames=8
    ) as out:
        out.append(frames, np.arange(30.0))
        with pytest.raises(ValueError, match="increasing"):
            out.append(frames[:1], [3.0])
    rec = read_recording(tmp_path / "f.h5")
    assert rec.frames.dtype == np.float32 and np.array_equal(rec.frames, frames)


_WRITER = """
import sys
import numpy as np
from taxelkit.io.chunked_write import RecordingAppender
with RecordingAppender(sys.argv[1], shape=(16, 16), pitch_mm=2.0, chunk_frames=500) as out:
    i = 0
    while True:
        frames = np.zeros((100, 16, 16), bool)
        frames[:, 3:6, 4] = True
        out.append(frames, (np.arange(100) + i) * 0.01)
        i += 100
        if i % 500 == 0:
            print(i, flush=True)
"""


@pytest.mark.skipif(os.name != "posix", reason="needs SIGKILL")
def test_a_killed_writer_loses_at_most_one_chunk(tmp_path: Path) -> None:
    path = tmp_path / "crash.h5"
    proc = subprocess.Popen(
        [sys.executable, "-c", _WRITER, str(path)], stdout=subprocess.PIPE, text=True
    )
    assert proc.stdout is not None
    written = 0
    deadline = time.monotonic() + 20
    while written < 5000 and time.monotonic() < deadline:
        written = int(proc.stdout.readline())
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    rec = read_recording(path)
    assert rec.n_frames >= written - 500  # what was flushed is there
    assert rec.n_frames % 500 == 0


def test_recognize_shows_its_progress_on_a_long_recording(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from taxelkit.cli import run

    frames = np.zeros((70_000, 8, 8), bool)
    frames[100:400, 3:5, 3:5] = True  # one short press among clear frames
    short, long = tmp_path / "short.h5", tmp_path / "long.h5"
    for path, n in ((short, 1_000), (long, 70_000)):
        with RecordingAppender(path, shape=(8, 8), pitch_mm=2.0) as out:
            out.append(frames[:n], np.arange(n) / 240.0)
    assert run(["recognize", str(short), "--json"]) == 0
    assert capsys.readouterr().err == ""  # a short file draws no bar
    assert run(["recognize", str(long), "--json"]) == 0
    out = capsys.readouterr()
    assert "long.h5" in out.err and "frame" in out.err  # the bar, on stderr
    assert json.loads(out.out)["n_frames"] == 70_000  # stdout keeps the JSON alone
