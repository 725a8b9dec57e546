"""The rules the ``capacity`` experiment compares, and their scoring on traced moves.

Every rule sees the same traces. Chain-code rules store the Eq. 13 code of
the stored trace and recall the Eq. 13 code of the query's part traced so
far (relative frequencies of that part: no 0 = unknown element, since the
worst-case partial code of :mod:`taxelkit.memory.partial_code` needs the
contour's total length). Signature rules store the closed tangent signature
and recall the open signature of the part traced.

``masked_projection`` is left out: with no unknown element in any query it
is the ``projection`` rule exactly (see :mod:`taxelkit.memory.recall_rules`)
at the cost of a ``K x K`` solve per query and shift.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.experiments.paper000_common import IMPROVED_CHAIN_CODE
from taxelkit.memory.associatron import AssociativeMemory
from taxelkit.memory.chain_code import DEFAULT_CHAIN_CODE, ChainCodeConfig
from taxelkit.memory.contour_recall import memorise_contours, prefix_codes
from taxelkit.memory.signature_memory import SignatureMemory
from taxelkit.memory.turning_signature import tangent_signature

__all__ = [
    "CAPACITY_RULES",
    "CapacityRule",
    "RuleScores",
    "partition_memories",
    "prefix_moves",
    "score_rules",
]


@dataclass(frozen=True)
class CapacityRule:
    """A code and a recall rule, as compared in ``capacity``.

    Attributes
    ----------
    label : str
        Shown in the figure and the README.
    code : str
        ``"chain"`` (Eq. 13) or ``"signature"`` (order-aware).
    rule : str
        Recall rule of that code's memory.
    associative : bool
        True when the rule recalls a stored pattern by association (its
        output is a completed pattern); False for template matching.
    faithful : bool
        True for the paper's own rule and code.
    config : ChainCodeConfig
        Chain-code layout (chain codes only).
    phases : int
        Sector phases (chain codes only).
    beta_per_sample : float, optional
        ``beta`` of ``signature-dense`` (None: the default, ``1 + ln(K - 1)``).
    """

    label: str
    code: str
    rule: str
    associative: bool
    faithful: bool = False
    config: ChainCodeConfig = DEFAULT_CHAIN_CODE
    phases: int = 1
    beta_per_sample: float | None = None


def _chain(label: str, rule: str, associative: bool) -> CapacityRule:
    return CapacityRule(label, "chain", rule, associative, False, IMPROVED_CHAIN_CODE, 2)


#: Rules compared, by key.
CAPACITY_RULES: dict[str, CapacityRule] = {
    "hebbian": CapacityRule("Hebbian, 12 x 4 code (paper)", "chain", "hebbian", True, True),
    "zero_mean": _chain("zero-mean, 24 x 8 code", "zero_mean", True),
    "projection": _chain("projection, 24 x 8 code", "projection", True),
    "matched": _chain("template matching, 24 x 8 code", "matched", False),
    "dense": _chain("dense associative, 24 x 8 code", "dense", True),
    "signature": CapacityRule("template matching, signature", "signature", "signature", False),
    "signature-dense": CapacityRule(
        "dense associative, signature", "signature", "signature-dense", True
    ),
    "signature-dense-beta1": CapacityRule(
        "dense associative, signature, beta = 1",
        "signature",
        "signature-dense",
        True,
        beta_per_sample=1.0,
    ),
}


@dataclass(frozen=True, eq=False)
class RuleScores:
    """Fractions of queries per memory size and s.

    Attributes
    ----------
    spec : CapacityRule
    correct, undecided : (sizes, S) float64
        The true shape alone top-ranked; a tie at the top.
    """

    spec: CapacityRule
    correct: NDArray[np.float64]
    undecided: NDArray[np.float64]

    @property
    def accuracy(self) -> NDArray[np.float64]:
        """Alias of :attr:`correct`."""
        return self.correct

    def to_json(self) -> dict[str, Any]:
        """Label, code, kind and the two tables (rows: sizes, columns: s)."""
        return {
            "label": self.spec.label,
            "code": self.spec.code,
            "associative": self.spec.associative,
            "faithful": self.spec.faithful,
            "accuracy": np.round(self.correct, 4).tolist(),
            "undecided": np.round(self.undecided, 4).tolist(),
        }


def partition_memories(
    n_shapes: int, size: int, rng: np.random.Generator
) -> list[NDArray[np.intp]]:
    """Disjoint groups of ``size`` shape indices covering ``range(n_shapes)`` (seeded order)."""
    order = rng.permutation(n_shapes)
    return [np.sort(order[i : i + size]) for i in range(0, n_shapes, size)]


def prefix_moves(moves_mm: NDArray[np.float64], s: float) -> NDArray[np.float64]:
    """The moves up to the fraction ``s`` of the trace's path length (chosen after the fact).

    Same cut as :func:`~taxelkit.memory.contour_recall.prefix_codes`.
    """
    length = np.concatenate([[0.0], np.cumsum(np.hypot(moves_mm[:, 0], moves_mm[:, 1]))])
    k = max(1, int(np.searchsorted(length, s * length[-1] - 1e-9, side="left")))
    return moves_mm[:k]


def _score_chain(
    spec: CapacityRule,
    names: tuple[str, ...],
    stored: Sequence[NDArray[np.float64]],
    codes: NDArray[np.int8],
    groups: dict[int, list[NDArray[np.intp]]],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``codes`` ``(shapes, trials, S, N)`` recalled in each group's memory."""
    base = memorise_contours(names, list(stored), rule=spec.rule, phases=spec.phases,
                             config=spec.config)  # fmt: skip
    n_shapes, n_trials, n_s, n = codes.shape
    correct = np.zeros((len(groups), n_s))
    undecided = np.zeros((len(groups), n_s))
    for ki, (size, parts) in enumerate(groups.items()):
        for g in parts:
            mem = AssociativeMemory(tuple(names[i] for i in g), base.patterns[g], spec.config,
                                    spec.rule)  # fmt: skip
            res = mem.recall(codes[g].reshape(-1, n))
            index = res.recognised_index.reshape(len(g), n_trials, n_s)
            truth = np.arange(len(g))[:, None, None]
            correct[ki] += (index == truth).sum(axis=(0, 1))
            undecided[ki] += (index < 0).sum(axis=(0, 1))
        del size
    total = n_shapes * n_trials
    return correct / total, undecided / total


