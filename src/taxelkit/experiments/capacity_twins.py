"""Histogram twins in the ``capacity`` experiment: shapes chain-symbolizing cannot tell apart.

Two kinds of pairs, all traced by the real tracer:

named pairs (:data:`TWIN_PAIRS`)
    the square and the L-shape, the square and the cross (the same four
    directions in equal shares), the star and the pentagon (five directions
    72 deg apart). Each shape is stored from one canonical trace and queried
    from ``n_twin_trials`` traces at random poses and start points.
generator twins
    pairs of generated shapes whose stored chain codes are identical at the
    best rotation (the paper's 12 x 4 code, one sector phase), and near twins
    whose 24 x 8 codes (two phases) differ in at most 8 of 192 elements
    (:data:`GENERATOR_TWINS`).

A pair is *told apart* on a query when a memory holding just the two shapes
names the query's own shape alone (a tie is not told apart). Rates are given
for the order-aware code (tangent signature, template matching) and, for
contrast, for the chain code with template matching and with the paper's
Hebbian rule.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.experiments.capacity_rules import CAPACITY_RULES, prefix_moves
from taxelkit.experiments.capacity_traces import DIAMETER_MM, MAX_OFFSET_MM, TraceUnit
from taxelkit.memory.associatron import AssociativeMemory
from taxelkit.memory.code_rotation import all_cyclic_shifts
from taxelkit.memory.contour_recall import memorise_contours, prefix_codes
from taxelkit.memory.signature_memory import SignatureMemory
from taxelkit.memory.turning_signature import tangent_signature
from taxelkit.world.open_set_shapes import open_set_outline_mm
from taxelkit.world.relief import relief_shape

__all__ = [
    "GENERATOR_TWINS",
    "TWIN_PAIRS",
    "TWIN_SHAPES",
    "TwinScores",
    "score_twins",
    "twin_pairs",
    "twin_units",
]

#: Named histogram twins (stored shape, twin).
TWIN_PAIRS: tuple[tuple[str, str], ...] = (
    ("square", "l-shape"),
    ("square", "cross"),
    ("star", "pentagon"),
)
#: The named shapes traced, in a fixed order.
TWIN_SHAPES: tuple[str, ...] = ("square", "l-shape", "cross", "star", "pentagon")
#: Generated pairs scored: (label, rule whose code is compared, most differing
#: elements at the best rotation). Equal 12 x 4 codes are the paper's histogram
#: twins; the 24 x 8 code separates more, so pairs within 8 of its 192 elements
#: (4 %) are taken as near twins.
GENERATOR_TWINS: tuple[tuple[str, str, int], ...] = (
    ("12 x 4 codes equal", "hebbian", 0),
    ("24 x 8 codes within 8 elements", "matched", 8),
)
#: Rules scored on the twins: the order-aware code and two chain-code rules for contrast.
TWIN_RULES: tuple[str, ...] = ("signature", "matched", "hebbian")

_Traces = dict[tuple[str, int, int], tuple[NDArray[np.float64], bool]]


def _outline(name: str, rotation_deg: float, offset: NDArray[np.float64]) -> NDArray[np.float64]:
    where = (float(offset[0]), float(offset[1]))
    if name in ("square", "star"):
        relief = relief_shape(name, diameter_mm=DIAMETER_MM, rotation_deg=rotation_deg,
                              offset_mm=where)  # fmt: skip
        out: NDArray[np.float64] = relief.outline_mm()
        return out
    return open_set_outline_mm(name, diameter_mm=DIAMETER_MM, rotation_deg=rotation_deg,
                               offset_mm=where)  # fmt: skip


def twin_units(n_trials: int, seq: np.random.SeedSequence) -> list[TraceUnit]:
    """Trace units of the named twin shapes: one stored (trial -1) and ``n_trials`` queries each."""
    units = []
    for j, (name, child) in enumerate(zip(TWIN_SHAPES, seq.spawn(len(TWIN_SHAPES)), strict=True)):
        rng = np.random.default_rng(child)
        units.append(TraceUnit(("twin", j, -1), _outline(name, 0.0, np.zeros(2)), (0.0, 0.0),
                               (1.0, 0.0), int(rng.integers(2**63))))  # fmt: skip
        for t in range(n_trials):
            angle = float(rng.uniform(0.0, 360.0))
            off = rng.uniform(-MAX_OFFSET_MM, MAX_OFFSET_MM, 2)
            d = rng.normal(size=2)
            units.append(TraceUnit(("twin", j, t), _outline(name, angle, off),
                                   (float(off[0]), float(off[1])), (float(d[0]), float(d[1])),
                                   int(rng.integers(2**63))))  # fmt: skip
    return units


def _told_apart(
    rule: str,
    pair_stored: Sequence[NDArray[np.float64]],
    pair_queries: Sequence[Sequence[NDArray[np.float64]]],
    s: Sequence[float],
) -> NDArray[np.float64]:
    """``(S,)`` count of queries (of either shape) named right in the memory of the pair."""
    names = ("a", "b")
    spec = CAPACITY_RULES[rule]
    hits = np.zeros(len(s))
    if spec.code == "signature":
        mem = SignatureMemory.from_moves(names, list(pair_stored), rule=spec.rule)
        for truth, trials in zip(names, pair_queries, strict=True):
            sigs = [tangent_signature(prefix_moves(m, f), closed=False) for m in trials for f in s]
            got = np.array(mem.recall(sigs).recognised, dtype=object).reshape(len(trials), len(s))
            hits += (got == truth).sum(axis=0)
        return hits
    cmem: AssociativeMemory = memorise_contours(
        names, list(pair_stored), rule=spec.rule, phases=spec.phases, config=spec.config
    )
    for truth, trials in zip(names, pair_queries, strict=True):
        codes = np.concatenate([
            prefix_codes(m, cmem, s=s, unknown_for_partial=False, phases=spec.phases)
            for m in trials
        ])  # fmt: skip
        got = np.array(cmem.recall(codes).recognised, dtype=object).reshape(len(trials), len(s))
        hits += (got == truth).sum(axis=0)
    return hits


@dataclass(frozen=True, eq=False)
class TwinScores:
    """Told-apart rates of the twin pairs.

    Attributes
    ----------
    s : tuple of float
    named : dict of str to dict of str to (S,) float
        ``"A / B"`` -> rule -> fraction of the queries of A and B named right.
    generator_pairs : dict of str to list of (str, str)
        Label of :data:`GENERATOR_TWINS` -> the generated pairs it finds.
    generator : dict of str to dict of str to (S,) float
        Code -> rule -> fraction of the queries of those pairs named right.
    n_named_queries, n_generator_queries : dict of str to int
    """

    s: tuple[float, ...]
    named: dict[str, dict[str, NDArray[np.float64]]]
    generator_pairs: dict[str, list[tuple[str, str]]]
    generator: dict[str, dict[str, NDArray[np.float64]]]
    n_named_queries: dict[str, int]
    n_generator_queries: dict[str, int]

    def to_json(self) -> dict[str, Any]:
        """Rates per pair (or code) and rule, per s; the target check at s = 1."""

        def table(d: dict[str, NDArray[np.float64]]) -> dict[str, list[float]]:
            return {r: np.round(v, 4).tolist() for r, v in d.items()}

        sig_full = [v["signature"][-1] for v in (*self.named.values(), *self.generator.values())]
        return {
            "s": list(self.s),
            "named": {p: table(v) for p, v in self.named.items()},
            "named_queries": self.n_named_queries,
            "generator_pairs": {c: [list(p) for p in ps] for c, ps in self.generator_pairs.items()},
            "generator": {c: table(v) for c, v in self.generator.items()},
            "generator_queries": self.n_generator_queries,
            "target": {
                "told_apart": 0.95,
                "measured_min_full_contour": round(float(min(sig_full)), 4) if sig_full else None,
                "met": bool(sig_full) and bool(min(sig_full) >= 0.95),
            },
        }


def twin_pairs(
    names: tuple[str, ...], stored: Sequence[NDArray[np.float64]], rule: str, max_elements: int
) -> list[tuple[int, int]]:
    """Pairs whose stored chain codes differ in at most ``max_elements`` at the best rotation."""
    spec = CAPACITY_RULES[rule]
    codes = memorise_contours(names, list(stored), phases=spec.phases, config=spec.config).patterns
    shifted = all_cyclic_shifts(codes, config=spec.config)  # (K, m, N)
    pairs = []
    for a in range(len(names) - 1):  # one row of the distance matrix at a time
        d = (shifted[a][None, :, :] != codes[a + 1 :, None, :]).sum(axis=2).min(axis=1)
        pairs += [(a, a + 1 + int(b)) for b in np.flatnonzero(d <= max_elements)]
    return pairs


def score_twins(
    names: tuple[str, ...],
    stored: Sequence[NDArray[np.float64]],
    queries: Sequence[Sequence[NDArray[np.float64]]],
    traces: _Traces,
    s: Sequence[float],
) -> TwinScores:
    """Score the named and the generated twin pairs (see the module docs)."""
    n_twin = max(t for (kind, _, t) in traces if kind == "twin") + 1
    named: dict[str, dict[str, NDArray[np.float64]]] = {}
    n_named: dict[str, int] = {}
    for a, b in TWIN_PAIRS:
        ia, ib = TWIN_SHAPES.index(a), TWIN_SHAPES.index(b)
        pst = [traces[("twin", i, -1)][0] for i in (ia, ib)]
        pq = [[traces[("twin", i, t)][0] for t in range(n_twin)] for i in (ia, ib)]
        named[f"{a} / {b}"] = {r: _told_apart(r, pst, pq, s) / (2 * n_twin) for r in TWIN_RULES}
        n_named[f"{a} / {b}"] = 2 * n_twin
    gen_pairs: dict[str, list[tuple[str, str]]] = {}
    gen: dict[str, dict[str, NDArray[np.float64]]] = {}
    n_gen: dict[str, int] = {}
    for code, rule, within in GENERATOR_TWINS:
        pairs = twin_pairs(names, stored, rule, within)
        gen_pairs[code] = [(names[a], names[b]) for a, b in pairs]
        n_q = sum(len(queries[a]) + len(queries[b]) for a, b in pairs)
        n_gen[code] = n_q
        if not pairs:
            continue
        gen[code] = {
            r: sum(
                (_told_apart(r, [stored[a], stored[b]], [queries[a], queries[b]], s)
                 for a, b in pairs), np.zeros(len(s))
            ) / n_q
            for r in TWIN_RULES
        }  # fmt: skip
    return TwinScores(tuple(s), named, gen_pairs, gen, n_named, n_gen)
