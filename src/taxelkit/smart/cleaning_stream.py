"""The image cleaning of :mod:`taxelkit.smart.cleaning`, one frame at a time (streaming).

A frame is held as one Python integer, a bitboard: taxel ``(r, c)`` is bit
``r x (cols + 2) + c``, and the two spare bits per row keep shifts by one
or two columns from wrapping into the next row. Python's integer operations
on a few hundred bits take tens of nanoseconds, where NumPy on a 16 x 16
array spends microseconds per call; the rules themselves are the batch
module's functions, applied to these integers. The per-taxel state of the
stuck rule (how long a taxel has been isolated, how long a masked one has
been off) is kept only for the few taxels concerned.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.smart.cleaning import (
    CleaningConfig,
    _bridged,
    _crowded,
    _dilate3,
    _neighbours8,
    _stray,
    release_frames_for,
    stuck_frames_for,
)

__all__ = ["ImageCleaner"]

#: Spare bits after each row of the bitboard (shifts go up to two columns).
_GUARD_BITS = 2


class _IntOps:
    """The shift operations of the batch backends, on a bitboard integer."""

    def __init__(self, rows: int, cols: int) -> None:
        self.rows, self.cols = rows, cols
        self.stride = cols + _GUARD_BITS
        row = (1 << cols) - 1
        self.mask = sum(row << (r * self.stride) for r in range(rows))
        self._n_bytes = (rows * self.stride + 7) // 8

    def pack(self, image: NDArray[np.bool_]) -> int:
        padded = np.zeros((self.rows, self.stride), bool)
        padded[:, : self.cols] = image
        return int.from_bytes(np.packbits(padded, bitorder="little").tobytes(), "little")

    def unpack(self, a: int) -> NDArray[np.bool_]:
        raw = np.frombuffer(a.to_bytes(self._n_bytes, "little"), np.uint8)
        bits = np.unpackbits(raw, count=self.rows * self.stride, bitorder="little")
        out: NDArray[np.bool_] = bits.reshape(self.rows, self.stride)[:, : self.cols].view(bool)
        return out

    def left(self, a: int, n: int = 1) -> int:
        """Taxel (r, c) gets (r, c - n)."""
        return (a << n) & self.mask

    def right(self, a: int, n: int = 1) -> int:
        """Taxel (r, c) gets (r, c + n)."""
        return (a >> n) & self.mask

    def up(self, a: int, n: int = 1) -> int:
        """Taxel (r, c) gets (r + n, c)."""
        return a >> (n * self.stride)

    def down(self, a: int, n: int = 1) -> int:
        """Taxel (r, c) gets (r - n, c)."""
        return (a << (n * self.stride)) & self.mask


def _bits(a: int) -> list[int]:
    """Indices of the set bits of a non-negative integer."""
    out = []
    while a:
        low = a & -a
        out.append(low.bit_length() - 1)
        a ^= low
    return out


class ImageCleaner:
    """The cleaning of :func:`~taxelkit.smart.cleaning.clean_images`, one frame at a time.

    For the same frames and timestamps it returns the same images as the batch
    function (tested).

    Parameters
    ----------
    shape : (rows, cols)
    config : CleaningConfig, optional

    Examples
    --------
    >>> import numpy as np
    >>> cleaner = ImageCleaner((8, 8))
    >>> img = np.zeros((8, 8), bool); img[3:5, 3:5] = True
    >>> [int(cleaner.push(f, t).sum()) for f, t in ((img * 0 > 0, 0.0), (img, 0.05), (img, 0.1))]
    [0, 4, 4]
    """

    def __init__(self, shape: tuple[int, int], *, config: CleaningConfig | None = None) -> None:
        rows, cols = int(shape[0]), int(shape[1])
        if rows < 1 or cols < 1:
            raise InputError(f"shape must be two positive integers, got {shape!r}")
        self.shape = (rows, cols)
        self.config = CleaningConfig() if config is None else config
        self._ops = _IntOps(rows, cols)
        self.reset()

    def reset(self) -> None:
        """Forget the stream."""
        self._t0: float | None = None
        self._dt: float | None = None
        self._n_stuck = 3
        self._since_start: int | None = None
        self._held: dict[int, int] = {}  # bit -> frames isolated and on
        self._off: dict[int, int] = {}  # masked bit -> frames off
        self._armed = 0
        self._prev = 0
        self._prev_passed = 0  # the one-frame test of the frame before (rule 3)

    def push(self, image: Any, t_s: float) -> NDArray[np.bool_]:
        """Clean one image ``(rows, cols)`` bool taken at ``t_s``; return the cleaned image."""
        ops, cfg = self._ops, self.config
        img = np.asarray(image, dtype=bool)
        if img.shape != self.shape:
            raise InputError(f"image must have shape {self.shape}, got {img.shape}")
        on = ops.pack(img)
        if self._since_start is None:
            self._since_start, self._t0 = on, float(t_s)
        elif self._dt is None:
            self._dt = float(t_s) - (self._t0 or 0.0)
            self._n_stuck = stuck_frames_for(self._dt, cfg)
        self._since_start &= on
        stuck = self._stuck(on) if cfg.stuck else 0
        a = _bridged(ops, on, stuck, cfg)
        out = passed = a
        if cfg.persistence:
            crowded = _crowded(ops, a)
            passed = out = a & (_dilate3(ops, self._prev) | crowded)
            if cfg.persistence_depth > 1:
                out = a & (self._prev | crowded | _dilate3(ops, self._prev_passed))
        if cfg.strays:
            stray = _stray(ops, out)
            if out & ~stray:
                out &= ~stray
        self._prev, self._prev_passed = a, passed
        return ops.unpack(out)

    def _stuck(self, on: int) -> int:
        assert self._since_start is not None
        iso = on & ~_neighbours8(self._ops, on)
        self._held = {b: self._held.get(b, 0) + 1 for b in _bits(iso)}
        seed = self._since_start
        for b, n in self._held.items():
            if n >= self._n_stuck:
                seed |= 1 << b
        release = release_frames_for(self._dt, self.config)
        off = {b: (0 if (on >> b) & 1 else self._off.get(b, 0) + 1) for b in _bits(self._armed)}
        gone = sum(1 << b for b, n in off.items() if n >= release)
        self._armed = seed | (self._armed & ~gone)
        self._off = {b: n for b, n in off.items() if not (gone >> b) & 1}
        return on & self._armed