def _score_signature(
    spec: CapacityRule,
    memory: SignatureMemory,
    sigs: list[list[list[NDArray[np.complex128]]]],
    groups: dict[int, list[NDArray[np.intp]]],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``sigs[shape][trial][s]`` recalled in each group's memory."""
    n_shapes, n_trials, n_s = len(sigs), len(sigs[0]), len(sigs[0][0])
    correct = np.zeros((len(groups), n_s))
    undecided = np.zeros((len(groups), n_s))
    full = memory.with_rule(spec.rule, spec.beta_per_sample)
    for ki, parts in enumerate(groups.values()):
        for g in parts:
            mem = full.subset(g.tolist())
            flat = [sigs[i][t][j] for i in g for t in range(n_trials) for j in range(n_s)]
            res = mem.recall(flat)
            local = {n: k for k, n in enumerate(mem.names)}
            index = np.array([-1 if r is None else local[r] for r in res.recognised])
            index = index.reshape(len(g), n_trials, n_s)
            truth = np.arange(len(g))[:, None, None]
            correct[ki] += (index == truth).sum(axis=(0, 1))
            undecided[ki] += (index < 0).sum(axis=(0, 1))
    total = n_shapes * n_trials
    return correct / total, undecided / total


def score_rules(
    rules: Sequence[str],
    names: tuple[str, ...],
    stored: Sequence[NDArray[np.float64]],
    queries: Sequence[Sequence[NDArray[np.float64]]],
    groups: dict[int, list[NDArray[np.intp]]],
    s: Sequence[float],
) -> dict[str, RuleScores]:
    """Score each rule on the same traces.

    Parameters
    ----------
    rules : sequence of str
        Keys of :data:`CAPACITY_RULES`.
    names : tuple of str
        One per shape.
    stored : sequence of (K_i, 2) float, mm
        Moves of each shape's stored trace.
    queries : sequence (shapes) of sequence (trials) of (K, 2) float, mm
        Moves of the query traces.
    groups : dict of int to list of index arrays
        The memories of each size (:func:`partition_memories`).
    s : sequence of float
        Traced fractions.

    Returns
    -------
    dict of str to RuleScores
    """
    out: dict[str, RuleScores] = {}
    code_cache: dict[tuple[int, int, tuple[float, ...], int], NDArray[np.int8]] = {}
    sigs: list[list[list[NDArray[np.complex128]]]] | None = None
    sig_memory: SignatureMemory | None = None
    for key in rules:
        spec = CAPACITY_RULES[key]
        if spec.code == "chain":
            ck = (spec.config.m, spec.config.l, spec.config.thresholds, spec.phases)
            if ck not in code_cache:
                probe = memorise_contours(names[:1], [stored[0]], phases=spec.phases,
                                          config=spec.config)  # fmt: skip
                code_cache[ck] = np.stack([
                    np.stack([prefix_codes(m, probe, s=s, unknown_for_partial=False,
                                           phases=spec.phases) for m in trials])
                    for trials in queries
                ])  # fmt: skip
            correct, undecided = _score_chain(spec, names, stored, code_cache[ck], groups)
        else:
            if sigs is None or sig_memory is None:
                sig_memory = SignatureMemory.from_moves(names, list(stored))
                sigs = [[[tangent_signature(prefix_moves(m, f), closed=False) for f in s]
                         for m in trials] for trials in queries]  # fmt: skip
            correct, undecided = _score_signature(spec, sig_memory, sigs, groups)
        out[key] = RuleScores(spec, correct, undecided)
    return out
