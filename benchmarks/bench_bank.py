"""Throughput of the sensor bank: 1,000 arrays of 16 x 16 streamed at once, and one stream.

A skin of ``--arrays`` Bonneville arrays (16 x 16, 240 frames/s). Each array
replays a randomised roll of one of the six objects (seen through every
sensor imperfection, ``fault_model("all")``) from a random offset, so some
arrays are touched while others are clear, as on a skin; ``--active`` is the
fraction of arrays that carry a roll at all (the rest stay clear). Prints, in
the same run:

* bank: :class:`taxelkit.smart.bank.SensorBank`, one ``push((N, 16, 16))``
  per frame period, ``batch_frames`` pushes buffered: aggregate frames/s
  (target >= 2,000,000), the mean push and the longest (the one that runs a
  buffered batch), and the latency bound;
* baseline: ``N`` separate :class:`taxelkit.smart.streaming.SmartSensor`,
  one ``push`` per array per frame: measured on ``--baseline-arrays`` of the
  arrays (the same frames) and scaled to ``N`` (the cost is per array-frame);
* one stream: a ``SmartSensor`` with ``batch_frames`` on the rolls one after
  the other (target >= 200,000 frames/s), against the same sensor one frame
  at a time (``batch_frames=1``) and against batch
  :func:`taxelkit.smart.recogniser.recognise` on the same frames.

Times are CPU seconds of this process (``time.process_time``; BLAS on one
thread), so that other work on a shared machine does not count; the wall-clock
rate of the bank is printed beside.

Usage: ``python benchmarks/bench_bank.py [--arrays N] [--frames T] [--batch-frames B]
[--active F]``.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from taxelkit.frames import TactileFrames  # noqa: E402
from taxelkit.motion.rolling import frames_from_scenario  # noqa: E402
from taxelkit.motion.scenarios import make_scenario  # noqa: E402
from taxelkit.sensors import BONNEVILLE_16X16  # noqa: E402
from taxelkit.sensors.faults import fault_model  # noqa: E402
from taxelkit.smart.bank import SensorBank  # noqa: E402
from taxelkit.smart.recogniser import recognise  # noqa: E402
from taxelkit.smart.streaming import SmartSensor  # noqa: E402
from taxelkit.smart.tacteme_table import OBJECTS  # noqa: E402

RATE_HZ = BONNEVILLE_16X16.max_rate_hz
clock = time.process_time  # CPU time of this process: one core, whatever else runs


def roll_pool(n: int) -> list[np.ndarray]:
    """``n`` randomised rolls at 240 frames/s, faults 'all', as bool images."""
    sensor, thr = BONNEVILLE_16X16, BONNEVILLE_16X16.contact_threshold_mm
    out = []
    for k in range(n):
        rng = np.random.default_rng(k)
        sc = make_scenario(OBJECTS[k % len(OBJECTS)], rng=rng, rate_hz=RATE_HZ)
        rec = fault_model("all").apply(
            frames_from_scenario(sensor, sc, rng=rng), threshold=thr, rng=k
        )
        out.append(rec.frames > thr)
    return out


def skin_frames(
    pool: list[np.ndarray], n_arrays: int, n_frames: int, active: float, rng: np.random.Generator
) -> np.ndarray:
    """Frames ``(N, T, 16, 16)``: each active array loops one roll from a random offset."""
    out = np.zeros((n_arrays, n_frames, 16, 16), bool)
    for i in np.flatnonzero(rng.random(n_arrays) < active):
        roll = pool[int(rng.integers(len(pool)))]
        clear = np.zeros((int(rng.integers(50, 500)), 16, 16), bool)  # lifted between rolls
        loop = np.concatenate([clear, roll])
        idx = (int(rng.integers(loop.shape[0])) + np.arange(n_frames)) % loop.shape[0]
        out[i] = loop[idx]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arrays", type=int, default=1000)
    ap.add_argument("--frames", type=int, default=1024)
    ap.add_argument("--batch-frames", type=int, default=256)
    ap.add_argument("--stream-batch-frames", type=int, default=4096)
    ap.add_argument("--evaluate-every", type=int, default=1)
    ap.add_argument("--active", type=float, default=0.25)
    ap.add_argument("--rolls", type=int, default=12)
    ap.add_argument("--baseline-arrays", type=int, default=10)
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    pool = roll_pool(args.rolls)
    n, t_n, b = args.arrays, args.frames, args.batch_frames
    frames = skin_frames(pool, n, t_n, args.active, rng)
    times = (np.arange(t_n) / RATE_HZ).tolist()
    pitch = BONNEVILLE_16X16.array.pitch_mm

    bank = SensorBank(
        n, (16, 16), pitch_mm=pitch, batch_frames=b, evaluate_every=args.evaluate_every
    )
    per_push = []
    wall0, t_start = time.perf_counter(), clock()
    for j in range(t_n):
        t0 = clock()
        bank.push(frames[:, j], times[j])
        per_push.append(clock() - t0)
    bank.flush()
    t_bank = clock() - t_start
    wall = time.perf_counter() - wall0
    bank_rate = n * t_n / t_bank
    print(
        f"skin: {n:,} arrays of 16 x 16 at {RATE_HZ:.0f} frames/s, {t_n:,} frames each "
        f"({n * t_n:,} frames), {args.active:.0%} of the arrays rolling objects, faults 'all'"
    )
    print(
        f"bank (SensorBank.push, batch_frames={b}, evaluate_every={args.evaluate_every}): "
        f"{bank_rate:14,.0f} frames/s (target 2,000,000)"
    )
    print(f"  wall clock: {n * t_n / wall:,.0f} frames/s (load average {os.getloadavg()[0]:.1f})")
    print(
        f"  per push (CPU): mean {1e3 * np.mean(per_push):.2f} ms, "
        f"longest {1e3 * max(per_push):.1f} ms (the push that runs the batch); "
        f"latency bound {b} frames = {1e3 * b / RATE_HZ:.0f} ms at {RATE_HZ:.0f} frames/s"
    )
    print(
        f"  real time: {bank_rate / (n * RATE_HZ):.1f} x ({n:,} arrays at {RATE_HZ:.0f} frames/s)"
    )

    m = min(args.baseline_arrays, n)
    sensors = [SmartSensor((16, 16), pitch_mm=pitch) for _ in range(m)]
    t0 = clock()
    for j in range(t_n):
        t = times[j]
        for i in range(m):
            sensors[i].push(frames[i, j], t)
    t_sep = (clock() - t0) * n / m
    sep_rate = n * t_n / t_sep
    print(
        f"baseline ({n:,} separate SmartSensor.push, measured on {m} arrays, scaled): "
        f"{sep_rate:14,.0f} frames/s"
    )
    print(f"  ratio bank / separate sensors: {bank_rate / sep_rate:.1f}x")

    stream = np.concatenate(pool)
    ts = np.arange(stream.shape[0]) / RATE_HZ
    tl = ts.tolist()
    sb = args.stream_batch_frames
    one = SmartSensor((16, 16), pitch_mm=pitch, batch_frames=sb)
    t0 = clock()
    for f, t in zip(stream, tl, strict=True):
        one.push(f, t)
    one.flush()
    t_one = clock() - t0
    k = min(20_000, stream.shape[0])
    slow = SmartSensor((16, 16), pitch_mm=pitch)
    t0 = clock()
    for f, t in zip(stream[:k], tl[:k], strict=True):
        slow.push(f, t)
    t_slow = (clock() - t0) * stream.shape[0] / k
    t0 = clock()
    recognise(TactileFrames(stream, ts, pitch_mm=pitch))
    t_batch = clock() - t0
    s = stream.shape[0]
    print(f"one stream: {s:,} frames (the rolls one after the other)")
    print(f"  SmartSensor.push, batch_frames={sb}: {s / t_one:12,.0f} frames/s (target 200,000)")
    print(f"  SmartSensor.push, one frame at a time: {s / t_slow:12,.0f} frames/s")
    print(f"  recognise (batch, whole recording): {s / t_batch:12,.0f} frames/s")
    print(
        f"  ratio batched / one at a time: {t_slow / t_one:.1f}x; "
        f"batched / recognise: {t_batch / t_one:.2f}"
    )


if __name__ == "__main__":
    main()
