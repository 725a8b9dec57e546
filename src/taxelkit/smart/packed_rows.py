"""Line extents from packed rows: Level 1's extent of a line without its bool image.

The image cleaning (:mod:`taxelkit.smart.cleaning`) works on frames packed
one unsigned word per row (bit ``c`` = column ``c``). For arrays of at most
:data:`MAX_TABLE_COLS` columns a row's first and last contact column come
from a table of every possible word, and only the rows in contact are
visited, so :func:`line_extents_from_rows` costs a fraction of
:func:`~taxelkit.smart.track_geometry.line_extents` on the bool images, with
the same arithmetic on the same floats (tested equal).
:func:`line_extents_of_images` packs bool images first (a fraction of the
cost) and falls back to ``line_extents`` for wider arrays.
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.smart.track_geometry import line_extents

__all__ = ["MAX_TABLE_COLS", "line_extents_from_rows", "line_extents_of_images", "pack_rows"]

#: Widest row looked up in a table (2^16 words).
MAX_TABLE_COLS = 16


@functools.lru_cache(maxsize=MAX_TABLE_COLS)
def _column_ends(cols: int) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """First and last set bit of every word of ``cols`` bits (0 for the word 0)."""
    word = np.arange(1 << cols)
    on = ((word[:, None] >> np.arange(cols)) & 1).astype(bool)
    first = np.argmax(on, axis=1)
    last = np.where(word > 0, cols - 1 - np.argmax(on[:, ::-1], axis=1), 0)
    return first, last


def line_extents_from_rows(
    words: NDArray[Any],
    cols: int,
    centre_mm: NDArray[np.float64],
    orientation_deg: NDArray[np.float64],
    pitch_mm: float,
) -> NDArray[np.float64]:
    """:func:`~taxelkit.smart.track_geometry.line_extents` of frames given as packed rows.

    Parameters
    ----------
    words : (n, rows) unsigned int
        Non-empty frames, one word per row, bit ``c`` = column ``c`` (no bit
        at or above ``cols``), as the cleaning packs them.
    cols : int
        Columns, 1 to :data:`MAX_TABLE_COLS`.
    centre_mm, orientation_deg : (n, 2) and (n,) float
        The frames' centres (mm) and axes (deg), as for ``line_extents``.
    pitch_mm : float

    Returns
    -------
    (n, 2) float, mm
        Lowest and highest projection of a contact taxel's centre on the
        axis, from the centre, widened by half a pitch: the floats of
        ``line_extents`` on the same frames.

    Raises
    ------
    InputError
        If ``words`` is not 2-D unsigned, ``cols`` is out of range or a frame is empty.
    """
    if words.ndim != 2 or words.dtype.kind != "u":
        raise InputError(f"words must be unsigned (n, rows), got {words.dtype} {words.shape}")
    if not 1 <= cols <= MAX_TABLE_COLS:
        raise InputError(f"cols must be in [1, {MAX_TABLE_COLS}], got {cols}")
    n, rows = words.shape
    out = np.empty((n, 2))
    if n == 0:
        return out
    first_of, last_of = _column_ends(cols)
    u = (np.arange(cols) - 0.5 * (cols - 1)) * pitch_mm
    v = (np.arange(rows) - 0.5 * (rows - 1)) * pitch_mm
    t = np.deg2rad(orientation_deg)
    cos, sin = np.cos(t), np.sin(t)
    f, r = np.nonzero(words)  # the rows in contact, frame by frame
    starts = np.flatnonzero(np.diff(f, prepend=-1))
    if starts.size != n:
        raise InputError("words must hold no empty frame")
    w = words[f, r].astype(np.intp)
    cx, cy, c, s = centre_mm[f, 0], centre_mm[f, 1], cos[f], sin[f]
    up = c >= 0.0  # the projection grows with u
    first, last = first_of[w], last_of[w]
    along_v = (v[r] - cy) * s
    low = (u[np.where(up, first, last)] - cx) * c + along_v
    high = (u[np.where(up, last, first)] - cx) * c + along_v
    out[:, 0] = np.minimum.reduceat(low, starts) - 0.5 * pitch_mm
    out[:, 1] = np.maximum.reduceat(high, starts) + 0.5 * pitch_mm
    return out


def pack_rows(images: NDArray[np.bool_]) -> NDArray[Any]:
    """Bool frames ``(n, rows, cols)``, up to 16 columns, one word a row (bit ``c``: column ``c``).

    Returns
    -------
    (n, rows) uint8 (up to 8 columns) or uint16
    """
    n, rows, cols = images.shape
    if not 1 <= cols <= MAX_TABLE_COLS:
        raise InputError(f"images must have 1 to {MAX_TABLE_COLS} columns, got {cols}")
    packed = np.packbits(images, axis=2, bitorder="little")  # (n, rows, 1 or 2) bytes
    if cols <= 8:
        return packed.reshape(n, rows)
    out: NDArray[Any] = np.ascontiguousarray(packed).view("<u2").reshape(n, rows)
    return out


def line_extents_of_images(
    images: NDArray[np.bool_],
    centre_mm: NDArray[np.float64],
    orientation_deg: NDArray[np.float64],
    pitch_mm: float,
) -> NDArray[np.float64]:
    """:func:`~taxelkit.smart.track_geometry.line_extents`, by packed rows where the array allows.

    Parameters
    ----------
    images : (n, rows, cols) bool
        Non-empty contact images.
    centre_mm, orientation_deg : (n, 2) and (n,) float
    pitch_mm : float

    Returns
    -------
    (n, 2) float, mm
        The floats of ``line_extents``.
    """
    if images.shape[2] > MAX_TABLE_COLS:
        return line_extents(images, centre_mm, orientation_deg, pitch_mm)
    words = pack_rows(images)
    return line_extents_from_rows(words, images.shape[2], centre_mm, orientation_deg, pitch_mm)
