"""Throughput of the mechanoreceptive neuron model (paper 000, Eq. 1-6, 9).

Prints element-samples per second (one element at one time step) for the
vectorised batch model, the streaming model, the model as a NumPy user would
vectorise it (a difference and a running sum by ``cumsum``: the baseline) and a
naive per-element, per-sample Python loop, measured in the same run, with
their ratios.

Usage: ``python benchmarks/bench_neuron.py [--frames T] [--rows R] [--cols C]``.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from _record import add_record_option, record  # noqa: E402
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


def numpy_user(u: np.ndarray, dt: float, params: NeuronParams, eps: float) -> np.ndarray:
    """Eq. 2-4 and 9 as a NumPy user would vectorise them: a difference, a running sum."""
    n = window_samples(params.tau_s, dt)
    s = np.zeros_like(u)
    s[1:] = params.gain_a * (u[1:] - u[:-1])  # the rate times dt
    c = np.cumsum(s, axis=0)
    acc = c.copy()
    acc[n:] -= c[:-n]
    out: np.ndarray = np.where(acc > eps, 1, np.where(acc < -eps, -1, 0)).astype(np.int8)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=20_000)
    ap.add_argument("--rows", type=int, default=6)
    ap.add_argument("--cols", type=int, default=6)
    add_record_option(ap)
    args = ap.parse_args()
    dt, eps = 0.02, 0.01
    params = NeuronParams(tau_s=0.1)
    rng = np.random.default_rng(0)
    u = np.cumsum(rng.normal(0, 0.005, (args.frames, args.rows, args.cols)), axis=0)
    n_el = u.size

    t0 = time.perf_counter()
    z = direction_output(u, dt, epsilon=eps, params=params)
    t_batch = time.perf_counter() - t0

    t0 = time.perf_counter()
    zu = numpy_user(u, dt, params, eps)
    t_user = (time.perf_counter() - t0) / n_el
    agree = float(np.mean(zu == z))

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
    print(f"{'method':34s} {'element-samples/s':>18s} {'vs naive':>10s} {'vs NumPy':>10s}")
    for name, t in (
        ("batch (taxelkit)", per_batch),
        ("NumPy cumsum (baseline)", t_user),
        ("streaming, one frame per call", t_stream),
        ("naive per-element Python loop", t_naive),
    ):
        print(f"{name:34s} {1 / t:18,.0f} {t_naive / t:9.1f}x {t_user / t:9.2f}x")
    print(
        f"batch, streaming and naive outputs agree exactly; the NumPy baseline on "
        f"{100 * agree:.2f} % of element-samples"
    )
    if args.record:
        faster = " (faster)" if per_batch > t_user else ""
        record(
            __file__,
            figure=f"neuron model: {1 / per_batch / 1e6:.0f} M element-samples/s",
            ratio=f"{t_user / per_batch:.2f}x a NumPy user's `cumsum` version{faster}; "
            f"{t_naive / per_batch:.0f}x a per-element loop",
            measured={
                "batch_s_per_element": per_batch,
                "numpy_s_per_element": t_user,
                "streaming_s_per_element": t_stream,
                "naive_s_per_element": t_naive,
            },
        )


if __name__ == "__main__":
    main()
