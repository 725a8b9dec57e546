"""Chain codes of partial traces with 0 = unknown elements (extension of paper 000, Eq. 13).

The Associatron accepts 0 = unknown input elements (Eq. 10). A trace that has
covered only part of a contour cannot decide every element of Eq. 13 yet;
:func:`partial_chain_code_from_histogram` sets exactly those to 0.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_in_range
from taxelkit.memory.chain_code import DEFAULT_CHAIN_CODE, ChainCodeConfig
from taxelkit.memory.direction_histogram import _check_counts, histogram_from_moves

__all__ = ["partial_chain_code_from_histogram", "partial_chain_code_from_moves"]


def partial_chain_code_from_histogram(
    counts: ArrayLike, *, coverage: float, config: ChainCodeConfig = DEFAULT_CHAIN_CODE
) -> NDArray[np.int8]:
    """Chain code of a partial trace with undecidable elements set to 0 = unknown.

    Extension of Eq. 13 (not in the paper). A trace that has covered only a
    fraction ``s`` (``coverage``) of the contour's moves shows relative
    frequencies ``f(i)``; the full trace's frequency ``F(i)`` is unknown but
    bounded. If the remaining ``1 - s`` of the moves all avoid sector ``i``,
    ``F(i) = s f(i)``; if they all fall in it, ``F(i) = s f(i) + 1 - s``. So

    * ``x = +1`` if ``s f(i) >= d_j`` (no continuation can bring ``F`` below
      ``d_j``),
    * ``x = -1`` if ``s f(i) + (1 - s) < d_j`` (no continuation can lift ``F``
      to ``d_j``),
    * ``x = 0`` (unknown) otherwise.

    Every non-zero element therefore equals the element of the full trace's
    Eq. 13 code, whatever the rest of the contour looks like: the rule
    is worst-case honest, not a guess. With ``coverage = 1`` there is no 0 and
    the result is exactly :func:`chain_code_from_histogram`. Note that the
    relative frequency of a partial trace over-states the sectors seen so far
    (half a square shows 0.5 per side, a full one 0.25), so the plain Eq. 13
    code of a partial trace has wrong +1 elements at the high levels as well as
    wrong -1 elements in the sectors not reached yet; this rule removes both.

    ``coverage`` is the fraction of the full trace's moves already made; with
    equal PTP steps it is the normalised arc length ``s = l / L`` of the
    paper's Fig. 9. A lower bound is safe (more zeros); an over-estimate can
    make elements wrong.

    Parameters
    ----------
    counts : (m,) int
        Moves per sector observed so far (raw counts). All zeros (nothing
        observed) gives an all-zero code.
    coverage : float
        Fraction ``s`` of the contour traced, in ``(0, 1]``.
    config : ChainCodeConfig

    Returns
    -------
    (N,) int8
        Values in {-1, 0, +1}.

    Raises
    ------
    InputError
        If ``counts`` is invalid or ``coverage`` is outside ``(0, 1]``.

    References
    ----------
    Paper 000, Eq. 10 (0 = unknown element) and Eq. 13.

    Examples
    --------
    Half of a square (two sides of equal length) in the paper's configuration:
    the two sides' sectors are +1 up to level 3 and unknown at level 4; all
    other elements are unknown because the unseen half could fill any sector.

    >>> counts = np.zeros(12, dtype=int)
    >>> counts[[0, 3]] = 10
    >>> partial_chain_code_from_histogram(counts, coverage=0.5).reshape(4, 12)[:, :4].tolist()
    [[1, 0, 0, 1], [1, 0, 0, 1], [1, 0, 0, 1], [0, 0, 0, 0]]
    """
    s = check_in_range("coverage", coverage, 0.0, 1.0)
    if s == 0.0:
        raise InputError("coverage must be in (0, 1], got 0")
    c = _check_counts(counts, config.m)
    total = float(c.sum())
    if total == 0.0:
        return np.zeros(config.n_elements, dtype=np.int8)
    low = s * (c / total)  # (m,) least possible final fraction
    high = low + (1.0 - s)  # (m,) largest possible final fraction
    d = config.thresholds_array()[:, np.newaxis]  # (l, 1)
    code = np.zeros((config.l, config.m), dtype=np.int8)
    code[low[np.newaxis, :] >= d] = 1
    code[high[np.newaxis, :] < d] = -1
    out: NDArray[np.int8] = code.reshape(-1)
    return out


def partial_chain_code_from_moves(
    moves_mm: ArrayLike, *, coverage: float, config: ChainCodeConfig = DEFAULT_CHAIN_CODE
) -> NDArray[np.int8]:
    """Chain code of a partial trace's moves, 0 where undecidable.

    See :func:`partial_chain_code_from_histogram` for the rule.

    Parameters
    ----------
    moves_mm : (K, 2) float, mm
        Moves made so far; zero-length ones are ignored.
    coverage : float
        Fraction of the full contour's moves these represent, in ``(0, 1]``.
    config : ChainCodeConfig

    Returns
    -------
    (N,) int8
        Values in {-1, 0, +1}.

    Raises
    ------
    InputError
        If an argument is invalid.
    """
    return partial_chain_code_from_histogram(
        histogram_from_moves(moves_mm, m=config.m), coverage=coverage, config=config
    )
