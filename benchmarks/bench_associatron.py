"""Throughput of rotation-invariant Associatron recall (paper 000, Eq. 12 and 14).

Recalls a seeded batch of random queries (values in {-1, 0, +1}) at all m = 12
cyclic shifts against the five paper shapes (circle, square, triangle, star,
hexagon; 90 mm, traced in 3 mm steps) and prints queries per second for

* ``batched``: :meth:`taxelkit.memory.AssociativeMemory.recall`, all shifts of
  all queries in one matrix product per chunk;
* ``per-shift batched`` (the baseline): a Python loop over the 12 shifts,
  all queries in one NumPy product per shift: the best a NumPy user would write;
* ``per-shift NumPy``: a Python loop over queries and shifts, NumPy inside
  (measured on a subset);
* ``naive Python``: loops over queries, shifts and elements, the way Eq. 12 and
  Eq. 14 read (measured on a smaller subset; linear rules only).

The loop baselines are checked against the batched result on their subset.
Usage: ``python benchmarks/bench_associatron.py [--queries 10000] [--repeat 3]``.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"  # one core, so the ratio compares algorithms, not threads

import argparse  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

from _record import add_record_option, record  # noqa: E402
from taxelkit.memory import (  # noqa: E402
    RECALL_RULES,
    AssociativeMemory,
    LinearRecall,
    cyclic_shift_index,
    memorise,
    ternary,
)
from taxelkit.world.relief import SHAPE_NAMES, relief_shape  # noqa: E402

STEP_MM = 3.0  # PTP section length of paper 000, Section VI.3
DIAMETER_MM = 90.0  # circumscribed diameter of the specimens, Section VI.3


def traced_moves(name: str) -> np.ndarray:
    """Moves of a walk along the shape's outline in 3 mm arc-length steps."""
    closed = relief_shape(name, diameter_mm=DIAMETER_MM).outline_mm()
    edges = np.diff(closed, axis=0)
    lengths = np.hypot(edges[:, 0], edges[:, 1])
    cumulative = np.concatenate([[0.0], np.cumsum(lengths)])
    arc = np.arange(0.0, cumulative[-1], STEP_MM)
    edge = np.minimum(np.searchsorted(cumulative, arc, side="right") - 1, len(lengths) - 1)
    points = closed[edge] + edges[edge] * ((arc - cumulative[edge]) / lengths[edge])[:, None]
    return np.diff(np.vstack([points, closed[:1]]), axis=0)


def best_of(fn: Callable[[], Any], repeat: int) -> float:
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return float(best)


def per_shift_numpy(mem: AssociativeMemory, queries: np.ndarray) -> np.ndarray:
    """Loop over queries and shifts; NumPy for each recall. Returns (Q, K) correlations."""
    m, n = mem.config.m, mem.config.n_elements
    x = mem.patterns.astype(np.float64)
    table = cyclic_shift_index(mem.config)
    out = np.empty((len(queries), len(x)))
    for q, y in enumerate(queries):
        best = np.full((len(x), 2), -np.inf)
        for s in range(m):
            ys = y[table[s]].astype(np.float64)
            z = ternary(mem.operator.fields(ys), mem.operator.epsilon).astype(np.float64)
            for k in range(len(x)):
                key = (float(x[k] @ z), float(x[k] @ ys))
                if key > tuple(best[k]):
                    best[k] = key
        out[q] = best[:, 0] / n
    return out


def per_shift_batched(mem: AssociativeMemory, queries: np.ndarray) -> np.ndarray:
    """Loop over the m shifts only; all queries in one product per shift (a NumPy user's best)."""
    m, n = mem.config.m, mem.config.n_elements
    x = mem.patterns.astype(np.float64)
    table = cyclic_shift_index(mem.config)
    best_c = np.full((len(queries), len(x)), -np.inf)
    best_a = np.full((len(queries), len(x)), -np.inf)
    for s in range(m):
        ys = queries[:, table[s]].astype(np.float64)
        z = ternary(mem.operator.fields(ys), mem.operator.epsilon).astype(np.float64)
        c, a = z @ x.T, ys @ x.T
        better = (c > best_c) | ((c == best_c) & (a > best_a))  # (c, a) compared in order
        best_c = np.where(better, c, best_c)
        best_a = np.where(better, a, best_a)
    out: np.ndarray = best_c / n
    return out


