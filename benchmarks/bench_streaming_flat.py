"""Streaming cost against a contact's length: a contact held for 1,000,000 frames.

An object rests on a 16 x 16 array for ``--frames`` frames at 240 frames/s
(over an hour), its outline flickering by one taxel as a real contact's does
(each edge taxel off with probability 0.2 per frame, seeded), after ten clear
frames. :class:`taxelkit.smart.streaming.SmartSensor` takes it frame by frame
(``push``). Prints, in the same run:

* the rate over the contact's first 10,000 frames: the baseline;
* the rate over its last 10,000 frames and over all of it;
* the ratio last / first (the target: within 20 %, 0.8-1.25);

each the median of ``--repeats`` streams of the same contact, each on a
fresh sensor (a window of 10,000 frames is 20-40 ms of CPU time, and one
stream's first and last windows alone read anywhere between 0.74 and 1.65
apart on this machine in one session, the first window also carrying the
sensor's warm-up);
* the sensor's memory for the open segment (the scanner's arrays), which
  must not grow with the contact.

Before the incremental Level 3, the same contact slowed from about 43,000
frames/s to under 1,000 after 200,000 frames (issue 12).

Times are CPU seconds of this process (``time.process_time``), so that other
work on a shared machine does not count.

Usage: ``python benchmarks/bench_streaming_flat.py [--frames N] [--kind area|line|point|all]
[--batch-frames B] [--repeats R] [--record]`` (``--batch-frames 1``: one frame at a time, slow
over 10^6 frames; ``--record`` writes the README row,
``docs/results/bench/bench_streaming_flat.json``, and needs ``--kind all``, the default).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from _record import add_record_option, record  # noqa: E402
from taxelkit.smart.streaming import SmartSensor  # noqa: E402

RATE_HZ = 240.0
PITCH_MM = 1.7625
WINDOW = 10_000
KINDS = ("area", "line", "point")


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


def stream_kind(kind: str, n: int, batch_frames: int) -> tuple[list[float], list[int], float]:
    """One stream of a held contact of ``kind``: each window's rate, memory, and CPU seconds."""
    rng = np.random.default_rng(0)
    sensor = SmartSensor((16, 16), pitch_mm=PITCH_MM, batch_frames=batch_frames)
    for j in range(10):
        sensor.push(np.zeros((16, 16), bool), j / RATE_HZ)
    j0 = 10
    rates: list[float] = []
    memory: list[int] = []
    t_all = 0.0
    for start in range(0, n, WINDOW):
        m = min(WINDOW, n - start)
        block = held_frames(kind, m, rng)
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
    print(
        f"held {kind} contact: {n:,} frames of 16 x 16 at 240 frames/s "
        f"({n / RATE_HZ / 3600:.2f} h), batch_frames={batch_frames}: class runs "
        f"{len(sensor.classes.runs())}, events {len(sensor.result().events)}"
    )
    return rates, memory, t_all


def run_kind(kind: str, n: int, batch_frames: int, repeats: int) -> dict[str, float]:
    """Stream one held contact of ``kind`` ``repeats`` times; print and return its figures."""
    streams = [stream_kind(kind, n, batch_frames) for _ in range(max(1, repeats))]
    first = float(np.median([r[0] for r, _, _ in streams]))
    last = float(np.median([r[-1] for r, _, _ in streams]))
    t_all = float(np.median([t for _, _, t in streams]))
    rates = [float(np.median(w)) for w in zip(*(r for r, _, _ in streams), strict=True)]
    memory = [m for _, mem, _ in streams for m in mem]
    print(f"median of {len(streams)} streams:")
    print(f"first {WINDOW:,} frames: {first:12,.0f} frames/s (baseline)")
    print(f"last  {WINDOW:,} frames: {last:12,.0f} frames/s")
    print(f"all {n:,} frames:    {n / t_all:12,.0f} frames/s")
    print(f"ratio last / first: {last / first:.2f} (target 0.8-1.25)")
    print(f"slowest / fastest window: {min(rates) / max(rates):.2f}")
    print(f"open segment's scanner: {min(memory):,}-{max(memory):,} bytes over the streams")
    return {
        "first_frames_s": first,
        "last_frames_s": last,
        "all_frames_s": n / t_all,
        "last_over_first": last / first,
        "slowest_over_fastest": min(rates) / max(rates),
        "scanner_bytes_min": float(min(memory)),
        "scanner_bytes_max": float(max(memory)),
        "repeats": float(len(streams)),
    }


def record_row(runs: dict[str, dict[str, float]], n: int, batch_frames: int) -> None:
    """Write the README row from the figures of this run."""
    rates = ", ".join(f"{k} {v['all_frames_s']:,.0f}" for k, v in runs.items())
    ratios = ", ".join(f"{k} {v['last_over_first']:.2f}" for k, v in runs.items())
    lo = min(v["scanner_bytes_min"] for v in runs.values()) / 1000.0
    hi = max(v["scanner_bytes_max"] for v in runs.values()) / 1000.0
    ok = all(0.8 <= v["last_over_first"] <= 1.25 for v in runs.values())
    record(
        __file__,
        figure=f"a contact held {n:,} frames ({n / RATE_HZ / 3600:.2f} h at 240 Hz), "
        f"`SmartSensor` with `batch_frames={batch_frames}`, CPU time: {rates} frames/s over the "
        f"whole contact; the open segment's state stays at {lo:.0f}-{hi:.0f} kB",
        ratio=f"last / first {WINDOW:,} frames of the same stream (median of "
        f"{int(next(iter(runs.values()))['repeats'])} streams): {ratios} (target 0.8-1.25 "
        f"{'met' if ok else 'missed'})",
        measured={"frames": n, "batch_frames": batch_frames, "kinds": runs},
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=1_000_000)
    ap.add_argument("--kind", choices=(*KINDS, "all"), default="all")
    ap.add_argument("--batch-frames", type=int, default=2000)  # 5 per window
    ap.add_argument("--repeats", type=int, default=3, help="streams per kind (medians quoted)")
    add_record_option(ap)
    args = ap.parse_args()
    kinds = KINDS if args.kind == "all" else (args.kind,)
    if args.record and len(kinds) < len(KINDS):
        ap.error("--record needs --kind all (the README row covers every kind)")
    runs = {kind: run_kind(kind, args.frames, args.batch_frames, args.repeats) for kind in kinds}
    if args.record:
        record_row(runs, args.frames, args.batch_frames)


if __name__ == "__main__":
    main()
