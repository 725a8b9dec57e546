"""Recall rules of the associative memory: the paper's Hebbian Associatron and improved rules.

Every rule turns the stored patterns ``X`` (``(K, N)``, values +/-1) into a
:class:`RecallOperator` whose :meth:`~RecallOperator.fields` maps input
vectors ``y`` (``(..., N)``, values in {-1, 0, +1}; 0 = unknown) to the fields
``h`` that the ternary quantiser Phi (Eq. 9) turns into the recalled vector
``Z = Phi(h, epsilon)``. The fields are computed for any leading batch shape,
so all queries and all their cyclic shifts go through one matrix product.

Rules (:data:`RECALL_RULES`):

``"hebbian"`` (faithful, paper 000 Eq. 11-12; Nakano 1972)
    ``M = sum_k x_k^T x_k`` (diagonal kept), ``h = Phi(M) y`` with
    ``epsilon = 0``. With the five paper shapes the patterns share many -1
    elements, so ``Phi(M)`` is dominated by that common part and recalls are
    pulled towards one shape: on ideal full contours the square, triangle and
    star are all recognised as the hexagon (2 of 5 shapes right).

``"zero_mean"`` (covariance rule; Sejnowski 1977, Amit, Gutfreund & Sompolinsky 1987)
    Store the deviations from the mean pattern ``mu``: ``W = sum_k (x_k -
    mu)^T (x_k - mu)``; ``h = W (y - |y| mu)`` (known elements are centred,
    unknown ones stay 0, which now means "at the mean"). ``sign(x - mu) = x``
    wherever ``|mu| < 1``, so ``Phi(h)`` recalls ``x`` directly; where every
    stored pattern has the same value (``|mu| = 1``) the row of ``W`` is zero
    and the shared value is returned through a bias. ``W`` is not quantised:
    ``Phi(W)`` throws away the magnitudes that separate strongly correlated
    patterns (80 % instead of 100 % on full contours of the five shapes).

``"projection"`` (pseudo-inverse rule; Personnaz, Guyon & Dreyfus 1985, Kanter & Sompolinsky 1987)
    ``W = X^+ X``, the orthogonal projector onto the span of the stored
    patterns; ``h = W y``. Every stored pattern is a fixed point however
    correlated the (linearly independent) patterns are; the Hebbian rule needs
    them nearly orthogonal, as the paper itself notes after Eq. 11. ``W`` is real-valued and not
    quantised (``Phi(W)`` would destroy the projection).

``"masked_projection"`` (projection restricted to the known elements)
    For each input, fit the stored patterns by least squares on the known
    (non-zero) elements only, ``a = argmin || P (X^T a - y) ||`` with ``P`` the
    mask of known elements, and recall ``h = X^T a``. With no unknown element
    this equals ``"projection"``; with many unknowns it stops the zeros from
    being read as a value (``"projection"`` fits them as if 0 were observed,
    a value no stored pattern has). It needs a ``K x K`` solve per input and shift
    (batched, no Python loop), so it is slower than the single-matrix rules.

``"matched"`` (template matching; the identity memory)
    ``h = y``: no association between elements, so ``Z = Phi(y)`` and Eq. 14
    becomes the agreement of each stored pattern with the query on its known
    elements, best over the m rotations (a matched filter, or nearest stored
    code in Hamming distance over the known elements). On partial traces the
    associative rules can recall a vector unrelated to every stored pattern
    (all correlations negative); matching the evidence directly cannot, and it
    is the most reliable rule on partial contours in ``recall-vs-s``.

``"dense"`` (dense associative memory; Krotov & Hopfield 2016, Demircigil et al. 2017)
    Energy ``-sum_k exp(x_k . y)`` instead of the Hebbian quadratic one; one
    update recalls the stored pattern whose overlap with the cue is largest
    by a margin of a few elements, however many patterns are stored and
    however correlated they are (:mod:`taxelkit.memory.dense_recall`). An
    associative rule: ``Z`` is a completed stored pattern, not the cue.
    Because nearly every cyclic shift of a cue recalls *some* stored pattern
    exactly, several patterns reach ``c = 1`` over the shifts; they are then
    ranked by the evidence (:mod:`taxelkit.memory.recall`), so in practice
    the verdicts are those of ``"matched"`` (``capacity`` measures both).

Every real-valued rule uses :data:`FIELD_TOLERANCE` as ``epsilon`` so that
fields that are zero in exact arithmetic give 0, not a random sign.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.memory.dense_recall import DenseRecall
from taxelkit.neuron.quantisers import ternary

__all__ = [
    "FAITHFUL_RULE",
    "FIELD_TOLERANCE",
    "MASKED_PROJECTION_RIDGE",
    "RECALL_RULES",
    "LinearRecall",
    "MaskedProjectionRecall",
    "RecallOperator",
    "RecallRuleSpec",
    "get_recall_rule",
    "hebbian_matrix",
]

#: Dead zone of Phi for the real-valued rules: fields within this of 0 give 0
#: (absorbs floating-point rounding of exact zeros; the fields are O(1) to O(N K)).
FIELD_TOLERANCE = 1e-9

#: Tikhonov term added to the masked Gram matrix of ``"masked_projection"``
#: (dimensionless; the matrix entries are sums of +/-1 over the known elements,
#: up to N in size). Keeps the solve defined when the known elements cannot
#: tell all stored patterns apart; the fit then takes the smallest coefficients.
MASKED_PROJECTION_RIDGE = 1e-6

#: Name of the paper's rule.
FAITHFUL_RULE = "hebbian"


class RecallOperator(Protocol):
    """Maps input vectors to the fields that Phi quantises into the recall ``Z``."""

    @property
    def epsilon(self) -> float:
        """Dead zone of Phi (Eq. 9) applied to the fields."""
        ...

    def fields(self, inputs: NDArray[np.float64]) -> NDArray[np.float64]:
        """Fields ``h`` for inputs ``(..., N)`` in {-1, 0, +1}; returns ``(..., N)``."""
        ...


@dataclass(frozen=True, eq=False)
class LinearRecall:
    """Affine recall ``h = (y - |y| * input_offset) @ weights.T + output_bias``.

    Parameters
    ----------
    weights : (N, N) float64
        Weight matrix (``Phi(M)`` for the Hebbian rule).
    input_offset : (N,) float64
        Value subtracted from each known input element (the mean pattern for
        ``"zero_mean"``, else 0); unknown (0) elements stay 0.
    output_bias : (N,) float64
        Added to the fields.
    epsilon : float
        Dead zone of Phi.
    """

    weights: NDArray[np.float64]
    input_offset: NDArray[np.float64]
    output_bias: NDArray[np.float64]
    epsilon: float

    def fields(self, inputs: NDArray[np.float64]) -> NDArray[np.float64]:
        """Fields for ``inputs`` ``(..., N)``: one matrix product for the whole batch."""
        y = inputs
        if np.any(self.input_offset):
            y = y - np.abs(y) * self.input_offset
        n = self.weights.shape[1]
        # One 2-D product (a stacked 3-D matmul would loop over the leading axes).
        h: NDArray[np.float64] = (y.reshape(-1, n) @ self.weights.T).reshape(y.shape)
        if np.any(self.output_bias):
            h += self.output_bias
        return h


@dataclass(frozen=True, eq=False)
class MaskedProjectionRecall:
    """Least-squares fit of the stored patterns on the known elements of each input.

    Parameters
    ----------
    patterns : (K, N) float64
        Stored patterns.
    epsilon : float
        Dead zone of Phi.
    """

    patterns: NDArray[np.float64]
    epsilon: float

    def fields(self, inputs: NDArray[np.float64]) -> NDArray[np.float64]:
        """Fields ``X^T a`` with ``a`` solving ``(X P X^T + ridge I) a = X y`` per input."""
        x = self.patterns
        k = x.shape[0]
        known = (inputs != 0).astype(np.float64)  # (..., N)
        # (..., K, K) Gram matrices of the patterns restricted to the known elements.
        gram = np.einsum("kn,...n,ln->...kl", x, known, x, optimize=True)
        gram += MASKED_PROJECTION_RIDGE * np.eye(k)
        rhs = inputs @ x.T  # (..., K)
        coeff = np.linalg.solve(gram, rhs[..., np.newaxis])[..., 0]
        h: NDArray[np.float64] = coeff @ x
        return h


def hebbian_matrix(patterns: NDArray[Any]) -> NDArray[np.int64]:
    """Associatron memory matrix ``M = sum_k x_k^T x_k`` (paper 000, Eq. 11).

    Parameters
    ----------
    patterns : (K, N) int
        Stored patterns (rows), values +/-1.

    Returns
    -------
    (N, N) int64
        Symmetric, diagonal kept (equal to ``K``).

    References
    ----------
    Paper 000, Section V.1, Eq. 11; K. Nakano, "Associatron - a model of
    associative memory", IEEE Trans. SMC 2(3), 380-388, 1972.
    """
    x = np.asarray(patterns, dtype=np.int64)
    m: NDArray[np.int64] = x.T @ x
    return m


def _hebbian(patterns: NDArray[np.float64]) -> RecallOperator:
    n = patterns.shape[1]
    w = ternary(hebbian_matrix(patterns.astype(np.int64)), 0.0).astype(np.float64)
    zero = np.zeros(n)
    return LinearRecall(weights=w, input_offset=zero, output_bias=zero, epsilon=0.0)


def _zero_mean(patterns: NDArray[np.float64]) -> RecallOperator:
    mean = patterns.mean(axis=0)
    centred = patterns - mean
    w = centred.T @ centred
    shared = np.isclose(np.abs(mean), 1.0)
    bias = np.where(shared, mean, 0.0)
    return LinearRecall(weights=w, input_offset=mean, output_bias=bias, epsilon=FIELD_TOLERANCE)


def _projection(patterns: NDArray[np.float64]) -> RecallOperator:
    n = patterns.shape[1]
    w = np.linalg.pinv(patterns) @ patterns
    zero = np.zeros(n)
    return LinearRecall(weights=w, input_offset=zero, output_bias=zero, epsilon=FIELD_TOLERANCE)


def _matched(patterns: NDArray[np.float64]) -> RecallOperator:
    n = patterns.shape[1]
    zero = np.zeros(n)
    return LinearRecall(weights=np.eye(n), input_offset=zero, output_bias=zero, epsilon=0.0)


def _masked_projection(patterns: NDArray[np.float64]) -> RecallOperator:
    return MaskedProjectionRecall(patterns=patterns.copy(), epsilon=FIELD_TOLERANCE)


def _dense(patterns: NDArray[np.float64]) -> RecallOperator:
    return DenseRecall(patterns=patterns.copy())


@dataclass(frozen=True)
class RecallRuleSpec:
    """A named recall rule.

    Parameters
    ----------
    name : str
        Registry key.
    build : callable
        ``build(patterns (K, N) float64) -> RecallOperator``.
    faithful : bool
        True for the paper's own rule.
    reference : str
        Where the rule comes from.
    """

    name: str
    build: Callable[[NDArray[np.float64]], RecallOperator]
    faithful: bool
    reference: str


#: Recall rules by name (read-only mapping). ``"hebbian"`` is the paper's.
RECALL_RULES: Mapping[str, RecallRuleSpec] = MappingProxyType(
    {
        "hebbian": RecallRuleSpec(
            "hebbian",
            _hebbian,
            True,
            "paper 000 Eq. 11-12; Nakano, IEEE Trans. SMC 2(3) 1972",
        ),
        "zero_mean": RecallRuleSpec(
            "zero_mean",
            _zero_mean,
            False,
            "covariance rule: Sejnowski, J. Math. Biol. 4 (1977); "
            "Amit, Gutfreund & Sompolinsky, Phys. Rev. A 35 (1987)",
        ),
        "projection": RecallRuleSpec(
            "projection",
            _projection,
            False,
            "Personnaz, Guyon & Dreyfus, J. Phys. Lett. 46 (1985); "
            "Kanter & Sompolinsky, Phys. Rev. A 35 (1987)",
        ),
        "masked_projection": RecallRuleSpec(
            "masked_projection",
            _masked_projection,
            False,
            "projection rule fitted on the known elements only (taxelkit)",
        ),
        "matched": RecallRuleSpec(
            "matched",
            _matched,
            False,
            "identity memory: template matching on the known elements (taxelkit)",
        ),
        "dense": RecallRuleSpec(
            "dense",
            _dense,
            False,
            "dense associative memory, F = exp: Krotov & Hopfield, NeurIPS 2016; "
            "Demircigil et al., J. Stat. Phys. 168 (2017)",
        ),
    }
)


def get_recall_rule(name: str) -> RecallRuleSpec:
    """Look up a recall rule by name.

    Parameters
    ----------
    name : str
        One of :data:`RECALL_RULES`.

    Returns
    -------
    RecallRuleSpec

    Raises
    ------
    InputError
        If the name is unknown; the message lists the known names.
    """
    try:
        return RECALL_RULES[name]
    except (KeyError, TypeError):
        known = ", ".join(sorted(RECALL_RULES))
        raise InputError(f"rule must be one of {known}; got {name!r}") from None
