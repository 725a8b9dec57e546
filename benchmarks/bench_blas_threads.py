"""Levels 1-2 whatever the BLAS's threads: the products kept small enough for one thread.

Level 1's index sums and Level 2's network are matrix products. OpenBLAS
splits a product among threads once ``m n k`` reaches twice 262,144; on a
2-core machine the threads' hand-offs then cost more than the product (a
512-frame product of 16 x 16 images took 8 ms instead of 80 us). The other
benchmarks set ``OPENBLAS_NUM_THREADS=1``; a user's program or the
``taxelkit`` command usually does not. This script runs the same work in two
child processes, one with the BLAS's threads left to their default and one
with one thread, and in each both ways:

* bounded: the library as it is (:func:`taxelkit.smart.index_sums.product_rows`
  keeps every product within :data:`~taxelkit.smart.index_sums.ONE_THREAD_PRODUCT`);
* unbounded: the same code with the bound lifted (512-frame products for the
  index sums, one product over all rows for the network), as before the bound;

measuring :func:`~taxelkit.smart.index_sums.index_sums` on 65,536 frames of
16 x 16 and the out-of-core recogniser
(:class:`~taxelkit.smart.recognise_chunks.ChunkRecogniser`) on ``--frames``
frames of rolls at 240 frames/s through every imperfection, in chunks of
65,536. Wall-clock and CPU seconds (busy BLAS threads count in the latter).

Usage: ``python benchmarks/bench_blas_threads.py [--frames N] [--repeat R] [--record]``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from typing import Any

_BLAS_VARS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")


def _rolls(n_frames: int) -> tuple[Any, Any]:
    """Binary frames ``(n, 16, 16)`` of randomised rolls (faults 'all') and their times."""
    import numpy as np

    from _rolls import RATE_HZ, roll_images

    one = np.concatenate(roll_images(12, faults=True))
    frames = np.concatenate([one] * (n_frames // one.shape[0] + 1))[:n_frames]
    return frames, np.arange(n_frames) / RATE_HZ


def _timed(repeat: int, fn: Any) -> tuple[float, float]:
    """Fastest wall-clock time of ``repeat`` calls and the CPU time of that call, s."""
    best = (float("inf"), float("inf"))
    for _ in range(repeat):
        w, c = time.perf_counter(), time.process_time()
        fn()
        best = min(best, (time.perf_counter() - w, time.process_time() - c))
    return best


def child(n_frames: int, repeat: int) -> dict[str, Any]:
    """Measure in this process (its BLAS threads fixed by the environment at start)."""
    import numpy as np

    import taxelkit.smart.index_sums as index_sums_module
    from taxelkit.sensors import BONNEVILLE_16X16
    from taxelkit.smart.index_sums import index_sums
    from taxelkit.smart.recognise_chunks import ChunkRecogniser

    frames, t_s = _rolls(n_frames)
    images = frames[:65536]
    bound = index_sums_module.ONE_THREAD_PRODUCT

    def recognise_all() -> None:
        rec = ChunkRecogniser((16, 16), pitch_mm=BONNEVILLE_16X16.array.pitch_mm)
        for a in range(0, n_frames, 65536):
            rec.push(frames[a : a + 65536], t_s[a : a + 65536])
        rec.result()

    out: dict[str, Any] = {}
    for name, limit in (("bounded", bound), ("unbounded", 2**62)):
        index_sums_module.ONE_THREAD_PRODUCT = limit
        try:
            out[name] = {
                "index_sums": _timed(repeat, lambda: index_sums(images)),
                "recogniser": _timed(max(1, repeat // 2), recognise_all),
            }
        finally:
            index_sums_module.ONE_THREAD_PRODUCT = bound
    out["frames"] = {"index_sums": int(images.shape[0]), "recogniser": int(n_frames)}
    out["cpus"] = os.cpu_count()
    out["numpy"] = np.__version__
    return out


def run_child(threads: str, n_frames: int, repeat: int) -> dict[str, Any]:
    """Run :func:`child` in a fresh process with the BLAS threads ``threads`` ('default' or '1')."""
    env = {k: v for k, v in os.environ.items() if k not in _BLAS_VARS}
    if threads != "default":
        env.update({k: threads for k in _BLAS_VARS})
    cmd = [sys.executable, __file__, "--child", "--frames", str(n_frames), "--repeat", str(repeat)]
    done = subprocess.run(cmd, env=env, capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise SystemExit(f"the child with BLAS threads {threads} failed:\n{done.stderr}")
    result: dict[str, Any] = json.loads(done.stdout.strip().splitlines()[-1])
    return result


def _busy_cores(n: int) -> list[subprocess.Popen[bytes]]:
    """``n`` processes that keep a core busy each (a loaded machine), until killed."""
    spin = [sys.executable, "-c", "while True: pass"]
    return [subprocess.Popen(spin) for _ in range(n)]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=262_144)
    ap.add_argument("--repeat", type=int, default=6)
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    from _record import add_record_option, record

    add_record_option(ap)
    args = ap.parse_args()
    if args.child:
        print(json.dumps(child(args.frames, args.repeat)))
        return
    runs: dict[str, dict[str, Any]] = {}
    others = max(1, (os.cpu_count() or 2) - 1)
    for load in ("idle", "busy"):
        for threads in ("default", "1"):
            spinners = _busy_cores(others) if load == "busy" else []
            try:
                runs[f"{threads}/{load}"] = run_child(threads, args.frames, args.repeat)
            finally:
                for p in spinners:
                    p.kill()
                    p.wait()
    first = runs["1/idle"]
    n = first["frames"]
    print(
        f"{first['cpus']} CPUs, numpy {first['numpy']}; index sums on {n['index_sums']:,} "
        f"frames of 16 x 16, out-of-core recogniser on {n['recogniser']:,} frames; "
        f"other cores idle, or {others} kept busy by other processes"
    )
    rates: dict[str, float] = {}
    for key, res in runs.items():
        threads, load = key.split("/")
        for mode in ("bounded", "unbounded"):
            parts = []
            for what in ("index_sums", "recogniser"):
                wall, cpu = res[mode][what]
                rates[f"{key}/{mode}/{what}"] = n[what] / wall
                parts.append(f"{what} {n[what] / wall:11,.0f} frames/s (CPU {cpu / wall:.2f})")
            print(f"threads {threads:>7}, others {load}, products {mode:>9}: " + "; ".join(parts))
    r = rates
    gain = {
        load: r[f"default/{load}/bounded/recogniser"] / r[f"default/{load}/unbounded/recogniser"]
        for load in ("idle", "busy")
    }
    same = r["default/busy/bounded/recogniser"] / r["1/busy/bounded/recogniser"]
    print(
        "recogniser with default threads, bounded / unbounded products: "
        f"{gain['idle']:.2f}x (other cores idle), {gain['busy']:.2f}x (busy); "
        f"bounded, default threads / one thread (busy): {same:.2f}"
    )
    if args.record:
        cpu_idle = runs["default/idle"]["unbounded"]["recogniser"]
        record(
            __file__,
            figure="Levels 1-4 out of core, the BLAS's threads left to their default: "
            f"{r['default/busy/bounded/recogniser']:,.0f} frames/s with the other cores busy "
            f"({same:.2f}x one BLAS thread), {r['default/idle/bounded/recogniser']:,.0f} with "
            f"them idle, on one core (unbounded products kept {cpu_idle[1] / cpu_idle[0]:.2f} "
            "cores busy)",
            ratio=f"{gain['busy']:.2f}x (busy) and {gain['idle']:.2f}x (idle) the same code with "
            "unbounded products",
            measured={"rates": rates, "runs": runs, "busy_processes": others},
        )


if __name__ == "__main__":
    main()
