"""Order-aware contour code: the tangent signature along the traced path (beyond paper 000).

Chain-symbolizing (Eq. 13) keeps only how often each direction occurs, so an
L-shape and a square, or a pentagon and the star, get the same code
(*histogram twins*). The tangent signature keeps the order of the directions
along the contour:

``z[j] = exp(i theta(t_j))``
    the unit tangent (as a complex number) of the traced path at arc length
    ``t_j = j * step``, ``step`` = :data:`SIGNATURE_STEP_MM` (the tracer's PTP
    section, paper 000 Sect. VI.3). The tangent at ``t`` is the chord from
    the path point at ``t - h`` to the point at ``t + h``
    (``h`` = :data:`SIGNATURE_HALF_CHORD_MM`), which averages out the
    tracer's small sideways corrections ``de`` (Eq. 7).

A stored contour is a closed trace: its samples are taken at ``L / n`` with
``n = round(L / step)`` so that the sequence is cyclic (the chord wraps round
the start). A query is the part traced so far, sampled at exactly ``step`` mm
from its first point: nothing uses the length of the whole contour, which a
robot tracing an unknown contour does not know.

Matching (:func:`signature_overlaps`)
    For stored signature ``u`` (cyclic, ``n_u`` samples) and query ``v``
    (``n_v`` samples), the overlap at start ``j`` is
    ``r[j] = sum_t v[t] conj(u[(j + t) mod n_u])``. A rotation of the
    specimen by ``alpha`` multiplies every ``v[t]`` by ``exp(i alpha)``, so
    ``|r[j]|`` is rotation invariant (any angle, not only multiples of a
    sector) and ``arg r[j]`` is the rotation. Every start ``j`` is tried,
    so the start point does not matter either. All starts of all stored
    signatures come from one FFT product per query (no loop over starts or
    stored shapes). ``|r[j]| / n_v`` is 1 when the query's tangents, turned
    by one angle, equal the stored ones from start ``j`` on.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError

__all__ = [
    "SIGNATURE_HALF_CHORD_MM",
    "SIGNATURE_STEP_MM",
    "StoredSignatures",
    "overlaps_of_padded",
    "signature_overlaps",
    "tangent_signature",
]

#: Arc length between signature samples, mm (the PTP section of paper 000, Sect. VI.3).
SIGNATURE_STEP_MM = 3.0
#: Half the chord that gives the tangent at a sample, mm (one PTP section each way).
SIGNATURE_HALF_CHORD_MM = 3.0
#: Moves shorter than this carry no direction and are dropped, mm.
_ZERO_MOVE_MM = 1e-9


def _fast_length(n: int) -> int:
    """The smallest ``2^a 3^b 5^c >= n`` (a length pocketfft transforms fast)."""
    best = 1 << math.ceil(math.log2(n))
    p3 = 1
    while p3 < best:
        p5 = p3
        while p5 < best:
            p2 = p5
            while p2 < n:
                p2 *= 2
            best = min(best, p2)
            p5 *= 5
        p3 *= 3
    return best


def _path_points(moves_mm: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Path points ``(K + 1, 2)`` from the first point, and their arc lengths ``(K + 1,)``."""
    moves = np.asarray(moves_mm, dtype=np.float64)
    if moves.ndim != 2 or moves.shape[1] != 2 or not np.all(np.isfinite(moves)):
        raise InputError(f"moves_mm must be a finite (K, 2) array in mm, got shape {moves.shape}")
    length = np.hypot(moves[:, 0], moves[:, 1])
    moves = moves[length > _ZERO_MOVE_MM]
    if moves.shape[0] == 0:
        raise InputError("moves_mm must hold at least one non-zero move")
    points = np.vstack([np.zeros((1, 2)), np.cumsum(moves, axis=0)])
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(moves[:, 0], moves[:, 1]))])
    return points, arc


