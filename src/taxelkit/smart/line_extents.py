"""The drawn ends of a line contact along its axis (Level 1's extent, the pivot's yardstick).

:func:`line_extents` projects the taxels of each line frame on its axis: the
nearest and farthest, each widened by half a pitch, are the line's drawn ends
(:func:`~taxelkit.smart.track_geometry.drawn_half_mm` turns them into a
half-length). Arrays of 8 or 16 columns take a path on packed row words.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["line_extents"]

#: Frames per pass of :func:`line_extents` (its temporaries stay in the cache)...
_EXTENT_CHUNK = 1024
#: ... and of its path for rows of 8 or 16 taxels (only the rows with contact are kept).
_WORD_EXTENT_CHUNK = 8192


def _bit_ends() -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    """Lowest and highest set bit of every 16-bit word (0 for the word 0)."""
    word = np.arange(1 << 16)
    bits = ((word[:, None] >> np.arange(16)) & 1).astype(bool)
    low = np.argmax(bits, axis=1)
    high = 15 - np.argmax(bits[:, ::-1], axis=1)
    return low, np.where(word > 0, high, 0)


_LOW_BIT, _HIGH_BIT = _bit_ends()
#: Multiplier that gathers the low bits of eight bytes into the top byte.
_GATHER = np.uint64(0x0102040810204080)


def _row_words(on: NDArray[np.bool_]) -> NDArray[np.uint64]:
    """Each row of frames ``(m, rows, 8 or 16)`` as a word ``(m, rows)``, bit ``c`` column ``c``."""
    m, rows, cols = on.shape
    # eight 0/1 bytes to eight bits: the multiply puts byte k's bit at bit 56 + k
    eights = np.ascontiguousarray(on).view("<u8").reshape(m, rows, cols // 8)
    word: NDArray[np.uint64] = (eights[..., 0] * _GATHER) >> np.uint64(56)
    if cols == 16:
        word |= ((eights[..., 1] * _GATHER) >> np.uint64(56)) << np.uint64(8)
    return word


def _row_ends(
    on: NDArray[np.bool_],
) -> tuple[NDArray[np.intp], NDArray[np.intp], NDArray[np.bool_]]:
    """First and last contact column of each row, and whether it has one, ``(rows, m)`` each."""
    cols = on.shape[2]
    rows_first = on.transpose(1, 0, 2)
    first = np.argmax(rows_first, axis=2)
    last = cols - 1 - np.argmax(rows_first[:, :, ::-1], axis=2)
    has: NDArray[np.bool_] = np.any(rows_first, axis=2)
    return first, last, has


def line_extents(
    images: NDArray[np.bool_],
    centre_mm: NDArray[np.float64],
    orientation_deg: NDArray[np.float64],
    pitch_mm: float,
    *,
    row_words: NDArray[np.unsignedinteger[Any]] | None = None,
) -> NDArray[np.float64]:
    """Where each contact begins and ends along its own axis, mm from its centre.

    Parameters
    ----------
    images : (n, rows, cols) bool
        Contact images (non-empty).
    centre_mm, orientation_deg : (n, 2) and (n,) float
        Their centres (centred index coordinates times the pitch, as
        :func:`~taxelkit.smart.moments.image_stats`) and axes.
    pitch_mm : float
    row_words : (n, rows) unsigned int, optional
        The same images packed one word per row, bit ``c`` column ``c`` (as
        :class:`~taxelkit.smart.packed_rows.PackedRows`), for arrays 8 or 16
        taxels wide: saves packing them again.

    Returns
    -------
    (n, 2) float, mm
        The lowest and highest projection of a contact taxel's centre on the
        axis, relative to the centre, widened by half a pitch: the ends of the
        line as drawn, whatever its width profile. (The second moment gives a
        tapering line, such as a cone's whose width falls to nothing at the
        apex, a shorter length and a centre shifted to its wide end.)
    """
    n, rows, cols = images.shape
    u = (np.arange(cols) - 0.5 * (cols - 1)) * pitch_mm
    v = (np.arange(rows) - 0.5 * (rows - 1)) * pitch_mm
    t = np.deg2rad(orientation_deg)
    cos, sin = np.cos(t), np.sin(t)
    out = np.empty((n, 2))
    if cols in (8, 16):  # a line crosses few rows: only those with contact are projected
        for a in range(0, n, _WORD_EXTENT_CHUNK):
            b = min(n, a + _WORD_EXTENT_CHUNK)
            word = _row_words(images[a:b]) if row_words is None else row_words[a:b]
            out[a:b] = _row_extents(word, centre_mm[a:b], cos[a:b], sin[a:b], u, v)
        out[:, 0] -= 0.5 * pitch_mm
        out[:, 1] += 0.5 * pitch_mm
        return out
    # A taxel's projection, (u - cx) cos + (v - cy) sin rounded step by step, is
    # monotonic in u along a row (rounding is monotonic): a row's extremes lie at
    # its first and last contact taxels, and are the same floats.
    for a in range(0, n, _EXTENT_CHUNK):  # chunks that stay in cache
        b = min(n, a + _EXTENT_CHUNK)
        first_col, last_col, row_on = _row_ends(images[a:b])  # (rows, m) each
        cx, cy, c, s = centre_mm[a:b, 0], centre_mm[a:b, 1], cos[a:b], sin[a:b]
        up = c >= 0.0  # the projection grows with u
        along_v = (v[:, None] - cy) * s
        low = (u[np.where(up, first_col, last_col)] - cx) * c + along_v
        high = (u[np.where(up, last_col, first_col)] - cx) * c + along_v
        out[a:b, 0] = np.where(row_on, low, np.inf).min(axis=0) - 0.5 * pitch_mm
        out[a:b, 1] = np.where(row_on, high, -np.inf).max(axis=0) + 0.5 * pitch_mm
    return out


def _row_extents(
    word: NDArray[np.unsignedinteger[Any]],
    centre_mm: NDArray[np.float64],
    cos: NDArray[np.float64],
    sin: NDArray[np.float64],
    u: NDArray[np.float64],
    v: NDArray[np.float64],
) -> NDArray[np.float64]:
    """The lowest and highest projection of :func:`line_extents` ``(m, 2)``, rows with contact.

    ``word`` ``(m, rows)``: each frame's rows as words (bit ``c`` column ``c``).
    The same expression on each row with contact as over all rows, the
    extremes taken per frame (exact): frames without contact get +-inf.
    """
    m, rows = word.shape
    flat = word.reshape(-1)
    at = np.flatnonzero(flat)  # frame by frame
    f = at // rows
    r = at - f * rows
    w = flat[at].astype(np.intp)
    first_col, last_col = _LOW_BIT.take(w), _HIGH_BIT.take(w)
    cx, cy = centre_mm[:, 0].take(f), centre_mm[:, 1].take(f)
    c, s = cos.take(f), sin.take(f)
    up = c >= 0.0  # the projection grows with u
    along_v = (v.take(r) - cy) * s
    low = (u.take(np.where(up, first_col, last_col)) - cx) * c + along_v
    high = (u.take(np.where(up, last_col, first_col)) - cx) * c + along_v
    out = np.empty((m, 2))
    out[:, 0], out[:, 1] = np.inf, -np.inf
    if f.size:
        new = np.empty(f.size, bool)
        new[0] = True
        np.not_equal(f[1:], f[:-1], out=new[1:])
        lead = np.flatnonzero(new)
        first = f[lead]
        out[first, 0] = np.minimum.reduceat(low, lead)
        out[first, 1] = np.maximum.reduceat(high, lead)
    return out