def naive_python(mem: AssociativeMemory, queries: np.ndarray) -> np.ndarray:
    """Loops over queries, shifts and elements (Eq. 12 and 14 as written)."""
    op = mem.operator
    assert isinstance(op, LinearRecall)
    m, n = mem.config.m, mem.config.n_elements
    w = op.weights.tolist()
    offset = op.input_offset.tolist()
    bias = op.output_bias.tolist()
    eps = op.epsilon
    x = mem.patterns.astype(int).tolist()
    out = np.empty((len(queries), len(x)))
    for q, y0 in enumerate(queries.tolist()):
        best: list[tuple[int, int]] = [(-(10**9), 0)] * len(x)
        for s in range(m):
            y = [y0[(e % m - s) % m + m * (e // m)] for e in range(n)]
            yc = [y[j] - abs(y[j]) * offset[j] for j in range(n)]
            z = []
            for i in range(n):
                h = bias[i]
                for j in range(n):
                    h += w[i][j] * yc[j]
                z.append(1 if h > eps else (-1 if h < -eps else 0))
            for k in range(len(x)):
                c = 0
                a = 0
                for i in range(n):
                    c += x[k][i] * z[i]
                    a += x[k][i] * y[i]
                best[k] = max(best[k], (c, a))
        out[q] = [key[0] / n for key in best]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--queries", type=int, default=10_000)
    ap.add_argument("--loop-queries", type=int, default=300, help="subset for the NumPy loop")
    ap.add_argument("--naive-queries", type=int, default=20, help="subset for pure Python")
    ap.add_argument("--repeat", type=int, default=3)
    add_record_option(ap)
    args = ap.parse_args()

    rng = np.random.default_rng(0)
    queries = rng.choice(np.array([-1, 0, 1], dtype=np.int8), size=(args.queries, 48))
    stored = [traced_moves(name) for name in SHAPE_NAMES]

    header = (
        f"{'rule':<18} {'path':<18} {'queries':>8} {'time s':>9} {'queries/s':>11} "
        f"{'vs naive':>10} {'vs per-shift':>15}"
    )
    print(f"{args.queries} random queries x 12 shifts vs {len(stored)} stored shapes, 1 thread")
    print(header)
    print("-" * len(header))
    measured: dict[str, dict[str, float]] = {}
    for rule in RECALL_RULES:
        mem = memorise(SHAPE_NAMES, stored, rule=rule)
        mem.recall(queries[:10])  # build the operator outside the timing
        result = mem.recall(queries)
        rows: list[tuple[str, int, float]] = []
        t = best_of(lambda mem=mem: mem.recall(queries), args.repeat)
        rows.append(("batched", args.queries, t))

        shifts = per_shift_batched(mem, queries)
        np.testing.assert_allclose(shifts, result.correlations)
        t_base = best_of(lambda mem=mem: per_shift_batched(mem, queries), args.repeat)
        rows.append(("per-shift batched", args.queries, t_base))

        sub = queries[: args.loop_queries]
        loop_corr = per_shift_numpy(mem, sub)
        np.testing.assert_allclose(loop_corr, result.correlations[: len(sub)])
        t = best_of(lambda mem=mem, sub=sub: per_shift_numpy(mem, sub), 1)
        rows.append(("per-shift NumPy", len(sub), t))

        naive_rate = None
        if isinstance(mem.operator, LinearRecall):
            tiny = queries[: args.naive_queries]
            t0 = time.perf_counter()
            naive_corr = naive_python(mem, tiny)
            t = time.perf_counter() - t0
            np.testing.assert_allclose(naive_corr, result.correlations[: len(tiny)])
            rows.append(("naive Python", len(tiny), t))
            naive_rate = len(tiny) / t

        base_rate = args.queries / t_base
        measured[rule] = {
            "batched_queries_s": args.queries / rows[0][2],
            "per_shift_queries_s": base_rate,
        }
        for path, count, seconds in rows:
            rate = count / seconds
            ratio = f"{rate / naive_rate:9.0f}x" if naive_rate else f"{'-':>10}"
            print(
                f"{rule:<18} {path:<18} {count:>8} {seconds:>9.4f} {rate:>11.0f} {ratio} "
                f"{rate / base_rate:14.2f}x"
            )
    print("batched results equal the loop baselines on their subsets (checked)")
    if args.record:
        heb, mat = measured["hebbian"], measured["matched"]
        record(
            __file__,
            figure=f"recall over all 12 rotations: {heb['batched_queries_s']:,.0f} queries/s "
            f"(Hebbian), {mat['batched_queries_s']:,.0f} (matched)",
            ratio=f"{heb['batched_queries_s'] / heb['per_shift_queries_s']:.1f}x / "
            f"{mat['batched_queries_s'] / mat['per_shift_queries_s']:.1f}x one NumPy product "
            "per shift for all queries",
            measured=measured,
        )


if __name__ == "__main__":
    main()
