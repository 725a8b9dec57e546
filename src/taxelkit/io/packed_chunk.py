"""A chunk of contact frames kept as stored: rows packed 8 taxels to a byte.

A recording of contact frames stored packed (``frames_packed``, see
``docs/recording-format.md``) is read by
:meth:`~taxelkit.io.chunked_read.ChunkedRecording.packed_chunks` without
unpacking its bits: the recogniser's image cleaning works on packed rows
(:meth:`~taxelkit.smart.recognise_chunks.ChunkRecogniser.push_packed`), so
the bits are unpacked once, after the cleaning, instead of unpacked, packed
again and unpacked.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["PackedChunk", "unpack_rows"]


def unpack_rows(packed: NDArray[np.uint8], cols: int) -> NDArray[np.bool_]:
    """Bool frames ``(T, rows, cols)`` from rows packed ``(T, rows, ceil(cols / 8))``.

    Bit ``c % 8`` (least significant first) of byte ``c // 8`` is column
    ``c``; the bits past ``cols`` are ignored. Whole bytes unpack the flat
    array at once.
    """
    t, rows, n_bytes = packed.shape
    if cols == 8 * n_bytes:
        flat = np.unpackbits(np.ascontiguousarray(packed).reshape(-1), bitorder="little")
        return flat.view(bool).reshape(t, rows, cols)
    out: NDArray[np.bool_] = np.unpackbits(packed, axis=2, count=cols, bitorder="little").view(bool)
    return out


@dataclass(frozen=True, eq=False)
class PackedChunk:
    """Consecutive contact frames of a recording, packed as stored (read-only arrays).

    Attributes
    ----------
    rows : (T, rows, ceil(cols / 8)) uint8
        Each row's taxels, 8 to a byte: bit ``c % 8`` (least significant
        first) of byte ``c // 8`` is column ``c``; bits past ``cols`` are
        not taxels.
    t_s : (T,) float, s
        Timestamps (those of the whole recording; checked as a recording's).
    cols : int
        Taxels per row.
    pitch_mm : float
        Taxel pitch, mm.
    sensor : str
        Name of the sensor or preset that produced the frames.
    """

    rows: NDArray[np.uint8]
    t_s: NDArray[np.float64]
    cols: int
    pitch_mm: float
    sensor: str = "unknown"

    @property
    def n_frames(self) -> int:
        """Number of frames ``T``."""
        return int(self.rows.shape[0])

    @property
    def shape(self) -> tuple[int, int, int]:
        """``(T, rows, cols)`` of the frames unpacked."""
        return (self.n_frames, int(self.rows.shape[1]), self.cols)

    def unpacked(self) -> NDArray[np.bool_]:
        """The frames as bool contact images ``(T, rows, cols)``."""
        return unpack_rows(self.rows, self.cols)
