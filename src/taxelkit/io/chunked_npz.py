"""The ``.npz`` side of :func:`~taxelkit.io.chunked_read.open_chunks`.

An uncompressed member (``numpy.savez``) is memory-mapped at its offset in the
archive; a compressed one (``numpy.savez_compressed``) is decompressed as a
stream, a chunk at a time. A column-major member cannot be sliced by frames:
it raises :class:`FortranOrder` and is read whole instead.
"""

from __future__ import annotations

import math
import zipfile
from dataclasses import dataclass
from typing import IO, TYPE_CHECKING, Any

import numpy as np

from taxelkit.errors import CorruptRecordingError, InvalidRecordingError, TaxelkitError
from taxelkit.io._raw import describe_exception, fail
from taxelkit.io.limits import MAX_NPY_HEADER_BYTES, ReadBudget
from taxelkit.io.npz_read import npy_header, npz_members
from taxelkit.io.recording_codecs import sniff

if TYPE_CHECKING:
    from taxelkit.io.chunked_read import ChunkedRecording

__all__ = ["SCALARS", "FortranOrder", "Layout", "item_bytes", "open_npz"]

#: The scalar fields of a recording.
SCALARS = ("pitch_mm", "units", "sensor")


@dataclass(frozen=True)
class Layout:
    """Where a recording's arrays are and what they declare."""

    n_frames: int
    shape: tuple[int, int]
    packed: bool
    #: bytes one frame takes once read (integers become float64)
    frame_bytes: int = 1


def item_bytes(dtype: np.dtype[Any]) -> int:
    """Bytes per taxel once read: integers become float64."""
    return 8 if dtype.kind in "iu" else int(dtype.itemsize)


class FortranOrder(Exception):
    """A column-major ``.npy`` member: read whole instead of in chunks."""


def open_npz(rec: ChunkedRecording, head: bytes) -> None:
    path = rec.path
    if sniff(head) != "npz":
        raise fail(CorruptRecordingError, path, "not an .npz file (no zip archive signature)")
    try:
        archive = rec._stack.enter_context(zipfile.ZipFile(path))
        members = npz_members(path, archive)
        budget = ReadBudget(path)
        for name in SCALARS:
            if name in members:
                with archive.open(members[name]) as fh:
                    shape, dtype = npy_header(path, name, fh)
                budget.take(name, shape, dtype)
                with archive.open(members[name]) as fh:
                    rec._scalars[name] = np.lib.format.read_array(
                        fh, allow_pickle=False, max_header_size=MAX_NPY_HEADER_BYTES
                    )
        if "frames" not in members:
            found = ", ".join(members) or "nothing"
            raise fail(CorruptRecordingError, path, f"no 'frames' array (the file holds: {found})")
        frames, shape, dtype = _npz_array(rec, archive, members["frames"], "frames")
        if len(shape) != 3:
            raise fail(InvalidRecordingError, path, f"frames must be (T, rows, cols), got {shape}")
        t_s = None
        t_dtype: np.dtype[Any] | None = None
        if "t_s" in members:
            t_s, t_shape, t_dtype = _npz_array(rec, archive, members["t_s"], "t_s")
            if t_shape != (shape[0],):
                raise fail(
                    InvalidRecordingError,
                    path,
                    f"t_s must have {shape[0]} entries (one per frame), got shape {t_shape}",
                )
    except (TaxelkitError, FortranOrder):
        raise
    except Exception as exc:
        raise fail(
            CorruptRecordingError, path, f"unreadable .npz recording ({describe_exception(exc)})"
        ) from exc
    rec.layout = Layout(
        int(shape[0]),
        (int(shape[1]), int(shape[2])),
        False,
        shape[1] * shape[2] * item_bytes(dtype),
    )
    if isinstance(frames, np.ndarray) and (t_s is None or isinstance(t_s, np.ndarray)):
        rec._frames, rec._t_s = frames, t_s
        return
    # a compressed member: stream both arrays (the memory maps, if any, are re-opened as streams)
    fh = frames if not isinstance(frames, np.ndarray) else _stream(rec, archive, members["frames"])
    t_fh = None
    if t_s is not None:
        t_fh = t_s if not isinstance(t_s, np.ndarray) else _stream(rec, archive, members["t_s"])
    rec._npz_stream = (fh, dtype, t_fh)
    rec._t_s = t_dtype


def _stream(rec: ChunkedRecording, archive: zipfile.ZipFile, info: zipfile.ZipInfo) -> IO[bytes]:
    fh = rec._stack.enter_context(archive.open(info))
    npy_header(rec.path, info.filename, fh)
    return fh


def _npz_array(
    rec: ChunkedRecording, archive: zipfile.ZipFile, info: zipfile.ZipInfo, name: str
) -> tuple[Any, tuple[int, ...], np.dtype[Any]]:
    """A memory map of a stored member, else an open stream past its header."""
    fh = rec._stack.enter_context(archive.open(info))
    shape, dtype = npy_header(rec.path, name, fh)
    header = fh.tell()
    fh.seek(0)
    version = np.lib.format.read_magic(fh)
    read = (
        np.lib.format.read_array_header_1_0
        if version == (1, 0)
        else (np.lib.format.read_array_header_2_0)
    )
    fortran = bool(read(fh, MAX_NPY_HEADER_BYTES)[1])
    if fortran and len(shape) > 1:
        raise FortranOrder
    if dtype.kind in "US":
        raise fail(CorruptRecordingError, rec.path, f"array {name!r} holds text, not numbers")
    declared = math.prod(shape) * dtype.itemsize
    if declared > info.file_size - header:
        raise fail(
            CorruptRecordingError,
            rec.path,
            f"array {name!r} declares shape {shape} of {dtype} ({declared} bytes) but "
            f"stores {max(info.file_size - header, 0)} bytes",
        )
    if info.compress_type != zipfile.ZIP_STORED or dtype.byteorder == ">":
        return fh, shape, dtype
    # a stored member: its bytes lie in the file after the zip local header
    raw = rec._stack.enter_context(open(rec.path, "rb"))  # noqa: SIM115 - closed by the stack
    raw.seek(info.header_offset)
    local = raw.read(30)
    name_len, extra_len = (
        int.from_bytes(local[26:28], "little"),
        int.from_bytes(local[28:30], "little"),
    )
    offset = info.header_offset + 30 + name_len + extra_len + header
    if math.prod(shape) == 0:
        return np.zeros(shape, dtype), shape, dtype
    mapped = np.memmap(rec.path, dtype=dtype, mode="r", offset=offset, shape=shape)
    return mapped, shape, dtype
