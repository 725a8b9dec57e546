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
    The stored patterns are the ``K`` contours; as the paper tries every
    rotation of a chain code at recall, every start and rotation of each
    stored contour is tried, and contour ``k`` enters at its best one
    (``j_k``, ``phi_k = arg r_kj``). The energy is the exponential one of
    Demircigil et al. (2017) and Krotov & Hopfield (2016),
    ``E(xi) = -log sum_k exp(beta |<xi, u_k^(j_k)>|)``, ``beta`` per
    sample of overlap. One update (Ramsauer et al. 2021,
    "Hopfield networks is all you need") gives the retrieved state
    ``xi = sum_k w_k exp(i phi_k) u_k^(j_k)``, ``w = softmax(beta |r_k|)``:
    a completed contour, its unseen rest included
    (:meth:`SignatureMemory.complete`). The score of contour ``k`` is the
    overlap of the *retrieved* state (not the cue) with it, ``|<xi,
    u_k^(j_k)>| / n_v``, as Eq. 14 compares the recalled ``Z`` with each
    stored pattern. When the cue separates one contour by a few samples the
    weights concentrate on it and the verdict is the nearest contour's, as
    with template matching; the two differ when several contours fit almost
    equally. (Taking every start of every contour as a separate pattern
    instead blurs the retrieval: neighbouring starts of one contour are
    near copies, and the blurred polygon resembles a smooth curve.)

    ``beta`` (:func:`dense_beta`): the retrieved state is one contour, not a
    blend, when the weights of all ``K - 1`` others together stay below
    ``1/e`` of the best's while each trails it by one sample:
    ``(K - 1) exp(-beta) <= exp(-1)``, i.e. ``beta = 1 +
    ln(K - 1)`` per sample (1 for ``K <= 2``). This is Ramsauer et al.'s
    condition that ``beta`` times the separation exceed ``ln K``; a fixed
    ``beta = 1`` (each agreeing sample multiplies a weight by ``e``, as in
    the exponential DAM on +/-1 codes) blends the contours that fit a short
    cue and names the wrong one more often as ``K`` grows (``capacity``
    shows both).

