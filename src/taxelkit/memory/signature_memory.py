"""A memory of tangent signatures: order-aware recall of traced contours (beyond paper 000).

The stored patterns are the closed tangent signatures of
:mod:`taxelkit.memory.turning_signature`; a query is the signature of the
part traced so far. Both rules see every start of every stored contour and
every rotation (the modulus of the complex overlap), so recall is invariant
to where the trace began and how the specimen was turned.

Rules (:data:`SIGNATURE_RULES`)
-------------------------------
``"signature"`` (template matching)
    Score ``a_k = max_j |r_kj| / n_v``: the best agreement of the query with
    stored contour ``k`` over starts ``j`` (1 = the same tangents in the same
    order, up to one rotation). The nearest stored contour is recognised.
``"signature-dense"`` (dense associative memory)
    The stored patterns are all starts of all stored contours (the windows
    ``u_k^(j)`` aligned with the query); the energy is the exponential one of
    Demircigil et al. (2017) and Krotov & Hopfield (2016),
    ``E(xi) = -log sum_kj exp(beta |<xi, u_k^(j)>|)``, with ``beta = 1`` per
    sample (each sample that agrees multiplies a pattern's weight by ``e``,
    as one agreeing element does in the exponential DAM on +/-1 codes). One
    update (Ramsauer et al. 2021, "Hopfield networks is all you need")
    gives the weights ``w_kj = softmax(|r_kj|)`` and the retrieved state
    ``sum_kj w_kj exp(i arg r_kj) u_k^(j)``: the completed contour, its
    unseen rest included (:meth:`SignatureMemory.complete`). The score of
    contour ``k`` is its share of the weight, ``P_k = sum_j w_kj``: evidence
    summed over every start that fits, not the best one alone. With this
    ``beta`` the weights concentrate on one contour as soon as the cue
    separates it by a few samples, so the verdict is usually the nearest
    contour's; it differs when one contour fits at several starts (a
    symmetric shape) or two fit almost equally.

Ties: scores within ``tie_tolerance`` of the best are tied and the verdict is
"undecided between A and B"; no list order decides.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError
from taxelkit.memory.recall import verdict_text
from taxelkit.memory.turning_signature import (
    StoredSignatures,
    signature_overlaps,
    tangent_signature,
)

__all__ = [
    "SIGNATURE_CHUNK_QUERIES",
    "SIGNATURE_RULES",
    "SIGNATURE_TIE_TOLERANCE",
    "SignatureMemory",
    "SignatureRecall",
]

#: Recall rules of the signature memory.
SIGNATURE_RULES: tuple[str, ...] = ("signature", "signature-dense")
#: Scores (dimensionless, 0 to 1) within this of the best are tied; absorbs rounding only.
SIGNATURE_TIE_TOLERANCE = 1e-9
#: Queries per batched FFT product (bounds the ``(chunk, K, F)`` complex temporaries).
SIGNATURE_CHUNK_QUERIES = 16


@dataclass(frozen=True, eq=False)
class SignatureRecall:
    """Recall of ``Q`` query signatures against ``K`` stored ones.

    Attributes
    ----------
    names : tuple of str
        Stored names, memory order.
    scores : (Q, K) float64
        ``a_k`` (``"signature"``) or ``P_k`` (``"signature-dense"``), 0 to 1.
    start : (Q, K) int64
        Best start sample of the query on each stored contour.
    rotation_deg : (Q, K) float64
        Rotation of the query relative to each stored contour at that start, deg.
    recognised : tuple of (str or None)
        The single best name; None when tied (undecided).
    margin : (Q,) float64
        Best score minus the second best (``inf`` with one stored contour).
    tied : tuple of tuple of str
        Names within the tie tolerance of the best, sorted.
    """

    names: tuple[str, ...]
    scores: NDArray[np.float64]
    start: NDArray[np.int64]
    rotation_deg: NDArray[np.float64]
    recognised: tuple[str | None, ...]
    margin: NDArray[np.float64]
    tied: tuple[tuple[str, ...], ...]

    @property
    def verdicts(self) -> tuple[str, ...]:
        """The recognised name or ``"undecided between A and B"`` per query."""
        return tuple(verdict_text(t) for t in self.tied)


def _scores(
    overlaps: NDArray[np.complex128], samples: NDArray[np.int64], valid: NDArray[np.bool_], rule: str
) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.float64]]:
    """Scores, best starts and rotations ``(q, K)`` from overlaps ``(q, K, n_max)``."""
    size = np.abs(overlaps)  # (q, K, n_max), samples
    masked = np.where(valid[None], size, -np.inf)
    start = np.argmax(masked, axis=2)
    best = np.take_along_axis(overlaps, start[:, :, None], axis=2)[:, :, 0]
    rotation = np.rad2deg(np.angle(best))
    if rule == "signature":
        scores = np.abs(best) / samples[:, None]
    else:
        top = masked.max(axis=(1, 2), keepdims=True)
        w = np.where(valid[None], np.exp(masked - top), 0.0)
        scores = w.sum(axis=2) / w.sum(axis=(1, 2))[:, None]
    return scores, start.astype(np.int64), rotation


def _ties(
    names: tuple[str, ...], scores: NDArray[np.float64], tol: float
) -> tuple[tuple[str | None, ...], NDArray[np.float64], tuple[tuple[str, ...], ...]]:
    top = scores.max(axis=1, keepdims=True)
    is_tied = scores >= top - tol
    tied = tuple(tuple(sorted(names[j] for j in np.flatnonzero(row))) for row in is_tied)
    recognised = tuple(t[0] if len(t) == 1 else None for t in tied)
    if scores.shape[1] == 1:
        margin = np.full(scores.shape[0], np.inf)
    else:
        two = np.sort(scores, axis=1)[:, -2:]
        margin = two[:, 1] - two[:, 0]
    return recognised, margin, tied


@dataclass(frozen=True, eq=False)
class SignatureMemory:
    """Named closed tangent signatures and their recall rule.

    Parameters
    ----------
    names : tuple of str
        ``K`` unique names.
    signatures : tuple of (n_k,) complex128
        Closed signatures (:func:`~taxelkit.memory.turning_signature.tangent_signature`).
    rule : str
        One of :data:`SIGNATURE_RULES`.

    Raises
    ------
    InputError
        For duplicate or missing names, a count mismatch or an unknown rule.
    """

    names: tuple[str, ...]
    signatures: tuple[NDArray[np.complex128], ...]
    rule: str = "signature"

    def __post_init__(self) -> None:
        names = tuple(str(n) for n in self.names)
        if not names or len(set(names)) != len(names):
            raise InputError(f"names must be unique and at least one, got {names!r}")
        if len(self.signatures) != len(names):
            raise InputError(
                f"signatures must have one item per name ({len(names)}), got {len(self.signatures)}"
            )
        if self.rule not in SIGNATURE_RULES:
            raise InputError(f"rule must be one of {', '.join(SIGNATURE_RULES)}; got {self.rule!r}")
        object.__setattr__(self, "names", names)
        sigs = tuple(np.asarray(s, dtype=np.complex128).ravel() for s in self.signatures)
        object.__setattr__(self, "signatures", sigs)

    @classmethod
    def from_moves(
        cls, names: Sequence[str], moves_mm: Sequence[ArrayLike], *, rule: str = "signature"
    ) -> SignatureMemory:
        """Store closed traces given by their moves ``(K_i, 2)`` in mm."""
        if len(names) != len(moves_mm):
            raise InputError(f"names ({len(names)}) and moves ({len(moves_mm)}) must match")
        sigs = tuple(tangent_signature(m, closed=True) for m in moves_mm)
        return cls(tuple(names), sigs, rule)

    def with_rule(self, rule: str) -> SignatureMemory:
        """The same signatures under another rule."""
        return SignatureMemory(self.names, self.signatures, rule)

    def subset(self, indices: Sequence[int]) -> SignatureMemory:
        """A memory of the stored contours at ``indices`` (same rule)."""
        idx = list(indices)
        return SignatureMemory(
            tuple(self.names[i] for i in idx), tuple(self.signatures[i] for i in idx), self.rule
        )

    @cached_property
    def stored(self) -> StoredSignatures:
        """The signatures prepared for FFT matching (cached)."""
        return StoredSignatures(self.signatures)

    def recall(
        self, queries: Sequence[ArrayLike], *, tie_tolerance: float = SIGNATURE_TIE_TOLERANCE
    ) -> SignatureRecall:
        """Recognise open query signatures (parts traced so far).

        Parameters
        ----------
        queries : sequence of Q arrays (n_q,) complex
            :func:`~taxelkit.memory.turning_signature.tangent_signature` with
            ``closed=False`` of each part.
        tie_tolerance : float
            Scores within this of the best are tied (>= 0).

        Returns
        -------
        SignatureRecall

        Raises
        ------
        InputError
            For an empty or invalid query, or a negative tolerance.
        """
        tol = float(tie_tolerance)
        if not (np.isfinite(tol) and tol >= 0):
            raise InputError(f"tie_tolerance must be a finite number >= 0, got {tie_tolerance!r}")
        k = len(self.names)
        q = len(queries)
        scores = np.empty((q, k))
        start = np.empty((q, k), dtype=np.int64)
        rotation = np.empty((q, k))
        for lo in range(0, q, SIGNATURE_CHUNK_QUERIES):  # chunks bound memory only
            hi = min(lo + SIGNATURE_CHUNK_QUERIES, q)
            r, n = signature_overlaps(self.stored, queries[lo:hi])
            scores[lo:hi], start[lo:hi], rotation[lo:hi] = _scores(
                r, n, self.stored.valid_start, self.rule
            )
        recognised, margin, tied = _ties(self.names, scores, tol)
        return SignatureRecall(self.names, scores, start, rotation, recognised, margin, tied)

    def recall_moves(self, moves_mm: Sequence[ArrayLike]) -> SignatureRecall:
        """Recall parts of traces given by their moves (each encoded with ``closed=False``)."""
        return self.recall([tangent_signature(m, closed=False) for m in moves_mm])

    def complete(self, query: ArrayLike, n_samples: int) -> NDArray[np.complex128]:
        """The dense memory's one-step retrieval: the query continued for ``n_samples``.

        ``sum_kj w_kj exp(i arg r_kj) u_k[(j + t) mod n_k]`` for ``t <
        n_samples`` with ``w = softmax(|r|)`` over every start of every stored
        contour (``beta`` = 1 per sample, see the module docs). Beyond the cue
        this is the memory's prediction of the rest of the contour, in the
        query's own frame.

        Parameters
        ----------
        query : (n_q,) complex
            Open signature of the part traced.
        n_samples : int
            Length of the retrieved signature (>= 1).

        Returns
        -------
        (n_samples,) complex128
        """
        if int(n_samples) < 1:
            raise InputError(f"n_samples must be >= 1, got {n_samples!r}")
        r, _ = signature_overlaps(self.stored, [query])
        size = np.where(self.stored.valid_start, np.abs(r[0]), -np.inf)
        w = np.exp(size - size.max())
        w /= w.sum()
        out = np.zeros(int(n_samples), dtype=np.complex128)
        t = np.arange(int(n_samples))
        for k, j in zip(*np.nonzero(w > 1e-12 * w.max()), strict=True):  # the few that matter
            u = self.signatures[k]
            out += w[k, j] * np.exp(1j * np.angle(r[0, k, j])) * u[(j + t) % u.size]
        return out
