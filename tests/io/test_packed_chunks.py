"""Packed contact frames read as stored: the frames, times and checks of ``chunks``."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from taxelkit.errors import InputError, InvalidRecordingError
from taxelkit.frames import TactileFrames
from taxelkit.io.chunked_read import PackedChunk, open_chunks
from taxelkit.io.chunked_write import RecordingAppender
from taxelkit.io.packed_chunk import unpack_rows
from taxelkit.io.recordings import write_recording


def _appended(path: Path, frames: np.ndarray, t_s: np.ndarray) -> Path:
    with RecordingAppender(path, shape=frames.shape[1:], pitch_mm=2.0, chunk_frames=64) as out:
        for a in range(0, frames.shape[0], 37):
            out.append(frames[a : a + 37], t_s[a : a + 37])
    return path


@pytest.mark.parametrize("cols", [5, 8, 13, 16])
def test_packed_chunks_are_the_chunks_packed(tmp_path: Path, cols: int) -> None:
    rng = np.random.default_rng(cols)
    frames = rng.random((300, 4, cols)) < 0.3
    t_s = 0.5 + np.cumsum(rng.random(300))
    path = _appended(tmp_path / "p.h5", frames, t_s)
    for size in (1, 29, 300, 1000):
        with open_chunks(path) as opened:
            assert opened.packed
            plain = list(opened.chunks(size))
            packed = list(opened.packed_chunks(size))
        assert len(plain) == len(packed)
        for p, c in zip(packed, plain, strict=True):
            assert isinstance(p, PackedChunk) and not p.rows.flags.writeable
            assert p.shape == c.shape and p.n_frames == c.n_frames
            assert np.array_equal(p.unpacked(), c.frames)
            assert np.array_equal(p.t_s, c.t_s)
            assert (p.pitch_mm, p.sensor) == (c.pitch_mm, c.sensor) == (2.0, c.sensor)


def test_unpack_rows_ignores_the_bits_past_the_row() -> None:
    frames = np.random.default_rng(3).random((20, 3, 11)) < 0.5
    packed = np.packbits(frames, axis=2, bitorder="little")
    packed[:, :, -1] |= 0xF8  # bits 11..15: not taxels
    assert np.array_equal(unpack_rows(packed, 11), frames)
    whole = np.packbits(frames[:, :, :8], axis=2, bitorder="little")
    assert np.array_equal(unpack_rows(whole, 8), frames[:, :, :8])


def test_frames_not_stored_packed_have_no_packed_chunks(tmp_path: Path) -> None:
    rec = TactileFrames(np.zeros((6, 3, 3), bool))
    for name in ("b.h5", "b.npz", "b.csv"):
        path = write_recording(rec, tmp_path / name)
        with open_chunks(path) as opened:
            if opened.packed:  # a writer that packs bool frames
                assert len(list(opened.packed_chunks(4))) == 2
                continue
            with pytest.raises(InputError, match="not stored packed"):
                list(opened.packed_chunks(4))


def test_packed_timestamps_are_checked_as_by_chunks(tmp_path: Path) -> None:
    path = tmp_path / "r.h5"
    with h5py.File(path, "w") as root:
        root["frames_packed"] = np.zeros((4, 2, 1), np.uint8)
        root["t_s"] = [0.0, 1.0, 0.5, 2.0]
    for size in (2, 4):  # across chunks, and within one
        with open_chunks(path) as opened:
            assert opened.packed
            with pytest.raises(InvalidRecordingError, match="t_s") as plain:
                list(opened.chunks(size))
            with pytest.raises(InvalidRecordingError, match="t_s") as packed:
                list(opened.packed_chunks(size))
        assert str(packed.value) == str(plain.value)
    with open_chunks(path) as opened, pytest.raises(InputError, match="chunk_frames"):
        list(opened.packed_chunks(0))
