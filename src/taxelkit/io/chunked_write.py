"""Write a long recording a chunk at a time: an HDF5 file that grows, safe to interrupt.

:func:`~taxelkit.io.recordings.write_recording` writes a whole recording at
once, atomically. A day-long recording, or a live session, cannot be held in
memory first, so :class:`RecordingAppender` appends frames to resizable HDF5
datasets as they come. Every ``chunk_frames`` frames it writes one chunk and
flushes the file, so a crash (power, ``kill -9``) loses at most the frames of
the chunk being filled; :meth:`RecordingAppender.close` writes the rest.

The file is written in place, not through a temporary file: an append log is
useful precisely because what was flushed stays readable when the writer
dies. It is refused if it exists (unless ``force``).

Layout (``docs/recording-format.md``): contact frames are stored packed, 8
taxels to a byte along each row, as ``frames_packed`` ``(T, rows, ceil(cols/8))``
uint8 with a ``cols`` attribute (32 bytes per 16 x 16 frame, before
compression); float frames as ``frames`` in their dtype. Both are chunked by
``chunk_frames`` frames and gzip-compressed; ``t_s`` is float64.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import h5py
import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import (
    InputError,
    OutputExistsError,
    OutputWriteError,
    check_positive,
    check_shape,
)
from taxelkit.frames import CONTACT_UNITS
from taxelkit.io.chunked_read import DEFAULT_CHUNK_FRAMES
from taxelkit.io.recording_codecs import PACKED_COLS_ATTR, PACKED_FRAMES

__all__ = ["DEFAULT_GZIP_LEVEL", "RecordingAppender"]

#: gzip level of the appended chunks: 1 compresses contact frames about as
#: well as 9 (they are mostly zeros) at a fraction of the time.
DEFAULT_GZIP_LEVEL = 1
_FLOAT_DTYPES = (np.dtype(np.float16), np.dtype(np.float32), np.dtype(np.float64))


class RecordingAppender:
    """An HDF5 recording written by appending frames (a context manager).

    Parameters
    ----------
    path : str or os.PathLike
        Output ``.h5``/``.hdf5`` file; its folder must exist.
    shape : (rows, cols)
        Frame shape.
    pitch_mm : float
        Taxel pitch, mm.
    dtype : numpy dtype
        ``bool`` for contact images (stored packed), or float16/32/64.
    units : str, optional
        Default ``"contact"`` for bool, ``"mm"`` otherwise.
    sensor : str
        Sensor name.
    chunk_frames : int
        Frames per HDF5 chunk, and per flush.
    force : bool
        Replace an existing file.

    Raises
    ------
    InputError
        If an argument is out of range or the suffix is not ``.h5``/``.hdf5``.
    OutputExistsError
        If ``path`` exists and ``force`` is false.
    OutputWriteError
        If the file cannot be created.

    Examples
    --------
    >>> import tempfile
    >>> from taxelkit.io.recordings import read_recording
    >>> out = Path(tempfile.mkdtemp()) / "long.h5"
    >>> with RecordingAppender(out, shape=(4, 4), pitch_mm=2.0, chunk_frames=8) as rec:
    ...     for t in range(20):
    ...         rec.append(np.eye(4, dtype=bool)[None], [0.01 * t])
    >>> read_recording(out).n_frames
    20
    """

    def __init__(
        self,
        path: str | os.PathLike[str],
        *,
        shape: tuple[int, int],
        pitch_mm: float,
        dtype: Any = bool,
        units: str | None = None,
        sensor: str = "unknown",
        chunk_frames: int = DEFAULT_CHUNK_FRAMES,
        force: bool = False,
    ) -> None:
        self.path = Path(path)
        if self.path.suffix.lower() not in (".h5", ".hdf5"):
            raise InputError(f"a long recording is written as .h5 or .hdf5, got {self.path.name!r}")
        self.shape = check_shape("shape", shape)
        self.dtype = np.dtype(dtype)
        if self.dtype != np.dtype(bool) and self.dtype not in _FLOAT_DTYPES:
            raise InputError(f"dtype must be bool, float16, float32 or float64, got {self.dtype}")
        if isinstance(chunk_frames, bool) or not isinstance(chunk_frames, int) or chunk_frames < 1:
            raise InputError(f"chunk_frames must be an integer >= 1, got {chunk_frames!r}")
        self.chunk_frames = chunk_frames
        self.packed = self.dtype == np.dtype(bool)
        if units is None:
            units = CONTACT_UNITS if self.packed else "mm"
        if self.packed != (units == CONTACT_UNITS):
            raise InputError(f"units {CONTACT_UNITS!r} go with bool frames, got {units!r}")
        if self.path.exists() and not force:
            raise OutputExistsError(f"{self.path}: exists; pass force=True (--force) to replace it")
        rows, cols = self.shape
        stored: tuple[int, ...] = (rows, math.ceil(cols / 8)) if self.packed else (rows, cols)
        try:
            self._file = h5py.File(self.path, "w")
        except OSError as exc:
            raise OutputWriteError(f"{self.path}: cannot create ({exc})") from None
        name = PACKED_FRAMES if self.packed else "frames"
        self._frames = self._file.create_dataset(
            name,
            shape=(0, *stored),
            maxshape=(None, *stored),
            dtype=np.uint8 if self.packed else self.dtype,
            chunks=(chunk_frames, *stored),
            compression="gzip",
            compression_opts=DEFAULT_GZIP_LEVEL,
        )
        if self.packed:
            self._frames.attrs[PACKED_COLS_ATTR] = cols
        self._t_s = self._file.create_dataset(
            "t_s", shape=(0,), maxshape=(None,), dtype=np.float64, chunks=(chunk_frames,)
        )
        self._file.attrs["pitch_mm"] = np.float64(check_positive("pitch_mm", pitch_mm))
        self._file.attrs["units"] = units
        self._file.attrs["sensor"] = sensor
        self._buffer = np.empty((chunk_frames, *stored), self._frames.dtype)
        self._buffer_t = np.empty(chunk_frames)
        self._filled = 0
        self._written = 0
        self._t_last = -math.inf
        self._file.flush()

    @property
    def n_frames(self) -> int:
        """Frames appended so far (written or buffered)."""
        return self._written + self._filled

    def __enter__(self) -> RecordingAppender:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def append(self, frames: ArrayLike, t_s: ArrayLike) -> None:
        """Append frames; every full chunk is written and flushed.

        Parameters
        ----------
        frames : (n, rows, cols) bool or float
            In the recording's dtype (float frames are cast to it).
        t_s : (n,) float, s
            Timestamps, strictly increasing, after those already appended.

        Raises
        ------
        InputError
            If shapes, dtype or timestamps are wrong, or the file is closed.
        """
        if not self._file:
            raise InputError(f"{self.path}: the recording is closed")
        f = np.asarray(frames)
        t = np.asarray(t_s, dtype=np.float64)
        if f.ndim != 3 or f.shape[1:] != self.shape or t.shape != (f.shape[0],):
            raise InputError(
                f"frames must be (n, {self.shape[0]}, {self.shape[1]}) with t_s (n,), "
                f"got {f.shape} and {t.shape}"
            )
        if (f.dtype == bool) != self.packed:
            raise InputError(f"frames must be {self.dtype}, got {f.dtype}")
        if t.size and (not t[0] > self._t_last or np.any(np.diff(t) <= 0)):
            raise InputError("t_s must be strictly increasing across appends")
        if not np.all(np.isfinite(t)) or (not self.packed and not np.all(np.isfinite(f))):
            raise InputError("frames and t_s must be finite")
        rows: NDArray[Any] = (
            np.packbits(f, axis=2, bitorder="little") if self.packed else f.astype(self.dtype)
        )
        done = 0
        while done < rows.shape[0]:
            take = min(self.chunk_frames - self._filled, rows.shape[0] - done)
            self._buffer[self._filled : self._filled + take] = rows[done : done + take]
            self._buffer_t[self._filled : self._filled + take] = t[done : done + take]
            self._filled += take
            done += take
            if self._filled == self.chunk_frames:
                self.flush()
        if t.size:
            self._t_last = float(t[-1])

    def flush(self) -> None:
        """Write the buffered frames and flush the file to disk."""
        if not self._file:
            return
        n = self._filled
        if n:
            a = self._written
            self._frames.resize(a + n, axis=0)
            self._t_s.resize(a + n, axis=0)
            self._frames[a : a + n] = self._buffer[:n]
            self._t_s[a : a + n] = self._buffer_t[:n]
            self._written += n
            self._filled = 0
        self._file.flush()

    def close(self) -> None:
        """Write what is buffered and close the file (idempotent)."""
        if self._file:
            self.flush()
            self._file.close()
