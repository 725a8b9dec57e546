"""Chain-symbolizing of a traced contour (paper 000, Section V.2, Eq. 13).

The edge tracer moves the sensor in piecewise steps ``dr`` (Eq. 7). This
module turns those moves into the Associatron's hyper-vector (Eq. 10):

1. each move's direction, an angle in ``[0, 2 pi)`` measured counter-clockwise
   from +x, falls in one of ``m`` equal sectors
   (:func:`~taxelkit.memory.direction_histogram.histogram_from_moves`);
2. the direction frequency ``f(i)`` of each sector is compared with ``l``
   thresholds ``d_j`` (Eq. 13), giving ``N = m * l`` elements of value +1 or -1
   (:func:`chain_code_from_histogram`).

Conventions (0-based in code, 1-based in the paper)
---------------------------------------------------
* Sector ``i`` (``0 <= i < m``) covers ``[2 pi i / m, 2 pi (i + 1) / m)``; it is
  the paper's interval ``i + 1``. A direction that lies within
  :data:`~taxelkit.memory.direction_histogram.SECTOR_BOUNDARY_TOLERANCE` of a
  sector width below a boundary counts in the upper sector, so that edges
  exactly on a boundary (0, 90, 180 deg ... as computed in floating point)
  always land in the same sector.
* Element ``i + m * j`` (level ``j``, ``0 <= j < l``) is the paper's element
  ``i + m (j - 1)`` with 1-based ``i`` and ``j``. ``code.reshape(l, m)`` gives
  a ``[level, sector]`` table.
* ``f(i)`` is the **relative** frequency: the fraction of the (non-zero) moves
  in sector ``i``. The paper says only "direction frequency"; a fraction makes
  the code independent of the contour's length and of how much of it has been
  traced, which partial recall needs. The raw counts are available from
  :func:`~taxelkit.memory.direction_histogram.histogram_from_moves` and
  :func:`~taxelkit.memory.direction_histogram.histogram_from_directions`.
* Zero-length moves (norm <=
  :data:`~taxelkit.memory.direction_histogram.ZERO_MOVE_TOLERANCE_MM`) have no
  direction and are ignored.
* Rotation: a contour rotated counter-clockwise by ``s * 360 / m`` deg moves
  every direction ``s`` sectors up, which cyclically shifts the ``m`` elements
  inside each of the ``l`` blocks by ``+s``: ``shifted[i + m j] =
  code[(i - s) mod m + m j]``
  (:func:`~taxelkit.memory.code_rotation.all_cyclic_shifts`). Translation changes
  no move, so the code is translation invariant by construction.

Unknown elements
----------------
Eq. 13 uses +1 and -1 only; the faithful path here does exactly that. The
Associatron also accepts 0 = unknown (Eq. 10).
:func:`~taxelkit.memory.partial_code.partial_chain_code_from_histogram` marks as
0 the elements that a *partial* trace cannot decide yet; see its docstring for
the rule.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError
from taxelkit.memory.direction_histogram import (
    DEFAULT_SECTORS,
    _check_count,
    _check_counts,
    histogram_from_directions,
    histogram_from_moves,
    relative_frequency,
)

__all__ = [
    "DEFAULT_CHAIN_CODE",
    "DEFAULT_LEVELS",
    "ChainCodeConfig",
    "chain_code_from_directions",
    "chain_code_from_histogram",
    "chain_code_from_moves",
    "rounding_thresholds",
]

#: Number of threshold levels l (paper 000, Section VI.3); N = m * l = 48.
DEFAULT_LEVELS = 4


def rounding_thresholds(m: int, l: int) -> tuple[float, ...]:  # noqa: E741 (paper symbol)
    """Default thresholds ``d_j = (j - 1/2) / m`` for ``j = 1 .. l``.

    The paper does not give the thresholds ``d_j`` of Eq. 13. This choice
    makes level ``j`` (1-based) read "sector ``i`` holds at least ``j / m`` of
    the contour", with the boundary halfway between neighbouring multiples of
    ``1 / m``; the ``l`` levels are then a thermometer code of
    ``round(m * f(i))`` capped at ``l``.

    For the paper's ``m = 12, l = 4`` this gives ``(1/24, 3/24, 5/24, 7/24) =
    (0.042, 0.125, 0.208, 0.292)``, the midpoints between the fractions a
    sector receives from the five paper shapes traced in full:

    ======== ============================ =====================
    shape    sectors hit (edge directions) fraction per sector
    ======== ============================ =====================
    circle   12 (all directions)          1/12 = 0.083
    hexagon  6                            1/6  = 0.167
    star     5 (collinear edge pairs)     1/5  = 0.200
    square   4                            1/4  = 0.250
    triangle 3                            1/3  = 0.333
    ======== ============================ =====================

    ``d_1 = 1/24`` separates "direction present" from "absent" at half the
    circle's share, so the one or two corner-cutting moves of a polygon
    (about 1 % of ~90 moves each) stay below it; ``d_2 = 1/8`` separates the
    circle from the hexagon, ``d_3 = 5/24`` the hexagon from the square and
    ``d_4 = 7/24`` the square from the triangle. The star (a regular pentagram
    outline: its 10 edges lie pairwise on 5 chords, so its moves have 5
    directions 72 deg apart with about 0.19-0.2 each after corner moves) shares
    levels 1-2 with the hexagon; the two differ in how many sectors are hit
    (5 vs 6) and in their spacing (gaps of 2 or 3 sectors vs always 2). No
    threshold between 1/6 and 1/5 was chosen because it would leave the star
    within about 0.01 of a threshold.

    Parameters
    ----------
    m : int
        Number of sectors (>= 1).
    l : int
        Number of levels, ``1 <= l <= m``.

    Returns
    -------
    tuple of float
        ``l`` strictly increasing thresholds in ``(0, 1)``.

    Raises
    ------
    InputError
        If ``m`` or ``l`` is out of range.

    References
    ----------
    Paper 000, Section V.2, Eq. 13 (thresholds left open by the paper).

    Examples
    --------
    >>> [round(d, 4) for d in rounding_thresholds(12, 4)]
    [0.0417, 0.125, 0.2083, 0.2917]
    """
    m_ = _check_count("m", m)
    l_ = _check_count("l", l)
    if l_ > m_:
        raise InputError(
            f"l must be <= m for the default thresholds (d_l = (l - 1/2) / m <= 1), "
            f"got m={m_}, l={l_}; pass thresholds explicitly"
        )
    return tuple((j - 0.5) / m_ for j in range(1, l_ + 1))


@dataclass(frozen=True)
class ChainCodeConfig:
    """Parameters of chain-symbolizing (paper 000, Eq. 13).

    Parameters
    ----------
    m : int
        Number of angular sectors (paper: 12).
    l : int
        Number of threshold levels (paper: 4).
    thresholds : tuple of float
        ``d_1 < d_2 < ... < d_l``, each in ``(0, 1]``, compared with the
        relative direction frequency ``f(i)``. Empty (the default) means
        :func:`rounding_thresholds` ``(m, l)``; see there for why.

    Raises
    ------
    InputError
        If ``m`` or ``l`` is not a positive integer, or the thresholds are not
        ``l`` strictly increasing finite numbers in ``(0, 1]``.

    Examples
    --------
    >>> cfg = ChainCodeConfig()
    >>> cfg.n_elements, [round(d, 3) for d in cfg.thresholds]
    (48, [0.042, 0.125, 0.208, 0.292])
    """

    m: int = DEFAULT_SECTORS
    l: int = DEFAULT_LEVELS  # noqa: E741 (paper symbol)
    thresholds: tuple[float, ...] = ()

    def __post_init__(self) -> None:
        m = _check_count("m", self.m)
        l_ = _check_count("l", self.l)
        object.__setattr__(self, "m", m)
        object.__setattr__(self, "l", l_)
        if len(self.thresholds) == 0:
            object.__setattr__(self, "thresholds", rounding_thresholds(m, l_))
            return
        try:
            d = tuple(float(v) for v in self.thresholds)
        except (TypeError, ValueError):
            raise InputError(
                f"thresholds must be a sequence of numbers, got {self.thresholds!r}"
            ) from None
        if len(d) != l_:
            raise InputError(f"thresholds must have l={l_} values, got {len(d)}: {d}")
        for j, v in enumerate(d):
            if not (math.isfinite(v) and 0.0 < v <= 1.0):
                raise InputError(f"thresholds[{j}] must be in (0, 1], got {v!r}")
        if any(b <= a for a, b in itertools.pairwise(d)):
            raise InputError(f"thresholds must be strictly increasing, got {d}")
        object.__setattr__(self, "thresholds", d)

    @property
    def n_elements(self) -> int:
        """Length ``N = m * l`` of a chain code."""
        return self.m * self.l

    @property
    def sector_width_rad(self) -> float:
        """Angular width of one sector, rad."""
        return 2.0 * math.pi / self.m

    def thresholds_array(self) -> NDArray[np.float64]:
        """Thresholds as a ``(l,)`` float64 array."""
        return np.asarray(self.thresholds, dtype=np.float64)


#: The paper's configuration: m = 12, l = 4, thresholds from
#: :func:`rounding_thresholds`.
DEFAULT_CHAIN_CODE = ChainCodeConfig()


# ---------------------------------------------------------------- Eq. 13


def chain_code_from_histogram(
    counts: ArrayLike, *, config: ChainCodeConfig = DEFAULT_CHAIN_CODE
) -> NDArray[np.int8]:
    """Quantise a direction histogram to a chain code (paper 000, Eq. 13).

    ``x[i + m j] = +1 if f(i) >= d_j else -1`` with ``f`` the relative
    frequency (0-based ``i`` sector, ``j`` level).

    Parameters
    ----------
    counts : (m,) int or float
        Moves per sector (raw counts or fractions; only the proportions matter).
    config : ChainCodeConfig
        ``m``, ``l`` and the thresholds ``d_j``.

    Returns
    -------
    (N,) int8
        Values in {-1, +1}, ``N = m * l``.

    Raises
    ------
    InputError
        If ``counts`` does not have ``m`` finite, non-negative values with a
        positive sum.

    References
    ----------
    Paper 000, Section V.2, Eq. 13.

    Examples
    --------
    >>> cfg = ChainCodeConfig(m=4, l=2, thresholds=(0.2, 0.5))
    >>> chain_code_from_histogram([3, 1, 0, 6], config=cfg).tolist()
    [1, -1, -1, 1, -1, -1, -1, 1]
    """
    c = _check_counts(counts, config.m)
    f = relative_frequency(c)
    above = f[np.newaxis, :] >= config.thresholds_array()[:, np.newaxis]  # (l, m)
    code: NDArray[np.int8] = np.where(above, 1, -1).astype(np.int8).reshape(-1)
    return code


def chain_code_from_directions(
    directions_rad: ArrayLike, *, config: ChainCodeConfig = DEFAULT_CHAIN_CODE
) -> NDArray[np.int8]:
    """Chain code (Eq. 13) of a list of move directions.

    Parameters
    ----------
    directions_rad : (K,) float, rad
        Directions from +x, counter-clockwise, taken modulo ``2 pi``; at least one.
    config : ChainCodeConfig

    Returns
    -------
    (N,) int8
        Values in {-1, +1}.

    Raises
    ------
    InputError
        If there is no direction or the array is invalid.
    """
    return chain_code_from_histogram(
        histogram_from_directions(directions_rad, m=config.m), config=config
    )


def chain_code_from_moves(
    moves_mm: ArrayLike, *, config: ChainCodeConfig = DEFAULT_CHAIN_CODE
) -> NDArray[np.int8]:
    """Chain code (Eq. 13) of a traced contour's piecewise moves.

    Parameters
    ----------
    moves_mm : (K, 2) float, mm
        Moves ``dr`` of the tracer (Eq. 7); zero-length ones are ignored, at
        least one must remain.
    config : ChainCodeConfig

    Returns
    -------
    (N,) int8
        Values in {-1, +1}.

    Raises
    ------
    InputError
        If the array is invalid or holds no non-zero move.

    References
    ----------
    Paper 000, Section V.2, Eq. 13.
    """
    return chain_code_from_histogram(histogram_from_moves(moves_mm, m=config.m), config=config)