def _point_at(
    points: NDArray[np.float64], arc: NDArray[np.float64], t: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Path points ``(S, 2)`` at arc lengths ``t`` (clamped to the path)."""
    x = np.interp(t, arc, points[:, 0])
    y = np.interp(t, arc, points[:, 1])
    return np.column_stack([x, y])


def tangent_signature(
    moves_mm: ArrayLike,
    *,
    closed: bool,
    step_mm: float = SIGNATURE_STEP_MM,
    half_chord_mm: float = SIGNATURE_HALF_CHORD_MM,
) -> NDArray[np.complex128]:
    """Unit tangents along a traced path at equal arc-length steps.

    Parameters
    ----------
    moves_mm : (K, 2) float, mm
        The tracer's moves ``dr`` in order; zero-length ones are dropped.
    closed : bool
        True for a whole closed contour (a stored one): ``n = round(L /
        step_mm)`` samples ``L / n`` apart, the chord wrapping round the start.
        False for the part traced so far (a query): samples exactly
        ``step_mm`` apart from the first point, ``n = floor(L / step_mm) + 1``,
        chords clamped to the path's ends.
    step_mm : float, mm
        Sample spacing (> 0).
    half_chord_mm : float, mm
        Half length of the chord giving each tangent (> 0).

    Returns
    -------
    (n,) complex128
        ``exp(i theta_j)``, ``theta_j`` the tangent direction from +x,
        counter-clockwise; ``|z| = 1`` (a zero chord gives the move's own direction).

    Raises
    ------
    InputError
        For a malformed path or non-positive lengths.

    Examples
    --------
    A 30 mm square traced counter-clockwise has four runs of tangents, each
    a quarter turn from the one before:

    >>> sq = np.repeat([[3.0, 0], [0, 3.0], [-3.0, 0], [0, -3.0]], 10, axis=0)
    >>> z = tangent_signature(sq, closed=True)
    >>> np.round(np.angle(z[[5, 15, 25, 35]], deg=True)).tolist()
    [0.0, 90.0, 180.0, -90.0]
    """
    for name, value in (("step_mm", step_mm), ("half_chord_mm", half_chord_mm)):
        if not (math.isfinite(value) and value > 0):
            raise InputError(f"{name} must be a finite number > 0, got {value!r}")
    points, arc = _path_points(moves_mm)
    total = float(arc[-1])
    if closed:
        n = max(3, round(total / step_mm))
        t = np.arange(n) * (total / n)
        ahead = np.mod(t + half_chord_mm, total)
        behind = np.mod(t - half_chord_mm, total)
    else:
        n = math.floor(total / step_mm + 1e-9) + 1
        t = np.arange(n) * step_mm
        ahead = np.minimum(t + half_chord_mm, total)
        behind = np.maximum(t - half_chord_mm, 0.0)
    chord = _point_at(points, arc, ahead) - _point_at(points, arc, behind)
    z = chord[:, 0] + 1j * chord[:, 1]
    size = np.abs(z)
    # A chord can vanish only on a degenerate path; fall back on the move's direction there.
    move = np.clip(np.searchsorted(arc, t, side="right") - 1, 0, len(arc) - 2)
    own = np.diff(points, axis=0)[move]
    z = np.where(size > _ZERO_MOVE_MM, z, own[:, 0] + 1j * own[:, 1])
    out: NDArray[np.complex128] = (z / np.abs(z)).astype(np.complex128)
    return out


class StoredSignatures:
    """Closed signatures prepared for matching every start of each at once.

    Each signature is tiled periodically to ``fft_size`` samples and its
    conjugate transformed once, so that a query's overlaps with every start
    of every stored signature come from one FFT product.

    Parameters
    ----------
    signatures : sequence of (n_k,) complex
        Closed signatures (:func:`tangent_signature` with ``closed=True``).
    max_query_samples : int, optional
        Longest query matched in full (longer ones are cut to their first
        samples); default twice the longest stored signature.

    Raises
    ------
    InputError
        If there is no signature or one is empty or not finite.
    """

    def __init__(
        self, signatures: Sequence[ArrayLike], *, max_query_samples: int | None = None
    ) -> None:
        sigs = [np.asarray(s, dtype=np.complex128).ravel() for s in signatures]
        if not sigs or any(s.size == 0 or not np.all(np.isfinite(s)) for s in sigs):
            raise InputError("signatures must be one or more non-empty finite complex arrays")
        self.lengths: NDArray[np.int64] = np.array([s.size for s in sigs], dtype=np.int64)
        n_max = int(self.lengths.max())
        self.max_query_samples = 2 * n_max if max_query_samples is None else int(max_query_samples)
        if self.max_query_samples < 1:
            raise InputError(f"max_query_samples must be >= 1, got {max_query_samples!r}")
        self.fft_size = _fast_length(n_max + self.max_query_samples)
        tiled = np.stack([np.resize(s, self.fft_size) for s in sigs])  # periodic tiling
        self.spectra: NDArray[np.complex128] = np.fft.fft(np.conj(tiled), axis=-1)
        #: (K, n_max) the signatures, zero-padded.
        self.padded: NDArray[np.complex128] = tiled[:, :n_max] * (
            np.arange(n_max)[None, :] < self.lengths[:, None]
        )
        self.signatures = tuple(sigs)
        # (K, n_max) True at the valid starts j < n_k of each stored signature.
        self.valid_start: NDArray[np.bool_] = np.arange(n_max)[None, :] < self.lengths[:, None]

    @property
    def n_stored(self) -> int:
        """Number of stored signatures ``K``."""
        return len(self.signatures)


def signature_overlaps(
    stored: StoredSignatures, queries: Sequence[ArrayLike]
) -> tuple[NDArray[np.complex128], NDArray[np.int64]]:
    """Complex overlaps of each query with every start of every stored signature.

    Parameters
    ----------
    stored : StoredSignatures
    queries : sequence of Q arrays (n_q,) complex
        Open signatures of the parts traced (:func:`tangent_signature` with
        ``closed=False``); cut to ``stored.max_query_samples``.

    Returns
    -------
    overlaps : (Q, K, n_max) complex128
        ``r[q, k, j] = sum_t v_q[t] conj(u_k[(j + t) mod n_k])``; 0 at the
        invalid starts ``j >= n_k``.
    samples : (Q,) int64
        Samples of each query used (the normaliser of ``|r|``).

    Raises
    ------
    InputError
        If a query is empty or not finite.
    """
    f = stored.fft_size
    q = len(queries)
    padded = np.zeros((q, f), dtype=np.complex128)
    samples = np.empty(q, dtype=np.int64)
    for i, v in enumerate(queries):  # only copies each query into the padded block
        a = np.asarray(v, dtype=np.complex128).ravel()[: stored.max_query_samples]
        if a.size == 0 or not np.all(np.isfinite(a)):
            raise InputError(f"queries[{i}] must be a non-empty finite complex array")
        padded[i, : a.size] = a
        samples[i] = a.size
    return overlaps_of_padded(stored, padded), samples


def overlaps_of_padded(
    stored: StoredSignatures, padded: NDArray[np.complex128]
) -> NDArray[np.complex128]:
    """Overlaps ``(Q, K, n_max)`` of queries already zero-padded to ``(Q, fft_size)``."""
    n_max = int(stored.lengths.max())
    # r[j] = sum_t v[t] b[t + j], b = conj(u) tiled: cross-correlation by FFT.
    spec_v = np.conj(np.fft.fft(np.conj(padded), axis=-1))  # (Q, F)
    r = np.fft.ifft(spec_v[:, None, :] * stored.spectra[None, :, :], axis=-1)[:, :, :n_max]
    out: NDArray[np.complex128] = np.where(stored.valid_start[None, :, :], r, 0.0)
    return out
