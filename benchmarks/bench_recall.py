"""Recall throughput with 200 stored shapes over all rotations, per rule, against a per-query loop.

200 shapes from :func:`taxelkit.world.generate_shapes` (seed 0, 90 mm) are
walked round in 3 mm steps (ideal contours: this measures recall, not
tracing) and stored. The queries are the same shapes turned by a random
angle, started at a random point and cut at a random traced fraction s in
[0.3, 1]: their chain codes (Eq. 13 of the part traced; 12 x 4 for the
paper's Hebbian rule, 24 x 8 with two sector phases for the others) and their
open tangent signatures.

For each rule it prints queries per second of the batched recall (every
rotation of every query: the m cyclic shifts of a chain code, or every start
and rotation of a signature) and of the baseline, a Python loop calling the
same recall with one query at a time, measured in the same run; the two give
the same verdicts (checked). ``masked_projection`` solves a 200 x 200 system
per query and shift: it is measured on ``--masked-queries`` queries only.

Usage: ``python benchmarks/bench_recall.py [--queries 2000] [--loop-queries 200]``.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"  # one core, so the ratio compares algorithms, not threads

import argparse  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable, Sequence  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

from _record import add_record_option, record  # noqa: E402
from taxelkit.experiments.paper000_common import IMPROVED_CHAIN_CODE  # noqa: E402
from taxelkit.memory import (  # noqa: E402
    DEFAULT_CHAIN_CODE,
    RECALL_RULES,
    SIGNATURE_RULES,
    SignatureMemory,
    tangent_signature,
)
from taxelkit.memory.contour_recall import memorise_contours, prefix_codes  # noqa: E402
from taxelkit.world import generate_shapes  # noqa: E402

STEP_MM = 3.0  # PTP section of paper 000, Sect. VI.3
DIAMETER_MM = 90.0


def walk(outline: np.ndarray, rotation_deg: float, start: int) -> np.ndarray:
    """Moves round a closed outline in 3 mm steps, turned, from another start."""
    a = np.deg2rad(rotation_deg)
    rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    closed = np.vstack([outline, outline[:1]]) @ rot.T
    edges = np.diff(closed, axis=0)
    lengths = np.hypot(edges[:, 0], edges[:, 1])
    cum = np.concatenate([[0.0], np.cumsum(lengths)])
    arc = np.arange(0.0, cum[-1], STEP_MM)
    e = np.minimum(np.searchsorted(cum, arc, side="right") - 1, len(lengths) - 1)
    pts = closed[e] + edges[e] * ((arc - cum[e]) / lengths[e])[:, None]
    pts = np.roll(pts, -start, axis=0)
    return np.diff(np.vstack([pts, pts[:1]]), axis=0)


def timed(fn: Callable[[], Any]) -> tuple[Any, float]:
    t0 = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0


def loop(recall: Callable[[Any], Any], queries: Sequence[Any]) -> list[Any]:
    """The baseline: one recall call per query."""
    return [recall(q).recognised[0] for q in queries]


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--queries", type=int, default=2000)
    ap.add_argument("--loop-queries", type=int, default=200)
    ap.add_argument("--masked-queries", type=int, default=20)
    add_record_option(ap)
    args = ap.parse_args()
    rates: dict[str, tuple[float, float]] = {}  # rule -> (batched q/s, ratio to the loop)

    shapes = generate_shapes(200, rng=0)
    names = tuple(s.name for s in shapes)
    outlines = [s.outline_mm(diameter_mm=DIAMETER_MM) for s in shapes]
    stored = [walk(o, 0.0, 0) for o in outlines]
    rng = np.random.default_rng(1)
    truth = rng.integers(0, len(shapes), args.queries)
    parts = []
    for k in truth:
        moves = walk(outlines[k], float(rng.uniform(0, 360)), int(rng.integers(0, 60)))
        parts.append(moves[: max(2, int(rng.uniform(0.3, 1.0) * len(moves)))])

    print(f"{len(names)} stored shapes, {args.queries} partial queries (s in [0.3, 1]), 1 thread")
    head = (
        f"{'rule':<18} {'code':<10} {'batched q/s':>12} {'loop q/s':>10} {'ratio':>8} {'right':>7}"
    )
    print(head)
    print("-" * len(head))
    codes: dict[tuple[int, int], np.ndarray] = {}
    for rule in RECALL_RULES:
        cfg, phases = (DEFAULT_CHAIN_CODE, 1) if rule == "hebbian" else (IMPROVED_CHAIN_CODE, 2)
        mem = memorise_contours(names, stored, rule=rule, phases=phases, config=cfg)
        key = (cfg.m, phases)
        if key not in codes:
            codes[key] = np.stack(
                [prefix_codes(p, mem, s=[1.0], unknown_for_partial=False, phases=phases)[0]
                 for p in parts]
            )  # fmt: skip
        q = codes[key] if rule != "masked_projection" else codes[key][: args.masked_queries]
        mem.recall(q[:2])  # build the operator outside the timing
        res, t_batch = timed(lambda mem=mem, q=q: mem.recall(q))
        sub = q[: min(len(q), args.loop_queries)]
        looped, t_loop = timed(lambda mem=mem, sub=sub: loop(mem.recall, sub))
        assert looped == list(res.recognised[: len(sub)])
        right = np.mean(np.array(res.recognised, dtype=object) == np.array(names)[truth[: len(q)]])
        rate, base = len(q) / t_batch, len(sub) / t_loop
        rates[rule] = (rate, rate / base)
        print(f"{rule:<18} {f'{cfg.m} x {cfg.l}':<10} {rate:>12.0f} {base:>10.0f} "
              f"{rate / base:>7.1f}x {right:>7.3f}")  # fmt: skip
    sigs = [tangent_signature(p, closed=False) for p in parts]
    base_mem = SignatureMemory.from_moves(names, stored)
    for rule in SIGNATURE_RULES:
        smem = base_mem.with_rule(rule)
        smem.recall(sigs[:2])
        res, t_batch = timed(lambda smem=smem: smem.recall(sigs))
        sub = sigs[: args.loop_queries]
        looped, t_loop = timed(lambda smem=smem, sub=sub: loop(lambda v: smem.recall([v]), sub))
        assert looped == list(res.recognised[: len(sub)])
        right = np.mean(np.array(res.recognised, dtype=object) == np.array(names)[truth])
        rate, base = len(sigs) / t_batch, len(sub) / t_loop
        rates[rule] = (rate, rate / base)
        print(f"{rule:<18} {'signature':<10} {rate:>12.0f} {base:>10.0f} "
              f"{rate / base:>7.1f}x {right:>7.3f}")  # fmt: skip
    print("batched verdicts equal the per-query loop's on its subset (checked); "
          "'right': fraction named right")  # fmt: skip
    if args.record:
        each = ", ".join(f"{r} {v[0]:,.0f}" for r, v in rates.items())
        record(
            __file__,
            figure=(
                f"recall over all rotations with {len(names)} stored (generated) shapes, "
                f"{args.queries} partial queries, queries/s per rule: {each}"
            ),
            ratio=", ".join(f"{r} {v[1]:.1f}x" for r, v in rates.items())
            + " a loop of one query at a time (the same verdicts)",
            measured={r: {"queries_per_s": round(v[0], 1), "ratio": round(v[1], 3)}
                      for r, v in rates.items()},
        )  # fmt: skip


if __name__ == "__main__":
    main()
