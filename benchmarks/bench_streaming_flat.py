"""Streaming cost against a contact's length: a contact held for 1,000,000 frames.

An object rests on a 16 x 16 array for ``--frames`` frames at 240 frames/s
(over an hour), its outline flickering by one taxel as a real contact's does
(each edge taxel off with probability 0.2 per frame, seeded), after ten clear
frames. :class:`taxelkit.smart.streaming.SmartSensor` takes it frame by frame
(``push``). Prints, in the same run:

* the rate over the contact's first 10,000 frames: the baseline;
* the rate over its last 10,000 frames and over all of it;
* the ratio last / first (the target: within 20 %, 0.8-1.25);
* the sensor's memory for the open segment (the scanner's arrays), which
  must not grow with the contact.

Before the incremental Level 3, the same contact slowed from about 43,000
frames/s to under 1,000 after 200,000 frames (issue 12).

Times are CPU seconds of this process (``time.process_time``), so that other
work on a shared machine does not count.

Usage: ``python benchmarks/bench_streaming_flat.py [--frames N] [--kind area|line|point]
[--batch-frames B]`` (``--batch-frames 1``: one frame at a time, slow over 10^6 frames).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from taxelkit.smart.streaming import SmartSensor  # noqa: E402

RATE_HZ = 240.0
PITCH_MM = 1.7625
WINDOW = 10_000


def held_frames(kind: str, n: int, rng: np.random.Generator) -> np.ndarray:
    """``n`` frames (n, 16, 16) bool of one contact held still, its edge flickering."""
    core = np.zeros((16, 16), bool)
    edge = np.zeros((16, 16), bool)
    if kind == "area":
        core[5:10, 5:11] = True
        edge[4, 5:11] = edge[10, 5:11] = True
    elif kind == "line":
        core[8, 3:13] = True
        edge[8, 2] = edge[8, 13] = True
    else:
        core[7:9, 7] = True  # two taxels and a third that comes and goes: a point
        edge[7, 8] = True
    flicker = rng.random((n, 16, 16)) < 0.8
    return core[None] | (edge[None] & flicker)


def scanner_bytes(sensor: SmartSensor) -> int:
    """Bytes held by the open segment's scanner (its arrays)."""
    seg = sensor._stream._seg
    if seg is None:
        return 0
    total = 0
    for obj in (seg, *vars(seg).values()):
        for v in vars(obj).values() if hasattr(obj, "__dict__") else ():
            if isinstance(v, np.ndarray):
                total += v.nbytes
    return total


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=1_000_000)
    ap.add_argument("--kind", choices=("area", "line", "point"), default="area")
    ap.add_argument("--batch-frames", type=int, default=2000)  # 5 per window
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    sensor = SmartSensor((16, 16), pitch_mm=PITCH_MM, batch_frames=args.batch_frames)
    for j in range(10):
        sensor.push(np.zeros((16, 16), bool), j / RATE_HZ)
    n, j0 = args.frames, 10
    rates: list[float] = []
    memory: list[int] = []
    t_all = 0.0
    for start in range(0, n, WINDOW):
        m = min(WINDOW, n - start)
        block = held_frames(args.kind, m, rng)
        times = ((j0 + start + np.arange(m)) / RATE_HZ).tolist()
        push = sensor.push
        t0 = time.process_time()
        for f, t in zip(block, times, strict=True):
            push(f, t)
        dt = time.process_time() - t0
        t_all += dt
        rates.append(m / dt)
        memory.append(scanner_bytes(sensor))
    sensor.flush()
    classes = sensor.classes.runs()
    first, last = rates[0], rates[-1]
    print(
        f"held {args.kind} contact: {n:,} frames of 16 x 16 at 240 frames/s "
        f"({n / RATE_HZ / 3600:.2f} h), batch_frames={args.batch_frames}"
    )
    print(f"class runs: {len(classes)}; events: {len(sensor.result().events)}")
    print(f"first {WINDOW:,} frames: {first:12,.0f} frames/s (baseline)")
    print(f"last  {WINDOW:,} frames: {last:12,.0f} frames/s")
    print(f"all {n:,} frames:    {n / t_all:12,.0f} frames/s")
    print(f"ratio last / first: {last / first:.2f} (target 0.8-1.25)")
    print(f"slowest / fastest window: {min(rates) / max(rates):.2f}")
    print(
        f"open segment's scanner: {memory[0]:,} bytes after {WINDOW:,}, {memory[-1]:,} at the end"
    )


if __name__ == "__main__":
    main()
