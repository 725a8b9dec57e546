"""Directions of the tracer's moves and their histogram over m sectors (paper 000, Section V.2).

Sector ``i`` (0-based; the paper's interval ``i + 1``) covers
``[2 pi i / m, 2 pi (i + 1) / m)`` of the direction, an angle measured
counter-clockwise from +x. See :mod:`taxelkit.memory.chain_code` for all
conventions.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_finite_array

__all__ = [
    "DEFAULT_SECTORS",
    "SECTOR_BOUNDARY_TOLERANCE",
    "ZERO_MOVE_TOLERANCE_MM",
    "directions_from_moves",
    "histogram_from_directions",
    "histogram_from_moves",
    "relative_frequency",
]

#: Number of angular sectors m (paper 000, Section VI.3).
DEFAULT_SECTORS = 12

#: Moves shorter than this have no direction and are dropped, mm.
ZERO_MOVE_TOLERANCE_MM = 1e-9

#: Directions closer than this fraction of a sector width below a sector
#: boundary count in the upper sector (absorbs floating-point rounding of
#: directions that lie exactly on a boundary), dimensionless.
SECTOR_BOUNDARY_TOLERANCE = 1e-9


def _check_count(name: str, value: object) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or int(value) < 1:
        raise InputError(f"{name} must be an integer >= 1, got {value!r}")
    return int(value)


def directions_from_moves(moves_mm: ArrayLike) -> NDArray[np.float64]:
    """Directions of the non-zero moves, rad in ``[0, 2 pi)`` from +x.

    Parameters
    ----------
    moves_mm : (K, 2) float, mm
        Piecewise moves ``dr`` (Eq. 7), one ``(dx, dy)`` per row.

    Returns
    -------
    (K',) float64, rad
        Counter-clockwise angle from +x of each move longer than
        :data:`ZERO_MOVE_TOLERANCE_MM`; ``K' <= K``.

    Raises
    ------
    InputError
        If ``moves_mm`` is not a finite ``(K, 2)`` array.
    """
    dr = _check_moves(moves_mm)
    keep = np.hypot(dr[:, 0], dr[:, 1]) > ZERO_MOVE_TOLERANCE_MM
    angle: NDArray[np.float64] = np.mod(np.arctan2(dr[keep, 1], dr[keep, 0]), 2.0 * math.pi)
    return angle


def _check_moves(moves_mm: ArrayLike) -> NDArray[np.float64]:
    try:
        dr = np.asarray(moves_mm, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"moves_mm must be a numeric (K, 2) array, got {moves_mm!r}") from None
    if dr.ndim != 2 or dr.shape[1] != 2:
        raise InputError(f"moves_mm must have shape (K, 2), got shape {dr.shape}")
    check_finite_array("moves_mm", dr)
    return dr


def histogram_from_directions(
    directions_rad: ArrayLike, *, m: int = DEFAULT_SECTORS
) -> NDArray[np.int64]:
    """Count directions per sector (the histogram of paper 000, Fig. 5).

    Parameters
    ----------
    directions_rad : (K,) float, rad
        Move directions from +x, counter-clockwise; any finite value, taken
        modulo ``2 pi``.
    m : int
        Number of sectors.

    Returns
    -------
    (m,) int64
        Raw counts; sector ``i`` covers ``[2 pi i / m, 2 pi (i + 1) / m)``.

    Raises
    ------
    InputError
        If ``directions_rad`` is not a finite 1-D array or ``m < 1``.

    References
    ----------
    Paper 000, Section V.2 (histogram before Eq. 13).

    Examples
    --------
    >>> histogram_from_directions([0.1, 0.2, 3.3], m=4).tolist()
    [2, 0, 1, 0]
    """
    m_ = _check_count("m", m)
    try:
        theta = np.asarray(directions_rad, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(
            f"directions_rad must be a numeric (K,) array, got {directions_rad!r}"
        ) from None
    if theta.ndim != 1:
        raise InputError(f"directions_rad must have shape (K,), got shape {theta.shape}")
    check_finite_array("directions_rad", theta)
    position = np.mod(theta, 2.0 * math.pi) * (m_ / (2.0 * math.pi))
    sector = np.floor(position + SECTOR_BOUNDARY_TOLERANCE).astype(np.int64) % m_
    counts: NDArray[np.int64] = np.bincount(sector, minlength=m_).astype(np.int64)
    return counts


def histogram_from_moves(moves_mm: ArrayLike, *, m: int = DEFAULT_SECTORS) -> NDArray[np.int64]:
    """Count the directions of the non-zero moves per sector.

    Parameters
    ----------
    moves_mm : (K, 2) float, mm
        Piecewise moves ``dr``; zero-length ones are ignored.
    m : int
        Number of sectors.

    Returns
    -------
    (m,) int64
        Raw counts (see :func:`histogram_from_directions`).

    Raises
    ------
    InputError
        If ``moves_mm`` is not a finite ``(K, 2)`` array or ``m < 1``.

    Examples
    --------
    >>> histogram_from_moves([[3.0, 0.0], [0.0, 0.0], [0.0, -3.0]], m=4).tolist()
    [1, 0, 0, 1]
    """
    return histogram_from_directions(directions_from_moves(moves_mm), m=m)


def relative_frequency(counts: ArrayLike) -> NDArray[np.float64]:
    """Fraction of moves per sector, ``f(i) = counts[i] / sum(counts)``.

    Parameters
    ----------
    counts : (m,) int or float
        Non-negative counts with a positive sum.

    Returns
    -------
    (m,) float64
        Sums to 1.

    Raises
    ------
    InputError
        If ``counts`` is not a finite, non-negative 1-D array with a positive sum.
    """
    c = _check_counts(counts)
    total = float(c.sum())
    if total <= 0.0:
        raise InputError("counts must hold at least one move (sum > 0), got all zeros")
    out: NDArray[np.float64] = c / total
    return out


def _check_counts(counts: ArrayLike, m: int | None = None) -> NDArray[np.float64]:
    try:
        c = np.asarray(counts, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"counts must be a numeric (m,) array, got {counts!r}") from None
    if c.ndim != 1 or (m is not None and c.shape[0] != m):
        expected = "(m,)" if m is None else f"({m},)"
        raise InputError(f"counts must have shape {expected}, got shape {c.shape}")
    check_finite_array("counts", c)
    if np.any(c < 0):
        raise InputError(f"counts must be >= 0, got minimum {float(c.min())}")
    return c
