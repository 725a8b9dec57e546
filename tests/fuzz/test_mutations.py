"""Readers fed randomly damaged copies of valid files (hypothesis).

A damaged file must either read (the damage missed everything that matters)
or raise a :class:`~taxelkit.errors.TaxelkitError` whose one-line message
names the file; never another exception.
"""

from __future__ import annotations

import io
import tempfile
from collections.abc import Callable
from pathlib import Path

import h5py
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from taxelkit.errors import TaxelkitError
from taxelkit.frames import TactileFrames
from taxelkit.io.csv_format import write_csv_recording
from taxelkit.io.memory_file import read_memory
from taxelkit.io.recordings import read_recording
from taxelkit.world.heightmap import load_heightmap
from tests.fuzz.corpus import valid_heightmap, valid_memory_arrays, valid_recording

#: Examples per reader.
EXAMPLES = 100


def _npz(arrays: dict[str, np.ndarray]) -> bytes:
    buf = io.BytesIO()
    np.savez(buf, **arrays)
    return buf.getvalue()


def _h5() -> bytes:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "r.h5"
        with h5py.File(path, "w") as root:
            for name, value in valid_recording().items():
                root.create_dataset(name, data=value)
        return path.read_bytes()


def _csv() -> bytes:
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "r.csv"
        write_csv_recording(TactileFrames(valid_recording()["frames"]), path)
        return path.read_bytes()


READERS: dict[str, tuple[str, Callable[[], bytes], Callable[[Path], object]]] = {
    "recording-npz": (".npz", lambda: _npz(valid_recording()), read_recording),
    "recording-h5": (".h5", _h5, read_recording),
    "recording-csv": (".csv", _csv, read_recording),
    "heightmap": (".npz", lambda: _npz(valid_heightmap()), load_heightmap),
    "memory": (".npz", lambda: _npz(valid_memory_arrays()), read_memory),
}


@st.composite
def _mutation(draw: st.DrawFn, size: int) -> list[tuple[str, int, int]]:
    """Byte flips, overwrites, truncations and insertions, as (kind, offset, value)."""
    kinds = st.sampled_from(["flip", "set", "truncate", "insert", "delete"])
    step = st.tuples(kinds, st.integers(0, max(size - 1, 0)), st.integers(0, 255))
    return draw(st.lists(step, min_size=1, max_size=6))


def _apply(data: bytes, steps: list[tuple[str, int, int]]) -> bytes:
    out = bytearray(data)
    for kind, offset, value in steps:
        if not out:
            break
        k = offset % len(out)
        if kind == "flip":
            out[k] ^= 1 << (value % 8)
        elif kind == "set":
            out[k] = value
        elif kind == "truncate":
            del out[k:]
        elif kind == "insert":
            out[k:k] = bytes([value]) * (1 + value % 16)
        else:
            del out[k : k + 1 + value % 16]
    return bytes(out)


@pytest.mark.parametrize("reader", list(READERS))
@settings(max_examples=EXAMPLES, deadline=None, derandomize=True, database=None)
@given(data=st.data())
def test_damaged_file_reads_or_raises_one_typed_line(reader: str, data: st.DataObject) -> None:
    suffix, make, read = READERS[reader]
    original = make()
    damaged = _apply(original, data.draw(_mutation(len(original)), label="mutation"))
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"damaged{suffix}"
        path.write_bytes(damaged)
        try:
            read(path)
        except TaxelkitError as exc:
            message = str(exc)
            assert "\n" not in message
            assert str(path) in message, message
