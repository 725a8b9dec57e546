"""Frames packed one unsigned word per row (or a few for wide arrays), and their shifts.

The image cleaning (:mod:`taxelkit.smart.cleaning`) applies its rules to
packed frames: a taxel's neighbours are the bits of its word shifted left or
right, and the words of the rows above and below.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["PACK_MAX_COLS", "PackedRows", "WordRows", "backend_for", "repeats"]

#: Widest array that is packed into one uint64 per row.
PACK_MAX_COLS = 64


class PackedRows:
    """Frames ``(T, R)`` of unsigned words, bit ``c`` of row ``r`` = taxel ``(r, c)``.

    The word is the smallest of 8, 16, 32, 64 bits that holds a row: the
    operations stream through memory, so a 16-column array in ``uint16`` costs
    a quarter of ``uint64``.
    """

    def __init__(self, cols: int) -> None:
        self.bytes = next(b for b in (1, 2, 4, 8) if 8 * b >= cols)
        self.dtype = np.dtype(f"<u{self.bytes}")
        self.mask = self.dtype.type((1 << cols) - 1)
        self._full = cols == 8 * self.bytes  # a shift left drops the last column itself

    def pack(self, images: NDArray[np.bool_]) -> NDArray[Any]:
        t, r, c = images.shape
        if c % 8 == 0:  # whole bytes: pack the flat array (contiguous, fast)
            b = np.packbits(images.reshape(-1), bitorder="little").reshape(t, r, c // 8)
        else:
            b = np.packbits(images, axis=2, bitorder="little")
        if b.shape[2] != self.bytes:
            full = np.zeros((t, r, self.bytes), np.uint8)
            full[:, :, : b.shape[2]] = b
            b = full
        out: NDArray[Any] = np.ascontiguousarray(b).view(self.dtype).reshape(t, r)
        return out

    def unpack(self, rows: NDArray[Any], cols: int) -> NDArray[np.bool_]:
        t, r = rows.shape
        b = np.ascontiguousarray(rows).view(np.uint8)
        if cols == 8 * self.bytes:  # whole words: unpack the flat array (3x faster)
            flat = np.unpackbits(b.reshape(-1), bitorder="little").view(bool)
            return flat.reshape(t, r, cols)
        out: NDArray[np.bool_] = np.unpackbits(
            b.reshape(t, r, self.bytes), axis=2, count=cols, bitorder="little"
        ).view(bool)
        return out

    def left(self, a: NDArray[Any], n: int = 1) -> NDArray[Any]:
        """Taxel (r, c) gets (r, c - n)."""
        out: NDArray[Any] = a << self.dtype.type(n)
        if not self._full:
            out &= self.mask
        return out

    def right(self, a: NDArray[Any], n: int = 1) -> NDArray[Any]:
        """Taxel (r, c) gets (r, c + n)."""
        out: NDArray[Any] = a >> self.dtype.type(n)
        return out

    @staticmethod
    def down(a: NDArray[Any], n: int = 1) -> NDArray[Any]:
        """Taxel (r, c) gets (r - n, c)."""
        # one contiguous copy of all frames shifted by n rows, then each frame's first
        # n rows (they got the previous frame's last ones) cleared
        out = np.empty(a.shape, a.dtype)
        step = n * int(np.prod(a.shape[2:], dtype=np.int64))
        if step < out.size:
            out.reshape(-1)[step:] = np.ascontiguousarray(a).reshape(-1)[:-step]
        out[:, :n] = 0
        return out

    @staticmethod
    def up(a: NDArray[Any], n: int = 1) -> NDArray[Any]:
        """Taxel (r, c) gets (r + n, c)."""
        out = np.empty(a.shape, a.dtype)
        step = n * int(np.prod(a.shape[2:], dtype=np.int64))
        if step < out.size:
            out.reshape(-1)[:-step] = np.ascontiguousarray(a).reshape(-1)[step:]
        out[:, -n:] = 0
        return out

    @staticmethod
    def any_per_frame(a: NDArray[Any]) -> NDArray[np.bool_]:
        t = a.shape[0]
        frame_bytes = a.size // t * a.itemsize if t else 0
        if t and a.flags.c_contiguous and frame_bytes % 8 == 0:
            # a frame's words OR-ed 64 bits at a time, column by column (a short axis
            # reduced by NumPy costs a call per frame)
            w = a.reshape(t, -1).view(np.uint64)
            acc = w[:, 0].copy()
            for j in range(1, w.shape[1]):
                acc |= w[:, j]
            seen: NDArray[np.bool_] = acc != 0
            return seen
        out: NDArray[np.bool_] = np.any(a.reshape(t, -1) != 0, axis=1)
        return out

    @staticmethod
    def per_frame(flags: NDArray[np.bool_], like: NDArray[Any]) -> NDArray[Any]:
        """A per-frame flag as an all-ones/zeros word, shaped to broadcast against ``like``."""
        ones = np.invert(like.dtype.type(0))
        out: NDArray[Any] = (flags.astype(like.dtype) * ones).reshape(
            (-1,) + (1,) * (like.ndim - 1)
        )
        return out


class WordRows(PackedRows):
    """Frames ``(T, R, W)`` of uint64 words: row ``r`` spans ``W`` words, bit ``c % 64`` of
    word ``c // 64`` is taxel ``(r, c)`` (arrays wider than 64 columns)."""

    def __init__(self, cols: int) -> None:
        self.words = -(-cols // PACK_MAX_COLS)
        self.dtype = np.dtype("<u8")
        self.cols = cols
        self.last_mask = np.uint64((1 << (cols - PACK_MAX_COLS * (self.words - 1))) - 1)

    def pack(self, images: NDArray[np.bool_]) -> NDArray[Any]:
        t, r, c = images.shape
        b = np.zeros((t, r, 8 * self.words), np.uint8)
        b[:, :, : -(-c // 8)] = np.packbits(images, axis=2, bitorder="little")
        out: NDArray[Any] = b.view(self.dtype)
        return out

    def unpack(self, rows: NDArray[Any], cols: int) -> NDArray[np.bool_]:
        b = np.ascontiguousarray(rows).view(np.uint8)
        out: NDArray[np.bool_] = np.unpackbits(b, axis=2, count=cols, bitorder="little").view(bool)
        return out

    def left(self, a: NDArray[Any], n: int = 1) -> NDArray[Any]:
        """Taxel (r, c) gets (r, c - n): each word shifts up, taking the top of the one before."""
        out: NDArray[Any] = a << np.uint64(n)
        out[:, :, 1:] |= a[:, :, :-1] >> np.uint64(PACK_MAX_COLS - n)
        out[:, :, -1] &= self.last_mask
        return out

    def right(self, a: NDArray[Any], n: int = 1) -> NDArray[Any]:
        """Taxel (r, c) gets (r, c + n)."""
        out: NDArray[Any] = a >> np.uint64(n)
        out[:, :, :-1] |= a[:, :, 1:] << np.uint64(PACK_MAX_COLS - n)
        return out


def backend_for(cols: int) -> PackedRows:
    """The packed rows of an array ``cols`` taxels wide."""
    return PackedRows(cols) if cols <= PACK_MAX_COLS else WordRows(cols)


def repeats(
    flat: NDArray[Any], packed: NDArray[Any] | None, worth: float
) -> NDArray[np.bool_] | None:
    """``(n,)``: frames unlike the frame before them (the first is new).

    Frames of several arrays laid end to end may match across arrays: equal
    images have equal statistics. Compared 64 bits at a time, on the packed
    rows ``packed`` if given (else on the bool frames ``flat``, ``(n, ...)``);
    None when frames do not fill whole 64-bit words, or when more than
    ``worth`` of them are new (too few repeat to be worth gathering).
    """
    n = flat.shape[0]
    per = (flat if packed is None else packed).reshape(n, -1)
    if n < 2 or (per.shape[1] * per.itemsize) % 8 or not per.flags.c_contiguous:
        return None
    w = per.view(np.uint64)
    new = np.empty(n, bool)
    new[0] = True
    diff = new[1:]
    np.not_equal(w[1:, 0], w[:-1, 0], out=diff)
    for j in range(1, w.shape[1]):
        diff |= w[1:, j] != w[:-1, j]
    return None if np.count_nonzero(new) > worth * n else new
