"""Read a recording a chunk of frames at a time: memory bounded by the chunk, not the file.

:func:`~taxelkit.io.recordings.read_recording` loads a whole recording, under
the read limit of :mod:`taxelkit.io.limits`. :func:`open_chunks` opens one
and yields it as consecutive :class:`~taxelkit.frames.TactileFrames` of at
most ``chunk_frames`` frames each, validated as a whole recording is (each
chunk by the same rules, and timestamps increasing across chunks):

* ``.h5``/``.hdf5``: ``frames`` (or the packed ``frames_packed``, see
  ``docs/recording-format.md``) and ``t_s`` are sliced from the datasets;
* ``.npz``: an uncompressed member (``numpy.savez``) is memory-mapped, a
  compressed one (``numpy.savez_compressed``) is decompressed as a stream;
* ``.csv``, ``.mcap`` and bags are read whole and then cut (under the limit).

The read limit then applies to one chunk, not to the file: large recordings
need no ``--max-mb``. Links, external storage and virtual datasets are refused
as by the whole-file readers.
"""

from __future__ import annotations

import contextlib
import math
import os
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import IO, Any

import h5py
import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import (
    CorruptRecordingError,
    EmptyRecordingError,
    FileTooLargeError,
    InputError,
    InvalidRecordingError,
    TaxelkitError,
    check_positive,
)
from taxelkit.frames import DEFAULT_FRAME_INTERVAL_S, TactileFrames
from taxelkit.io._raw import RawRecording, describe_exception, fail
from taxelkit.io.chunked_h5 import open_h5
from taxelkit.io.chunked_npz import FortranOrder, Layout, open_npz
from taxelkit.io.limits import ReadBudget
from taxelkit.io.packed_chunk import PackedChunk, unpack_rows
from taxelkit.io.recording_codecs import PACKED_COLS_ATTR, PACKED_FRAMES
from taxelkit.io.recording_fields import build_frames
from taxelkit.io.recordings import _probe_input, read_recording

__all__ = [
    "DEFAULT_CHUNK_FRAMES",
    "PACKED_COLS_ATTR",
    "PACKED_FRAMES",
    "ChunkedRecording",
    "PackedChunk",
    "open_chunks",
]

#: Frames per chunk by default: 65,536 frames of 16 x 16 are 16 MiB as bool.
DEFAULT_CHUNK_FRAMES = 65536
#: Largest ratio of the frames' declared bytes to the file's size that is read
#: without raising the limit: gzip packs zeros about 1000x, real recordings of
#: contact frames (packed) 3-30x, so a file declaring more is taken for a
#: decompression bomb or a sparse dataset (the limit still applies to it).
MAX_EXPANSION = 256
#: Timestamps checked at a time by :meth:`ChunkedRecording.frames_at` (8 MiB).
_TIME_CHUNK_FRAMES = 2**20


