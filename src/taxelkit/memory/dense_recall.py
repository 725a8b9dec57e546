"""Dense associative memory over ternary codes: the ``"dense"`` recall rule (beyond paper 000).

The Hebbian Associatron (Eq. 11-12) stores ``K`` patterns in one ``N x N``
matrix and holds only about ``0.14 N`` nearly orthogonal ones; chain codes of
different shapes are strongly correlated, so it collapses onto one stored
shape long before that. A dense associative memory (Krotov & Hopfield 2016;
Demircigil, Heusel, Loewe, Upgang & Vermet 2017) replaces the quadratic
energy by ``E(y) = -sum_k F(x_k . y)`` with ``F(o) = exp(o)``, ``o`` the raw
overlap in elements (each agreeing known element +1, each disagreeing one
-1, unknown ones 0). Its capacity grows exponentially with ``N``.

Update (Demircigil et al., Eq. 3): element ``i`` takes the sign that lowers
the energy, ``Z_i = Phi(h_i)`` with

``h_i = sum_k [F(o_k^(i+)) - F(o_k^(i-))]``,

``o_k^(i+-)`` the overlap with element ``i`` of ``y`` set to +-1. Since
``o_k^(i+-) = o_k - x_ki y_i +- x_ki``,

``h_i = 2 sinh(1) sum_k x_ki exp(o_k - x_ki y_i)
      = 2 sinh(1) [c_i (w X)_i - y_i sinh(1) sum_k w_k]``, ``w_k = exp(o_k)``,

``c_i = cosh(1)`` for a known element and 1 for an unknown one
(``exp(-x_ki y_i) = cosh 1 - x_ki y_i sinh 1`` when ``y_i = +-1``). All
elements are updated at once from one product with the patterns
(``(P, N) @ (N, K)``, then ``(P, K) @ (K, N)``), for every query and every
cyclic shift in one batch; the weights are computed relative to the largest
overlap of each input (a common factor, which Phi ignores). One update is
made (a synchronous step; the cue's own overlap with the stored pattern
dominates after it). With ``F = exp`` there is no free parameter: the
weight of a pattern grows by ``e^2`` per element it agrees on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = ["DENSE_FIELD_TOLERANCE", "DenseRecall"]

#: Dead zone of Phi for the dense rule (fields are O(1) after the common factor).
DENSE_FIELD_TOLERANCE = 1e-9

_COSH1 = math.cosh(1.0)
_SINH1 = math.sinh(1.0)


@dataclass(frozen=True, eq=False)
class DenseRecall:
    """One update of the exponential dense associative memory.

    Parameters
    ----------
    patterns : (K, N) float64
        Stored patterns, +/-1.
    epsilon : float
        Dead zone of Phi.

    References
    ----------
    D. Krotov and J. J. Hopfield, "Dense associative memory for pattern
    recognition", NeurIPS 2016; M. Demircigil et al., "On a model of
    associative memory with huge storage capacity", J. Stat. Phys. 168 (2017).
    """

    patterns: NDArray[np.float64]
    epsilon: float = DENSE_FIELD_TOLERANCE

    def fields(self, inputs: NDArray[np.float64]) -> NDArray[np.float64]:
        """Fields ``h`` ``(..., N)`` for inputs ``(..., N)`` in {-1, 0, +1}."""
        x = self.patterns
        n = x.shape[1]
        y = inputs.reshape(-1, n)
        overlap = y @ x.T  # (P, K), elements
        w = np.exp(overlap - overlap.max(axis=1, keepdims=True))  # relative to the best: <= 1
        known = y != 0
        scale = np.where(known, _COSH1, 1.0)
        h = 2 * _SINH1 * (scale * (w @ x) - y * (_SINH1 * w.sum(axis=1, keepdims=True)))
        out: NDArray[np.float64] = h.reshape(inputs.shape)
        return out
