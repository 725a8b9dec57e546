"""Throughput of the mechanoreceptive neuron model (paper 000, Eq. 1-6, 9).

Prints element-samples per second (one element at one time step) for the
vectorised batch model, the streaming model, and a naive per-element,
per-sample Python loop measured in the same run, with their ratios.

Usage: ``python benchmarks/bench_neuron.py [--frames T] [--rows R] [--cols C]``.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from taxelkit.neuron import NeuronParams, StreamingNeuron, direction_output  # noqa: E402
from taxelkit.neuron.mechanoreceptor import window_samples  # noqa: E402


def naive(u: np.ndarray, dt: float, params: NeuronParams, eps: float) -> np.ndarray:
    """Eq. 2-4 and 9 element by element, sample by sample."""
    t_n, rows, cols = u.shape
    n = window_samples(params.tau_s, dt)
    z = np.zeros(u.shape, np.int8)
    for i in range(rows):
        for j in range(cols):
            s = [0.0] * t_n
            for t in range(1, t_n):
                s[t] = params.gain_a * (u[t, i, j] - u[t - 1, i, j]) / dt
            for t in range(t_n):
                acc = 0.0
                for k in range(max(0, t - n + 1), t + 1):
                    acc += s[k] * dt
                z[t, i, j] = 1 if acc > eps else (-1 if acc < -eps else 0)
    return z


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=20_000)
    ap.add_argument("--rows", type=int, default=6)
    ap.add_argument("--cols", type=int, default=6)
    args = ap.parse_args()
    dt, eps = 0.02, 0.01
    params = NeuronParams(tau_s=0.1)
    rng = np.random.default_rng(0)
    u = np.cumsum(rng.normal(0, 0.005, (args.frames, args.rows, args.cols)), axis=0)
    n_el = u.size

    t0 = time.perf_counter()
    z = direction_output(u, dt, epsilon=eps, params=params)
    t_batch = time.perf_counter() - t0

    n_stream = min(args.frames, 5_000)
    neuron = StreamingNeuron((args.rows, args.cols), dt, params, signed=True, epsilon=eps)
    t0 = time.perf_counter()
    zs = np.stack([neuron.push(f) for f in u[:n_stream]])
    t_stream = (time.perf_counter() - t0) / (n_stream * args.rows * args.cols)

    n_naive = min(args.frames, 300)
    t0 = time.perf_counter()
    zn = naive(u[:n_naive], dt, params, eps)
    t_naive = (time.perf_counter() - t0) / (n_naive * args.rows * args.cols)

    assert np.array_equal(zn, z[:n_naive]), "naive and batch disagree"
    assert np.array_equal(zs, z[:n_stream]), "streaming and batch disagree"
    per_batch = t_batch / n_el
    print(f"neuron model, direction mode, {args.rows} x {args.cols} elements, one core")
    print(f"{'method':34s} {'element-samples/s':>18s} {'vs naive':>10s}")
    print(f"{'batch (taxelkit)':34s} {1 / per_batch:18,.0f} {t_naive / per_batch:9.0f}x")
    print(f"{'streaming, one frame per call':34s} {1 / t_stream:18,.0f} {t_naive / t_stream:9.1f}x")
    print(f"{'naive per-element Python loop':34s} {1 / t_naive:18,.0f} {1.0:9.1f}x")
    print("outputs of all three agree exactly")


if __name__ == "__main__":
    main()
