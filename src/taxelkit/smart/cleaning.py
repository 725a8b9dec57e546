"""Image cleaning before Level 1: stuck taxels, dead taxels and flicker, from the stream itself.

Paper 001 thresholds each taxel and hands the binary image to Level 1. A real
array's faults (:mod:`taxelkit.sensors.faults`) then become contacts: a stuck
taxel is a point that never lifts, a flickering taxel a point that comes and
goes, a dead taxel splits a line. The cleaning below needs no calibration: it
reads the faults off the stream, causally (frame ``t`` is cleaned from frames
``0..t``), so the batch and the streaming paths give the same images.

Rules, in order (:class:`CleaningConfig` holds the numbers)
    1. **Stuck taxels** are masked. A taxel is stuck when it has been on in
       every frame since the stream began, or isolated (none of its eight
       neighbours on) in every frame for ``stuck_s`` seconds; it stays masked
       until it reads off once. A point contact held perfectly still on one
       taxel for longer than ``stuck_s`` (default 1.5 s; the scripts hold
       still states 0.4-0.9 s) is therefore taken for a stuck taxel, and a
       recording that begins in contact loses the taxels on from its first
       frame until they lift. A masked taxel is released once it has read off
       for ``stuck_release_s`` (a flickering stuck taxel that drops out for a
       frame stays masked).
    2. **Dead taxels and holes** are bridged: an off taxel whose two
       horizontal or two vertical neighbours are on is set on. A contact of a
       convex body contains the taxels between two of its taxels, so this
       only mends what the sensor lost (it thickens two lines one taxel apart,
       which one object does not produce).
    3. **Flicker** is suppressed by persistence. The one-frame test: a
       taxel passes if it or one of its eight neighbours was on (after rules
       1-2) in the previous frame, or if two of its neighbours are on now (a
       cluster of three or more, which independent flips almost never make).
       A random flip passes it when its neighbourhood flipped the frame
       before (probability ``9 r`` for a flip rate ``r``), and two flips side
       by side then survive together, far from the contact, and bend a
       line's moments. So a taxel counts (``persistence_depth=2``, the
       default) only if it was on itself in the previous frame, or two of its
       neighbours are on now, or one of its 3 x 3 block passed the one-frame
       test in the previous frame: a flip must then ride on a chain of flips
       two frames long (about ``r + 81 r^2``). A real contact moves less than
       a taxel per frame at the rates and speeds of interest, and a point
       contact of one or two taxels is delayed by one frame when it appears.
       ``persistence_depth=1`` is the one-frame test alone.
    4. **Stray taxels** are dropped: a taxel with no other taxel within two
       pitches (its 5 x 5 block) is removed when the frame also holds a
       larger contact.

The batch path works on frames packed into one unsigned word per row (arrays
up to 64 columns; wider ones in several uint64 words per row), so cleaning
costs a fraction of Levels 1-4 (``benchmarks/bench_cleaning.py``); the
streaming twin, :class:`~taxelkit.smart.cleaning_stream.ImageCleaner`, holds
one frame as a Python integer (a bitboard) and applies the same rule
functions to it.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.smart.packed_rows import PackedRows, WordRows, backend_for

__all__ = ["CleaningConfig", "clean_images", "release_frames_for", "stuck_frames_for"]

#: The frames a rule function works on: packed rows ``(T, R)``, bool frames
#: ``(T, R, C)``, or one frame as a Python-integer bitboard (streaming).
Board = Any


@dataclass(frozen=True)
class CleaningConfig:
    """Switches and numbers of the image cleaning.

    Parameters
    ----------
    stuck : bool
        Mask stuck taxels (rule 1).
    stuck_s : float
        Time a taxel must stay isolated and on to be taken as stuck, s.
    stuck_release_s : float
        Time a stuck taxel must read off to be released, s (at least 2 frames).
    bridge : bool
        Bridge dead taxels and holes (rule 2).
    persistence : bool
        Suppress flicker (rule 3).
    persistence_depth : int
        Frames of persistence (rule 3): 2 (default), or 1 for the one-frame
        test alone. Measured on the ``robustness`` recordings of seed 0
        (every rate, both engines, 50 rolls a cell) with flicker and with
        every imperfection at once: cones and truncated cones 1516 -> 1521
        of 1600 identified, wrong identities 3 -> 1; cubes and tetrahedra
        1586 -> 1594; spheres and cylinders 1565 -> 1570 (unchanged on the
        other imperfections, 3986 of 4000); the other arrays, clean and
        every imperfection, 1249 -> 1273 of 1536, wrong 10 -> 10. Held-out
        seed 11, cones and truncated cones: 1482 -> 1489, wrong 6 -> 6.
    strays : bool
        Drop stray taxels next to a larger contact (rule 4).
    """

    stuck: bool = True
    stuck_s: float = 1.5
    stuck_release_s: float = 0.2
    bridge: bool = True
    persistence: bool = True
    strays: bool = True
    persistence_depth: int = 2

    def __post_init__(self) -> None:
        check_positive("stuck_s", self.stuck_s)
        check_positive("stuck_release_s", self.stuck_release_s)
        if self.persistence_depth not in (1, 2):
            raise InputError(f"persistence_depth must be 1 or 2, got {self.persistence_depth!r}")


# the two backends of packed rows (taxelkit.smart.packed_rows), by their old names here
_Packed, _Words, _backend = PackedRows, WordRows, backend_for


def _neighbours8(ops: Any, a: Board) -> Board:
    """Taxels with at least one of their eight neighbours on."""
    beside = ops.left(a) | ops.right(a)
    row = a | beside
    out: NDArray[Any] = beside | ops.up(row) | ops.down(row)
    return out


def _crowded(ops: Any, a: Board) -> Board:
    """Taxels with at least two of their eight neighbours on (bit-sliced count).

    Each row's neighbours beside a taxel count ``h1 + 2 h2`` and each row's
    three taxels above or below one ``t1 + 2 t2`` (bit slices); two or more
    of the eight: a two-bit anywhere, or two of the three one-bits.
    """
    left, right = ops.left(a), ops.right(a)
    h1, h2 = left ^ right, left & right
    t1, t2 = a ^ h1, (a & (left | right)) | h2
    u1, u2, d1, d2 = ops.up(t1), ops.up(t2), ops.down(t1), ops.down(t2)
    out: Board = h2 | u2 | d2 | (h1 & (u1 | d1)) | (u1 & d1)
    return out


def _dilate3(ops: Any, a: Board) -> Board:
    row = a | ops.left(a) | ops.right(a)
    out: NDArray[Any] = row | ops.up(row) | ops.down(row)
    return out


def _stray(ops: Any, a: Board) -> Board:
    """Taxels with no other taxel in their 5 x 5 block."""
    beside = ops.left(a) | ops.right(a) | ops.left(a, 2) | ops.right(a, 2)
    row5 = a | beside
    others = beside | ops.up(row5) | ops.down(row5) | ops.up(row5, 2) | ops.down(row5, 2)
    out: NDArray[Any] = a & ~others
    return out


def _time_shift(a: NDArray[Any], n: int) -> NDArray[Any]:
    """Frame ``t`` gets frame ``t - n`` (zeros before the start)."""
    out = np.zeros_like(a)
    if n < a.shape[0]:
        out[n:] = a[:-n] if n > 0 else a
    return out


def _on_since_start(on: NDArray[Any]) -> NDArray[Any]:
    """Taxels on in every frame ``0..t`` (a running AND, stopped once nothing is left)."""
    out = np.zeros_like(on)
    acc = on[0]
    t, chunk = 0, 16
    while t < on.shape[0] and np.any(acc):
        seg = np.bitwise_and.accumulate(np.concatenate([acc[None], on[t : t + chunk]]), axis=0)
        out[t : t + chunk] = seg[1:]
        acc = seg[-1]
        t, chunk = t + chunk, 2 * chunk
    return out


def _held(a: NDArray[Any], n: int) -> NDArray[Any]:
    """Taxels on in each of the frames ``t - n + 1 .. t`` (bitwise, by doubling, until clear)."""
    out = a.copy()
    span = 1
    while span < n and np.any(out):
        step = min(span, n - span)
        out = out & _time_shift(out, step)
        span += step
    return out


def stuck_frames_for(dt_s: float, config: CleaningConfig) -> int:
    """Frames a taxel must stay isolated to be taken as stuck, from the frame interval."""
    return max(3, math.ceil(config.stuck_s / dt_s - 1e-9)) if dt_s > 0 else 3


def release_frames_for(dt_s: float | None, config: CleaningConfig) -> int:
    """Frames a stuck taxel must read off to be released, from the frame interval."""
    return max(2, math.ceil(config.stuck_release_s / dt_s - 1e-9)) if dt_s else 2


def _stuck_mask(
    ops: PackedRows,
    on: NDArray[Any],
    n_stuck: int,
    n_release: int,
    *,
    since_start: NDArray[Any] | None = None,
) -> NDArray[Any]:
    """Bits to mask as stuck in each frame (``on`` is the raw image)."""
    start = _on_since_start(on) if since_start is None else since_start
    seed = start | _held(on & ~_neighbours8(ops, on), n_stuck)
    if not np.any(seed):
        return np.zeros_like(on)
    # a seeded taxel stays masked until it has read off for n_release frames: per taxel
    frames, rest = on.shape[0], on.shape[1:]
    on_f = on.reshape(frames, -1)
    seed_f = seed.reshape(frames, -1)
    out = np.zeros_like(on_f)
    idx = np.arange(frames)
    cols = np.flatnonzero(np.bitwise_or.reduce(seed_f, axis=0))
    for j in cols.tolist():  # a few taxels (or rows of packed taxels) at most
        for bit in _bits_of(int(np.bitwise_or.reduce(seed_f[:, j])), on_f.dtype):
            o = (on_f[:, j] & bit) != 0
            s = (seed_f[:, j] & bit) != 0
            last_on = np.maximum.accumulate(np.where(o, idx, -1))
            released = (idx - last_on) >= n_release
            last_release = np.maximum.accumulate(np.where(released, idx, -1))
            last_seed = np.maximum.accumulate(np.where(s, idx, -1))
            masked = o & (last_seed > last_release)
            out[masked, j] |= bit
    return out.reshape((frames, *rest))


def _bits_of(word: int, dtype: Any) -> list[Any]:
    if np.dtype(dtype) == np.dtype(bool):
        return [True] if word else []
    return [dtype.type(1 << b) for b in range(8 * dtype.itemsize) if (word >> b) & 1]


def _bridged(ops: Any, on: Board, stuck: Board, config: CleaningConfig) -> Board:
    """Rules 1-2: stuck taxels masked, dead taxels and holes bridged."""
    a: Board = on & ~stuck
    if config.bridge:
        a = a | (ops.left(a) & ops.right(a)) | (ops.up(a) & ops.down(a))
    return a


def _after(first: NDArray[Any], frames: NDArray[Any]) -> NDArray[Any]:
    """Each frame's predecessor: ``first``, then ``frames`` but the last (axis 0)."""
    return np.concatenate([first[None], frames[:-1]])