Ties
----
Scores are overlaps in units of the query's ``n_v`` samples; two contours
whose overlaps differ by at most ``tie_samples`` samples (default
:data:`SIGNATURE_TIE_SAMPLES`, which absorbs the FFT's rounding only) are
tied, and the verdict is "undecided between A and B"; no list order decides.
Cues that fit several contours exactly (a straight edge on ideal polygons)
are undecided. On real traces the overlap of a short cue with the right
contour and with a wrong one often differ by less than one sample (the
tracer's direction noise costs the right one about as much as a different
shape does), yet the right one is usually ahead: calling every difference
below one sample a tie (``tie_samples=1``) leaves about half of the partial
traces at s = 0.6 undecided among 100 shapes, so the margin is reported and
the tolerance left to the caller.
"""

from __future__ import annotations

import math
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
    "SIGNATURE_TIE_SAMPLES",
    "SignatureMemory",
    "SignatureRecall",
    "dense_beta",
    "dense_weights",
]

#: Recall rules of the signature memory.
SIGNATURE_RULES: tuple[str, ...] = ("signature", "signature-dense")
#: Overlaps within this many samples of the best are tied (the tolerance on a
#: score is this over the query's sample count); absorbs the FFT's rounding.
SIGNATURE_TIE_SAMPLES = 1e-6
#: Queries per batched FFT product (bounds the ``(chunk, K, F)`` complex temporaries).
SIGNATURE_CHUNK_QUERIES = 4


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


def _aligned_windows(
    stored: StoredSignatures, start: NDArray[np.intp], n_samples: int
) -> NDArray[np.complex128]:
    """``u_k[(start[q, k] + t) mod n_k]`` for ``t < n_samples``: ``(q, K, n_samples)``."""
    t = np.arange(n_samples)
    idx = (start[:, :, None] + t) % stored.lengths[None, :, None]
    out: NDArray[np.complex128] = stored.padded[np.arange(stored.n_stored)[None, :, None], idx]
    return out


def dense_beta(n_stored: int) -> float:
    """Inverse temperature per sample of the dense rule: ``1 + ln(K - 1)`` (1 for K <= 2)."""
    return 1.0 + math.log(max(1, int(n_stored) - 1))


def dense_weights(best: NDArray[np.complex128], beta: float) -> NDArray[np.complex128]:
    """``w_k exp(i phi_k)``: softmax of ``beta |r_k|`` over the contours, with their rotations.

    ``best`` ``(q, K)`` holds each contour's overlap at its best start; ``beta``
    is per sample.
    """
    size = np.abs(best)
    w = np.exp(beta * (size - size.max(axis=1, keepdims=True)))
    w /= w.sum(axis=1, keepdims=True)
    out: NDArray[np.complex128] = w * np.where(size > 0, best / np.where(size > 0, size, 1), 0)
    return out


def _scores(
    stored: StoredSignatures, queries: Sequence[ArrayLike], rule: str, beta: float
) -> tuple[NDArray[np.float64], NDArray[np.int64], NDArray[np.float64], NDArray[np.int64]]:
    """Scores, best starts, rotations ``(q, K)`` and sample counts ``(q,)`` of a chunk."""
    r, samples = signature_overlaps(stored, queries)  # (q, K, n_max)
    masked = np.where(stored.valid_start[None], np.abs(r), -np.inf)
    start = np.argmax(masked, axis=2)
    best = np.take_along_axis(r, start[:, :, None], axis=2)[:, :, 0]  # (q, K)
    if rule == "signature-dense":
        # One update (Ramsauer et al.): the retrieved state on the query's window,
        # then its overlap with every stored contour at that contour's start.
        n_t = int(samples.max())
        win = _aligned_windows(stored, start, n_t)
        win = win * (np.arange(n_t)[None, None, :] < samples[:, None, None])
        retrieved = np.einsum("qk,qkt->qt", dense_weights(best, beta), win)
        scores = np.abs(np.einsum("qt,qkt->qk", retrieved, np.conj(win))) / samples[:, None]
    else:
        scores = np.abs(best) / samples[:, None]
    return scores, start.astype(np.int64), np.rad2deg(np.angle(best)), samples


def _ties(
    names: tuple[str, ...], scores: NDArray[np.float64], tol: NDArray[np.float64]
) -> tuple[tuple[str | None, ...], NDArray[np.float64], tuple[tuple[str, ...], ...]]:
    top = scores.max(axis=1, keepdims=True)
    is_tied = scores >= top - tol[:, None]
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
    beta_per_sample : float, optional
        ``beta`` of ``"signature-dense"`` (> 0); default :func:`dense_beta` of ``K``.

    Raises
    ------
    InputError
        For duplicate or missing names, a count mismatch, an unknown rule or a
        non-positive ``beta_per_sample``.
    """

    names: tuple[str, ...]
    signatures: tuple[NDArray[np.complex128], ...]
    rule: str = "signature"
    beta_per_sample: float | None = None

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
        beta = self.beta_per_sample
        if beta is not None and not (math.isfinite(beta) and beta > 0):
            raise InputError(f"beta_per_sample must be a finite number > 0, got {beta!r}")
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

    def with_rule(self, rule: str, beta_per_sample: float | None = None) -> SignatureMemory:
        """The same signatures under another rule (and ``beta``)."""
        return SignatureMemory(self.names, self.signatures, rule, beta_per_sample)

    def subset(self, indices: Sequence[int]) -> SignatureMemory:
        """A memory of the stored contours at ``indices`` (same rule and ``beta`` setting)."""
        idx = list(indices)
        return SignatureMemory(
            tuple(self.names[i] for i in idx),
            tuple(self.signatures[i] for i in idx),
            self.rule,
            self.beta_per_sample,
        )

    @property
    def beta(self) -> float:
        """``beta`` per sample of the dense rule (given, or :func:`dense_beta` of ``K``)."""
        if self.beta_per_sample is not None:
            return float(self.beta_per_sample)
        return dense_beta(len(self.names))

    @cached_property
    def stored(self) -> StoredSignatures:
        """The signatures prepared for FFT matching (cached)."""
        return StoredSignatures(self.signatures)

    def recall(
        self, queries: Sequence[ArrayLike], *, tie_samples: float = SIGNATURE_TIE_SAMPLES
    ) -> SignatureRecall:
        """Recognise open query signatures (parts traced so far).

        Parameters
        ----------
        queries : sequence of Q arrays (n_q,) complex
            :func:`~taxelkit.memory.turning_signature.tangent_signature` with
            ``closed=False`` of each part.
        tie_samples : float
            Overlaps within this many samples of the best are tied (>= 0).

        Returns
        -------
        SignatureRecall

        Raises
        ------
        InputError
            For an empty or invalid query, or a negative tolerance.
        """
        tol = float(tie_samples)
        if not (np.isfinite(tol) and tol >= 0):
            raise InputError(f"tie_samples must be a finite number >= 0, got {tie_samples!r}")
        k = len(self.names)
        q = len(queries)
        scores = np.empty((q, k))
        start = np.empty((q, k), dtype=np.int64)
        rotation = np.empty((q, k))
        samples = np.empty(q, dtype=np.int64)
        for lo in range(0, q, SIGNATURE_CHUNK_QUERIES):  # chunks bound memory only
            hi = min(lo + SIGNATURE_CHUNK_QUERIES, q)
            scores[lo:hi], start[lo:hi], rotation[lo:hi], samples[lo:hi] = _scores(
                self.stored, queries[lo:hi], self.rule, self.beta
            )
        recognised, margin, tied = _ties(self.names, scores, tol / samples)
        return SignatureRecall(self.names, scores, start, rotation, recognised, margin, tied)

    def recall_moves(self, moves_mm: Sequence[ArrayLike]) -> SignatureRecall:
        """Recall parts of traces given by their moves (each encoded with ``closed=False``)."""
        return self.recall([tangent_signature(m, closed=False) for m in moves_mm])

    def complete(self, query: ArrayLike, n_samples: int) -> NDArray[np.complex128]:
        """The dense memory's one-step retrieval: the query continued for ``n_samples``.

        ``sum_k w_k exp(i phi_k) u_k[(j_k + t) mod n_k]`` for ``t < n_samples``,
        ``j_k`` and ``phi_k`` contour ``k``'s best start and rotation, ``w =
        softmax(beta |r_k|)`` (see the module docs). Beyond the cue this is the
        memory's prediction of the rest of the contour, in the query's frame.

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
        masked = np.where(self.stored.valid_start[None], np.abs(r), -np.inf)
        start = np.argmax(masked, axis=2)
        best = np.take_along_axis(r, start[:, :, None], axis=2)[:, :, 0]
        win = _aligned_windows(self.stored, start, int(n_samples))
        out: NDArray[np.complex128] = np.einsum("qk,qkt->qt", dense_weights(best, self.beta), win)[
            0
        ]
        return out
