"""Rotation-invariant Associatron recall and its scores (paper 000, Section V, Eq. 10-12, 14).

A memory holds ``K`` named chain codes (:mod:`taxelkit.memory.chain_code`).
Recall of a query ``y`` (values in {-1, 0, +1}, 0 = unknown, Eq. 10) follows
the paper: every one of the ``m`` cyclic shifts of ``y`` (the contour rotated
by multiples of ``360 / m`` deg, Section V.2) is recalled as ``Z = Phi(h)``
(Eq. 12, Phi the ternary quantiser of Eq. 9, ``h`` the fields of the chosen
rule, :mod:`taxelkit.memory.recall_rules`) and compared with each stored
pattern by the correlation ``c`` of Eq. 14. The score of pattern ``k`` is the
best ``c`` over the shifts, and the recognised shape is the pattern with the
best score.

All shifts of all queries go through the rule in one batched matrix product
(in chunks of :data:`RECALL_CHUNK_QUERIES` queries to bound memory); there is
no Python loop over shifts or queries.

Ties (not covered by the paper) are common: when recalls converge to clean
stored patterns, several shifts or patterns reach the same ``c``, often 1.
They are broken by the *evidence* ``a = (1/N) sum_i x_i y_i`` - the agreement
between the stored pattern and the shifted query itself, where unknown
elements count 0 - and then by the lowest shift index and the lowest pattern
index. The primary score stays Eq. 14; :attr:`RecallResult.margin` is the gap
in ``c`` between the winner and the best other pattern, 0 when the win came
from a tie-break.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError
from taxelkit.memory.chain_code import DEFAULT_CHAIN_CODE, ChainCodeConfig
from taxelkit.memory.code_rotation import cyclic_shift_index
from taxelkit.memory.recall_rules import RecallOperator

__all__ = ["RECALL_CHUNK_QUERIES", "RecallResult", "correlation", "recall_with_operator"]

#: Queries recalled per batched matrix product (bounds the ``(chunk, m, N)``
#: float64 temporaries to a few MB for the paper's N = 48).
RECALL_CHUNK_QUERIES = 2048


def correlation(stored: ArrayLike, recalled: ArrayLike) -> NDArray[np.float64]:
    """Correlation ``c = (1/N) sum_i x_i Z_i`` between vectors (paper 000, Eq. 14).

    ``c = 1`` when all elements agree; for vectors of +/-1 it is -1 when all
    differ (the paper's text says "zero if all different", which holds only
    against an all-zero recall). Unknown (0) elements contribute 0.

    Parameters
    ----------
    stored : (..., N) int or float
        Stored vectors ``x``.
    recalled : (..., N) int or float
        Recalled vectors ``Z``; broadcast against ``stored``.

    Returns
    -------
    (...) float64
        Values in ``[-1, 1]``.

    Raises
    ------
    InputError
        If the last axes differ in length or are empty.

    References
    ----------
    Paper 000, Section VII.3, Eq. 14.

    Examples
    --------
    >>> float(correlation([1, -1, 1, 1], [1, -1, -1, 0]))
    0.25
    """
    x = np.asarray(stored, dtype=np.float64)
    z = np.asarray(recalled, dtype=np.float64)
    if x.ndim == 0 or z.ndim == 0 or x.shape[-1] != z.shape[-1] or x.shape[-1] == 0:
        raise InputError(
            f"stored and recalled must have the same non-empty last axis N, "
            f"got shapes {x.shape} and {z.shape}"
        )
    c: NDArray[np.float64] = np.einsum("...n,...n->...", x, z) / x.shape[-1]
    return c


@dataclass(frozen=True, eq=False)
class RecallResult:
    """Outcome of recalling ``Q`` queries against ``K`` stored patterns.

    Parameters
    ----------
    names : tuple of str
        The ``K`` stored names, in memory order.
    correlations : (Q, K) float64
        ``c_k`` (Eq. 14), the best over the ``m`` cyclic shifts of the query.
    best_shift : (Q, K) int64
        The shift ``s`` that gave ``c_k``: the query rotated counter-clockwise
        by ``s * 360 / m`` deg matches pattern ``k``, i.e. the query contour is
        pattern ``k``'s contour turned by about ``-s * 360 / m`` deg.
    evidence : (Q, K) float64
        Agreement ``(1/N) sum_i x_i y_i`` between pattern ``k`` and the query
        at ``best_shift`` (unknown elements count 0); the tie-breaker.
    recognised : tuple of str
        Name of the winning pattern per query.
    recognised_index : (Q,) int64
        Its index in ``names``.
    margin : (Q,) float64
        Winner's ``c`` minus the best other pattern's ``c`` (>= 0; 0 when the
        winner was chosen by a tie-break; ``inf`` with a single stored pattern).
    recalled : (Q, N) int8
        ``Z`` of the winning pattern's best shift, in {-1, 0, +1}; it is
        expressed in the stored (shifted-query) orientation.
    """

    names: tuple[str, ...]
    correlations: NDArray[np.float64]
    best_shift: NDArray[np.int64]
    evidence: NDArray[np.float64]
    recognised: tuple[str, ...]
    recognised_index: NDArray[np.int64]
    margin: NDArray[np.float64]
    recalled: NDArray[np.int8]


def _as_queries(queries: ArrayLike, n: int) -> NDArray[np.int8]:
    arr = np.asarray(queries)
    if arr.dtype.kind not in "biuf":
        try:
            arr = arr.astype(np.float64)
        except (TypeError, ValueError):
            raise InputError(
                f"queries must be a numeric (Q, {n}) array, got dtype {arr.dtype}"
            ) from None
    if arr.ndim == 1:
        arr = arr[np.newaxis, :]
    if arr.ndim != 2 or arr.shape[1] != n:
        raise InputError(f"queries must have shape ({n},) or (Q, {n}), got shape {arr.shape}")
    valid = (arr == 1) | (arr == 0) | (arr == -1)
    if not np.all(valid):
        raise InputError(f"queries must hold only -1, 0 and +1, got {arr[~valid][0]!r}")
    return arr.astype(np.int8)


def _phi(fields: NDArray[np.float64], epsilon: float) -> NDArray[np.int8]:
    """Ternary Phi of Eq. 9 (same values as :func:`ternary`), without per-call checks."""
    up = (fields > epsilon).view(np.int8)
    down = (fields < -epsilon).view(np.int8)
    out: NDArray[np.int8] = up - down
    return out


def recall_with_operator(
    operator: RecallOperator,
    patterns: NDArray[Any],
    queries: ArrayLike,
    *,
    names: Sequence[str],
    config: ChainCodeConfig = DEFAULT_CHAIN_CODE,
) -> RecallResult:
    """Recall queries at all ``m`` cyclic shifts and score them against the patterns.

    The pure function behind :meth:`AssociativeMemory.recall`. For the query
    batch ``Y`` the computation is ``Y[:, table]`` ``(Q, m, N)`` (all shifts by
    one gather) -> fields ``(Q, m, N)`` (one product with the rule's
    matrix) -> ``Z = Phi`` (Eq. 9) -> ``Z @ X.T / N`` ``(Q, m, K)`` -> best over
    ``m``; no loop over shifts or queries (only over chunks of
    :data:`RECALL_CHUNK_QUERIES` queries, to bound memory).

    Parameters
    ----------
    operator : RecallOperator
        Built by a rule of :data:`~taxelkit.memory.recall_rules.RECALL_RULES`
        from ``patterns``.
    patterns : (K, N) int
        Stored patterns, +/-1.
    queries : (Q, N) or (N,) int
        Values in {-1, 0, +1}; a single ``(N,)`` query gives ``Q = 1``.
    names : sequence of str
        ``K`` pattern names.
    config : ChainCodeConfig
        Gives ``m`` and ``l`` for the shifts.

    Returns
    -------
    RecallResult

    Raises
    ------
    InputError
        If the queries have the wrong shape or values.

    References
    ----------
    Paper 000, Eq. 12 (recall), Eq. 14 (correlation), Section V.2 (shifts).
    """
    x = np.asarray(patterns, dtype=np.float64)
    k, n = x.shape
    y = _as_queries(queries, n)
    q = y.shape[0]
    m = config.m
    table = cyclic_shift_index(config)  # (m, N)
    # Evidence sum_i x_k[i] y[table[s, i]] = sum_j x_k[inv[s, j]] y[j], inv[s] = table[-s]:
    # one product of the unshifted queries with the inversely shifted patterns.
    x_unshift = x[:, table[(-np.arange(m)) % m]].transpose(1, 0, 2).reshape(m * k, n)
    corr_n = np.empty((q, k), dtype=np.int64)
    evid_n = np.empty((q, k), dtype=np.int64)
    best_shift = np.empty((q, k), dtype=np.int64)
    recalled = np.empty((q, n), dtype=np.int8)
    winner = np.empty(q, dtype=np.int64)
    for start in range(0, q, RECALL_CHUNK_QUERIES):
        stop = min(start + RECALL_CHUNK_QUERIES, q)
        chunk = y[start:stop].astype(np.float64)  # (c, N)
        (
            corr_n[start:stop],
            evid_n[start:stop],
            best_shift[start:stop],
            winner[start:stop],
            recalled[start:stop],
        ) = _recall_chunk(operator, chunk, x, x_unshift, table)
    correlations = corr_n / n
    name_tuple = tuple(names)
    return RecallResult(
        names=name_tuple,
        correlations=correlations,
        best_shift=best_shift,
        evidence=evid_n / n,
        recognised=tuple(name_tuple[i] for i in winner),
        recognised_index=winner,
        margin=_winning_margin(correlations, winner),
        recalled=recalled,
    )


def _recall_chunk(
    operator: RecallOperator,
    chunk: NDArray[np.float64],
    x: NDArray[np.float64],
    x_unshift: NDArray[np.float64],
    table: NDArray[np.intp],
) -> tuple[
    NDArray[np.int64], NDArray[np.int64], NDArray[np.intp], NDArray[np.intp], NDArray[np.int8]
]:
    """Recall of a chunk of queries ``(c, N)`` against patterns ``x`` ``(K, N)``.

    Returns the correlation and evidence numerators ``(c, K)`` at each
    pattern's best shift, that shift ``(c, K)``, the winning pattern ``(c,)``
    and the recalled pattern at the winner's shift ``(c, N)``.
    """
    c, n = chunk.shape
    m, k = table.shape[0], x.shape[0]
    shifted = np.take(chunk, table, axis=1)  # (c, m, N): all shifts, one gather
    z = _phi(operator.fields(shifted), operator.epsilon)  # (c, m, N) int8
    # Integer numerators of Eq. 14 and of the evidence, exact in float64.
    cn = np.rint(z.reshape(-1, n).astype(np.float64) @ x.T).astype(np.int64)
    cn = cn.reshape(c, m, k)  # (c, m, K)
    an = np.rint(chunk @ x_unshift.T).astype(np.int64).reshape(c, m, k)
    # Lexicographic key: correlation first, evidence second (both in [-N, N]).
    key = (cn + n) * (2 * n + 1) + (an + n)
    shift = np.argmax(key, axis=1)  # (c, K): lowest shift on a full tie
    best_key = np.take_along_axis(key, shift[:, np.newaxis, :], axis=1)[:, 0, :]
    win = np.argmax(best_key, axis=1)  # (c,): lowest index on a full tie
    rows = np.arange(c)
    corr = np.take_along_axis(cn, shift[:, np.newaxis, :], axis=1)[:, 0, :]
    evid = np.take_along_axis(an, shift[:, np.newaxis, :], axis=1)[:, 0, :]
    return corr, evid, shift, win, z[rows, shift[rows, win], :]


def _winning_margin(
    correlations: NDArray[np.float64], winner: NDArray[np.int64]
) -> NDArray[np.float64]:
    """Winner's correlation minus the best other one, ``(Q,)``; ``inf`` with one pattern."""
    q, k = correlations.shape
    if k == 1:
        return np.full(q, np.inf)
    others = correlations.copy()
    others[np.arange(q), winner] = -np.inf
    margin: NDArray[np.float64] = correlations[np.arange(q), winner] - others.max(axis=1)
    return margin
