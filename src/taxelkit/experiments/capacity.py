"""Experiment ``capacity``: recall accuracy against the number of stored shapes and s.

``n_shapes`` (200) distinct relief shapes come from
:func:`~taxelkit.world.random_shapes.generate_shapes` (random star-shaped
polygons and smooth curves, 90 mm circumscribed diameter, minimum pairwise
difference :data:`~taxelkit.world.random_shapes.MIN_SHAPE_DIFFERENCE`). Every
shape is traced by the real tracer:

* once in its canonical pose (rotation 0, centred, edge searched towards +x):
  the stored trace;
* ``n_trials`` times at a random rotation (0-360 deg), translation
  (+-:data:`MAX_OFFSET_MM`) and start point (edge searched in a random
  direction), each with its own sensor noise: the query traces.

The traces run as units on a local process pool, or on a Dask scheduler
(:func:`~taxelkit.experiments.work_units.run_units`, the path of the smart
sensor sweeps); everything after tracing is vectorised recall in-process.
Each trace is made once; the partial traces at each ``s`` are prefixes of
the one query trace, chosen after the fact. Their codes use only the moves
of the prefix (Eq. 13 of the part traced, or its open tangent signature),
never the contour's total length.

For each memory size ``K`` of :data:`CAPACITY_SIZES` the 200 shapes (in a
seeded random order) are cut into ``200 / K`` disjoint memories of ``K``
shapes; every query trace is recalled against the memory that holds its
shape, so each size is scored on all queries. A recall is correct when the
true shape alone is top-ranked; ties are "undecided" (never correct).

Rules compared on the same traces (:mod:`taxelkit.experiments.capacity_rules`):
the paper's Hebbian Associatron (12 x 4 chain code), the other chain-code
rules on the 24 x 8 code with two sector phases, the dense associative
memory, and the order-aware tangent signature with template matching and
with the dense associative memory. Histogram twins (pairs with equal chain
codes, among the generated shapes and the L-shape/square, cross/square,
pentagon/star pairs) are scored by :mod:`taxelkit.experiments.capacity_twins`.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.experiments.capacity_rules import (
    CAPACITY_RULES,
    RuleScores,
    partition_memories,
    score_rules,
)
from taxelkit.experiments.capacity_traces import (
    DIAMETER_MM,
    MAX_OFFSET_MM,
    TraceUnit,
    trace_unit,
)
from taxelkit.experiments.capacity_twins import TwinScores, score_twins, twin_units
from taxelkit.experiments.work_units import run_units
from taxelkit.world.random_shapes import MIN_SHAPE_DIFFERENCE, GeneratedShape, generate_shapes

__all__ = [
    "CAPACITY_SIZES",
    "CAPACITY_S_GRID",
    "CapacityResult",
    "run_capacity",
]

#: Numbers of stored shapes.
CAPACITY_SIZES = (5, 20, 50, 100, 200)
#: Traced fractions evaluated (after the fact).
CAPACITY_S_GRID = (0.2, 0.4, 0.6, 0.8, 1.0)
#: Acceptance: the best associative rule at this many shapes and this s.
TARGET_SIZE, TARGET_S, TARGET_ACCURACY = 100, 0.6, 0.90


def _shape_units(
    shapes: tuple[GeneratedShape, ...], n_trials: int, seq: np.random.SeedSequence
) -> list[TraceUnit]:
    units = []
    for i, (shape, child) in enumerate(zip(shapes, seq.spawn(len(shapes)), strict=True)):
        entropy = int(child.generate_state(1)[0])
        units.append(
            TraceUnit(("gen", i, -1), shape.outline_mm(diameter_mm=DIAMETER_MM), (0.0, 0.0),
                      (1.0, 0.0), entropy)
        )  # fmt: skip
        rng = np.random.default_rng(child)
        for t in range(n_trials):
            angle = float(rng.uniform(0.0, 360.0))
            off = rng.uniform(-MAX_OFFSET_MM, MAX_OFFSET_MM, 2)
            d = rng.normal(size=2)
            outline = shape.outline_mm(diameter_mm=DIAMETER_MM, rotation_deg=angle, offset_mm=off)
            units.append(
                TraceUnit(("gen", i, t), outline, (float(off[0]), float(off[1])),
                          (float(d[0]), float(d[1])), int(rng.integers(2**63)))
            )  # fmt: skip
    return units


@dataclass(frozen=True, eq=False)
class CapacityResult:
    """Accuracy of every rule against memory size and s, and the twin checks.

    Attributes
    ----------
    shape_names : tuple of str
        The generated shapes, generation order.
    sizes : tuple of int
    s : tuple of float
    n_trials : int
        Query traces per shape.
    rules : dict of str to RuleScores
        Per rule (:data:`~taxelkit.experiments.capacity_rules.CAPACITY_RULES`).
    closed : (n_shapes, n_trials + 1) bool
        Whether each trace closed (column 0 the stored one).
    twins : TwinScores
    seed : int
    """

    shape_names: tuple[str, ...]
    sizes: tuple[int, ...]
    s: tuple[float, ...]
    n_trials: int
    rules: dict[str, RuleScores]
    closed: NDArray[np.bool_]
    twins: TwinScores
    seed: int

    def best_associative(self, size: int, s: float) -> tuple[str, float] | None:
        """The best associative rule at ``size`` and ``s``, and its accuracy (None if none ran)."""
        ki, si = self.sizes.index(size), self.s.index(s)
        candidates = [r for r in self.rules.values() if r.spec.associative]
        if not candidates:
            return None
        best = max(candidates, key=lambda r: r.accuracy[ki, si])
        return best.spec.label, float(best.accuracy[ki, si])

    def to_json(self) -> dict[str, Any]:
        """Accuracy and undecided fractions per rule, size and s; twins; the target check."""
        target: dict[str, Any] = {"size": TARGET_SIZE, "s": TARGET_S, "accuracy": TARGET_ACCURACY}
        found = None
        if TARGET_SIZE in self.sizes and TARGET_S in self.s:
            found = self.best_associative(TARGET_SIZE, TARGET_S)
        if found is not None:
            label, acc = found
            target |= {"best_associative": label, "measured": round(acc, 4),
                       "met": bool(acc >= TARGET_ACCURACY)}  # fmt: skip
        return {
            "experiment": "capacity",
            "seed": self.seed,
            "n_shapes": len(self.shape_names),
            "kinds": {
                k: sum(n.startswith(f"gen-{k}-") for n in self.shape_names)
                for k in ("polygon", "curve")
            },
            "min_difference": MIN_SHAPE_DIFFERENCE,
            "sizes": list(self.sizes),
            "s": list(self.s),
            "n_trials_per_shape": self.n_trials,
            "n_queries": int(self.closed.shape[0] * self.n_trials),
            "closed_fraction": round(float(self.closed.mean()), 4),
            "rules": {name: r.to_json() for name, r in self.rules.items()},
            "target": target,
            "twins": self.twins.to_json(),
        }


def run_capacity(
    *,
    seed: int = 0,
    n_trials: int = 2,
    n_shapes: int = max(CAPACITY_SIZES),
    sizes: tuple[int, ...] = CAPACITY_SIZES,
    s: tuple[float, ...] = CAPACITY_S_GRID,
    rules: tuple[str, ...] | None = None,
    n_twin_trials: int = 10,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> CapacityResult:
    """Generate the shapes, trace them, and score every rule at every size and s.

    Parameters
    ----------
    seed : int
        Root seed (shapes, poses, sensor noise, memory partition).
    n_trials : int
        Query traces per shape (>= 1).
    n_shapes : int
        Shapes generated (>= the largest size).
    sizes : tuple of int
        Memory sizes; each must divide ``n_shapes``.
    s : tuple of float
        Traced fractions, in (0, 1].
    rules : tuple of str, optional
        Keys of :data:`~taxelkit.experiments.capacity_rules.CAPACITY_RULES`
        (default: all).
    n_twin_trials : int
        Query traces per named twin shape (L-shape, square, ...).
    workers : int, optional
        Local worker processes (default: the CPU count, at most 4; 1 in-process).
    scheduler : str, optional
        Dask scheduler address: trace there instead.
    progress : callable, optional
        ``progress(done, total)`` over traces.

    Raises
    ------
    InputError
        For sizes that do not divide ``n_shapes``, an unknown rule, or bad counts.
    """
    if int(n_trials) < 1 or int(n_twin_trials) < 1:
        raise InputError(
            f"n_trials and n_twin_trials must be >= 1, got {n_trials}, {n_twin_trials}"
        )
    bad = [k for k in sizes if k < 1 or n_shapes % k]
    if bad:
        raise InputError(f"sizes must divide n_shapes={n_shapes}, got {bad}")
    chosen = tuple(CAPACITY_RULES) if rules is None else tuple(rules)
    unknown = [r for r in chosen if r not in CAPACITY_RULES]
    if unknown:
        raise InputError(f"unknown rule(s) {unknown}; known: {', '.join(CAPACITY_RULES)}")
    shape_seq, trace_seq, part_seq, twin_seq = np.random.SeedSequence(seed).spawn(4)
    shapes = generate_shapes(n_shapes, rng=np.random.default_rng(shape_seq))
    units = _shape_units(shapes, int(n_trials), trace_seq) + twin_units(
        int(n_twin_trials), twin_seq
    )
    n_workers = min(4, os.cpu_count() or 1) if workers is None else max(1, int(workers))
    traces: list[tuple[NDArray[np.float64], bool] | None] = [None] * len(units)
    stream = run_units(trace_unit, units, workers=n_workers, scheduler=scheduler)
    for done, (i, res) in enumerate(stream, start=1):
        traces[i] = res
        if progress is not None:
            progress(done, len(units))
    by_key = {u.key: t for u, t in zip(units, traces, strict=True) if t is not None}
    stored = [by_key[("gen", i, -1)][0] for i in range(n_shapes)]
    queries = [[by_key[("gen", i, t)][0] for t in range(n_trials)] for i in range(n_shapes)]
    closed = np.array(
        [[by_key[("gen", i, t)][1] for t in range(-1, n_trials)] for i in range(n_shapes)]
    )
    names = tuple(sh.name for sh in shapes)
    groups = {k: partition_memories(n_shapes, k, np.random.default_rng(part_seq)) for k in sizes}
    scores = score_rules(chosen, names, stored, queries, groups, s)
    twins = score_twins(names, stored, queries, by_key, s)
    return CapacityResult(names, tuple(sizes), tuple(s), int(n_trials), scores, closed, twins, seed)