def _clean(
    ops: PackedRows,
    a: NDArray[Any],
    prev: NDArray[Any],
    prev_passed: NDArray[Any],
    config: CleaningConfig,
    after: Callable[[NDArray[Any], NDArray[Any]], NDArray[Any]] = _after,
) -> tuple[NDArray[Any], NDArray[Any]]:
    """Rules 3-4 on bridged packed frames ``a``.

    ``prev`` is the bridged frame before the first and ``prev_passed`` its
    one-frame test (rule 3); ``after(first, frames)`` gives each frame's
    predecessor. Returns the cleaned frames and the one-frame test of ``a``
    (the next chunk's ``prev_passed`` comes from it).
    """
    out, passed = a, a
    if config.persistence and a.shape[0]:
        before = after(prev, a)
        crowded = _crowded(ops, a)
        passed = a & (_dilate3(ops, before) | crowded)
        out = passed
        if config.persistence_depth > 1:
            out = a & (before | crowded | _dilate3(ops, after(prev_passed, passed)))
    if config.strays:
        stray = _stray(ops, out)
        big = ops.any_per_frame(out & ~stray)
        out = out & ~(stray & ops.per_frame(big, out))
    return out, passed


def clean_images(
    images: ArrayLike, t_s: ArrayLike, *, config: CleaningConfig | None = None
) -> NDArray[np.bool_]:
    """Clean a whole sequence of contact images (batch; causal, same as :class:`ImageCleaner`).

    Parameters
    ----------
    images : (T, rows, cols) bool
        Thresholded contact images.
    t_s : (T,) float, s
        Timestamps (the stuck rule's time base is the interval of the first two).
    config : CleaningConfig, optional

    Returns
    -------
    (T, rows, cols) bool
        The cleaned images.
    """
    cfg = CleaningConfig() if config is None else config
    img = np.asarray(images)
    if img.ndim != 3 or img.dtype != bool:
        raise InputError(f"images must be bool with shape (T, rows, cols), got {img.dtype}")
    t = np.asarray(t_s, dtype=np.float64)
    if t.shape != (img.shape[0],):
        raise InputError(f"t_s must have shape ({img.shape[0]},), got {t.shape}")
    if img.shape[0] == 0:
        return img.copy()
    ops = _backend(img.shape[2])
    on = ops.pack(img)
    dt = float(t[1] - t[0]) if t.size > 1 else 1.0
    stuck = (
        _stuck_mask(ops, on, stuck_frames_for(dt, cfg), release_frames_for(dt, cfg))
        if cfg.stuck
        else np.zeros_like(on)
    )
    blank = np.zeros_like(on[0])
    a = _bridged(ops, on, stuck, cfg)
    from taxelkit.smart.cleaning_runs import clean_runs_if_worth  # it builds on this module

    out = clean_runs_if_worth(ops, a, a.shape[0], blank[None], blank[None], cfg)
    if out is None:
        out, _ = _clean(ops, a, blank, blank, cfg)
    return ops.unpack(out, img.shape[2])