class ChunkedRecording:
    """An open recording read chunk by chunk (use :func:`open_chunks`).

    Attributes
    ----------
    path : pathlib.Path
    n_frames : int
        Frames in the recording.
    shape : (rows, cols)
        Frame shape.
    """

    def __init__(self, path: Path, pitch_mm: float | None) -> None:
        self.path = path
        self._override = pitch_mm
        self._stack = contextlib.ExitStack()
        self._scalars: dict[str, object | None] = {}
        self._whole: TactileFrames | None = None
        self._frames: Any = None  # h5py dataset, numpy memmap, or a zip member stream
        self._t_s: Any = None
        self._npz_stream: tuple[IO[bytes], np.dtype[Any], IO[bytes] | None] | None = None
        self.layout = Layout(0, (0, 0), False)

    @property
    def n_frames(self) -> int:
        """Frames in the recording."""
        return self.layout.n_frames

    @property
    def shape(self) -> tuple[int, int]:
        """Frame shape ``(rows, cols)``."""
        return self.layout.shape

    def __enter__(self) -> ChunkedRecording:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        """Close the file."""
        self._stack.close()

    def chunks(self, chunk_frames: int | None = None) -> Iterator[TactileFrames]:
        """Yield the recording as consecutive validated pieces of at most ``chunk_frames``.

        Parameters
        ----------
        chunk_frames : int, optional
            Frames per piece, >= 1. Default :data:`DEFAULT_CHUNK_FRAMES`, fewer
            if a piece would take more than a quarter of the read limit.

        Yields
        ------
        TactileFrames
            Pieces in order; their timestamps are those of the whole recording.

        Raises
        ------
        RecordingError
            If a piece breaks the rules of a recording (named by its frames).
        """
        chunk_frames = self._chunk_frames(chunk_frames)
        if self._whole is not None:
            whole = self._whole
            for a in range(0, whole.n_frames, chunk_frames):
                yield TactileFrames(
                    whole.frames[a : a + chunk_frames],
                    whole.t_s[a : a + chunk_frames],
                    pitch_mm=whole.pitch_mm,
                    units=whole.units,
                    sensor=whole.sensor,
                )
            return
        yield from self._pieces(0, self.n_frames, chunk_frames)

    @property
    def packed(self) -> bool:
        """Whether the frames are stored packed, and :meth:`packed_chunks` reads them so."""
        return self.layout.packed and self._whole is None and self._npz_stream is None

    def packed_chunks(self, chunk_frames: int | None = None) -> Iterator[PackedChunk]:
        """As :meth:`chunks`, the contact frames kept packed as stored (only if :attr:`packed`).

        The timestamps and the recording's fields are checked as by
        :meth:`chunks` (the same errors); the bits need none.

        Raises
        ------
        InputError
            If the recording is not stored packed.
        """
        if not self.packed:
            raise InputError(f"{self.path} is not stored packed: read it with chunks()")
        cols, step = self.shape[1], self._chunk_frames(chunk_frames)
        for rows, chunk in self._pieces(0, self.n_frames, step, packed=True):
            yield PackedChunk(rows, chunk.t_s, cols, chunk.pitch_mm, chunk.sensor)

    def _chunk_frames(self, chunk_frames: int | None) -> int:
        """Frames per piece: as given (checked), else the default within the read limit."""
        if chunk_frames is None:
            quarter = ReadBudget(self.path).limit // 4
            chunk_frames = max(1, min(DEFAULT_CHUNK_FRAMES, quarter // self.layout.frame_bytes))
        if isinstance(chunk_frames, bool) or not isinstance(chunk_frames, int) or chunk_frames < 1:
            raise InputError(f"chunk_frames must be an integer >= 1, got {chunk_frames!r}")
        return chunk_frames

    def _pieces(
        self, first: int, stop: int, chunk_frames: int = DEFAULT_CHUNK_FRAMES, packed: bool = False
    ) -> Iterator[Any]:
        """Frames ``first .. stop - 1`` of a sliceable recording, in validated pieces.

        ``packed``: pieces ``(rows, chunk)`` of the packed rows as stored and a
        chunk holding the same timestamps and fields over one-taxel frames
        (validated as the frames would be; bits need no check).
        """
        budget = ReadBudget(self.path)
        t_last = -math.inf
        for a in range(first, stop, chunk_frames):
            b = min(a + chunk_frames, stop)
            frames, t_s = self._read(a, b, budget, unpack=not packed)
            rows = frames
            if packed:
                frames = np.broadcast_to(np.zeros((1, 1, 1), bool), (b - a, 1, 1))
            if t_s is not None and t_s.size and not t_s[0] > t_last:
                raise fail(
                    InvalidRecordingError,
                    self.path,
                    f"t_s must be strictly increasing, got t_s[{a - 1}]={t_last!r} "
                    f">= t_s[{a}]={float(t_s[0])!r}",
                )
            if t_s is None:
                t_s = np.arange(a, b, dtype=np.float64) * DEFAULT_FRAME_INTERVAL_S
            scalars = self._scalars
            raw = RawRecording(
                frames=frames,
                t_s=t_s,
                pitch_mm=scalars.get("pitch_mm"),
                units=scalars.get("units"),
                sensor=scalars.get("sensor"),
            )
            # frames read from HDF5 are new arrays (a memory-mapped member's are not)
            owned = isinstance(self._frames, h5py.Dataset)
            chunk = build_frames(raw, self.path, self._override, owned=owned)
            t_last = float(chunk.t_s[-1])
            if packed:
                rows.setflags(write=False)
                yield rows, chunk
            else:
                yield chunk

    def frames_at(self, indices: Sequence[int]) -> TactileFrames:
        """Only the frames at ``indices`` (increasing, in ``[0, n_frames)``), as a recording.

        HDF5 datasets and memory-mapped members are read at those frames only;
        compressed ``.npz`` members are read through once.
        """
        wanted = np.asarray(indices, dtype=np.int64)
        if wanted.ndim != 1 or wanted.size == 0 or np.any(np.diff(wanted) <= 0):
            raise InputError("indices must be a non-empty increasing sequence of frames")
        if wanted[0] < 0 or wanted[-1] >= self.n_frames:
            raise InputError(f"indices must lie in [0, {self.n_frames - 1}], got {wanted.tolist()}")
        frames: list[NDArray[Any]] = []
        times: list[NDArray[Any]] = []
        template: TactileFrames | None = None
        if self._whole is not None or self._npz_stream is not None:
            start = 0
            for chunk in self.chunks():
                inside = wanted[(wanted >= start) & (wanted < start + chunk.n_frames)] - start
                frames.append(chunk.frames[inside])
                times.append(chunk.t_s[inside])
                template = chunk
                start += chunk.n_frames
        else:
            self._check_times()
            for i in wanted.tolist():
                for chunk in self._pieces(i, i + 1):
                    frames.append(chunk.frames)
                    times.append(chunk.t_s)
                    template = chunk
        assert template is not None
        return TactileFrames(  # pieces of a checked recording: valid together
            np.concatenate(frames),
            np.concatenate(times),
            pitch_mm=template.pitch_mm,
            units=template.units,
            sensor=template.sensor,
        )

    def _check_times(self) -> None:
        """Every timestamp finite and increasing, read a chunk at a time (8 bytes a frame)."""
        if self._t_s is None:
            return
        last = -math.inf
        for a in range(0, self.n_frames, _TIME_CHUNK_FRAMES):
            t = np.asarray(self._t_s[a : a + _TIME_CHUNK_FRAMES], dtype=np.float64)
            if not np.all(np.isfinite(t)):
                raise fail(InvalidRecordingError, self.path, "t_s must be finite (no NaN or Inf)")
            steps = np.diff(np.concatenate([[last], t]))
            if np.any(steps <= 0):
                k = a + int(np.flatnonzero(steps <= 0)[0]) - 1
                raise fail(
                    InvalidRecordingError,
                    self.path,
                    f"t_s must be strictly increasing, got t_s[{k}] >= t_s[{k + 1}]",
                )
            last = float(t[-1])

    def _read(
        self, a: int, b: int, budget: ReadBudget, *, unpack: bool = True
    ) -> tuple[NDArray[Any], NDArray[Any] | None]:
        try:
            if self._npz_stream is not None:
                return self._read_stream(a, b, budget)
            budget.check_block(f"frames {a}..{b - 1}", (b - a) * self.layout.frame_bytes)
            frames = np.asarray(self._frames[a:b])
            if self.layout.packed and unpack:
                frames = unpack_rows(frames, self.shape[1])
            t_s = None if self._t_s is None else np.asarray(self._t_s[a:b])
        except TaxelkitError:
            raise
        except Exception as exc:
            raise fail(
                CorruptRecordingError,
                self.path,
                f"frames {a}..{b - 1} are unreadable ({describe_exception(exc)})",
            ) from exc
        return frames, t_s

    def _read_stream(
        self, a: int, b: int, budget: ReadBudget
    ) -> tuple[NDArray[Any], NDArray[Any] | None]:
        assert self._npz_stream is not None
        fh, dtype, t_fh = self._npz_stream
        n = (b - a) * math.prod(self.shape)
        budget.check_block(f"frames {a}..{b - 1}", (b - a) * self.layout.frame_bytes)
        frames = np.frombuffer(_read_exactly(fh, n * dtype.itemsize), dtype=dtype)
        t_s = None
        if t_fh is not None:
            t_dtype = self._t_s
            t_s = np.frombuffer(_read_exactly(t_fh, (b - a) * t_dtype.itemsize), dtype=t_dtype)
        return frames.reshape((b - a, *self.shape)), t_s


def _read_exactly(fh: IO[bytes], nbytes: int) -> bytes:
    data = fh.read(nbytes)
    if len(data) != nbytes:
        raise EOFError(f"expected {nbytes} bytes, the member ends after {len(data)}")
    return data


def open_chunks(path: str | os.PathLike[str], *, pitch_mm: float | None = None) -> ChunkedRecording:
    """Open a recording to read it chunk by chunk.

    Parameters
    ----------
    path : str or os.PathLike
        A recording file (any format :func:`~taxelkit.io.recordings.read_recording` reads).
    pitch_mm : float, optional
        Taxel pitch, mm, replacing the stored one.

    Returns
    -------
    ChunkedRecording
        Use it as a context manager; iterate :meth:`ChunkedRecording.chunks`.

    Raises
    ------
    RecordingError
        As :func:`~taxelkit.io.recordings.read_recording`, for what can be
        checked before the frames are read (the frames are checked chunk by chunk).

    Examples
    --------
    >>> import tempfile
    >>> from taxelkit.io.recordings import write_recording
    >>> out = write_recording(
    ...     TactileFrames(np.zeros((5, 4, 4), bool)), Path(tempfile.mkdtemp()) / "r.h5")
    >>> with open_chunks(out) as rec:
    ...     [c.n_frames for c in rec.chunks(2)]
    [2, 2, 1]
    """
    p = Path(path)
    override = None if pitch_mm is None else check_positive("pitch_mm", pitch_mm)
    suffix = p.suffix.lower()
    rec = ChunkedRecording(p, override)
    if suffix not in (".h5", ".hdf5", ".npz"):
        rec._whole = read_recording(p, pitch_mm=override)
        rec.layout = Layout(rec._whole.n_frames, rec._whole.shape[1:], False)
        return rec
    size, head = _probe_input(p)
    if size == 0:
        raise fail(EmptyRecordingError, p, "is empty (0 bytes)")
    try:
        if suffix == ".npz":
            open_npz(rec, head)
        else:
            open_h5(rec)
    except FortranOrder:
        rec.close()
        rec = ChunkedRecording(p, override)
        rec._whole = read_recording(p, pitch_mm=override)
        rec.layout = Layout(rec._whole.n_frames, rec._whole.shape[1:], False)
        return rec
    except BaseException:
        rec.close()
        raise
    if rec.n_frames == 0:
        rec.close()
        raise fail(EmptyRecordingError, p, "holds zero frames")
    rows, cols = rec.shape
    per_frame = rows * -(-cols // 8) if rec.layout.packed else rec.layout.frame_bytes
    declared = rec.n_frames * per_frame
    limit = ReadBudget(p).limit
    if declared > max(limit, MAX_EXPANSION * size):
        rec.close()
        raise fail(
            FileTooLargeError,
            p,
            f"declares {declared / 2**20:.4g} MiB of frames in {size / 2**20:.4g} MiB on disk, "
            f"more than {MAX_EXPANSION}x (a decompression bomb?) and over the read limit of "
            f"{limit / 2**20:.4g} MiB; raise the limit with --max-mb or TAXELKIT_MAX_MB",
        )
    return rec
