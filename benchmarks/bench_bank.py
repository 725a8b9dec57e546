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

Each skin (``--active``: one or more fractions) is run once to warm up (the
first run pays the page faults of the bank's buffers; not counted), then
``--runs`` times, and the range is quoted; ``--record`` writes the README row
(``docs/results/bench/bench_bank.json``), or, with another ``--batch-frames``
or an ``--evaluate-every`` above 1, a variant
(``docs/results/bench/variants/bench_bank-batchB[-everyE].json``) that only
the table of ``docs/tutorials/stream-many-arrays.md`` shows.

Usage: ``python benchmarks/bench_bank.py [--arrays N] [--frames T] [--batch-frames B]
[--active F ...] [--runs R] [--record]``.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

from _record import add_record_option, record  # noqa: E402
from _rolls import roll_images  # noqa: E402
from taxelkit.experiments.readme_tables import span  # noqa: E402
from taxelkit.frames import TactileFrames  # noqa: E402
from taxelkit.sensors import BONNEVILLE_16X16  # noqa: E402
from taxelkit.smart.bank import SensorBank  # noqa: E402
from taxelkit.smart.recogniser import recognise  # noqa: E402
from taxelkit.smart.streaming import SmartSensor  # noqa: E402

RATE_HZ = BONNEVILLE_16X16.max_rate_hz
clock = time.process_time  # CPU time of this process: one core, whatever else runs


def roll_pool(n: int) -> list[np.ndarray]:
    """``n`` randomised rolls at 240 frames/s, faults 'all', as bool images."""
    return roll_images(n, faults=True)


def skin_frames(
    pool: list[np.ndarray], n_arrays: int, n_frames: int, active: float, rng: np.random.Generator
) -> np.ndarray:
    """Frames ``(T, N, 16, 16)``, time first (each push takes one contiguous block, as a
    skin's fresh frames would be): each active array loops one roll from a random offset."""
    out = np.zeros((n_frames, n_arrays, 16, 16), bool)
    for i in np.flatnonzero(rng.random(n_arrays) < active):
        roll = pool[int(rng.integers(len(pool)))]
        clear = np.zeros((int(rng.integers(50, 500)), 16, 16), bool)  # lifted between rolls
        loop = np.concatenate([clear, roll])
        idx = (int(rng.integers(loop.shape[0])) + np.arange(n_frames)) % loop.shape[0]
        out[:, i] = loop[idx]
    return out


def bank_run(frames: np.ndarray, args: argparse.Namespace) -> dict[str, float]:
    """One bank run over ``frames`` ``(T, N, 16, 16)``: CPU rate, per-push times, wall rate."""
    t_n, n, b = frames.shape[0], frames.shape[1], args.batch_frames
    times = (np.arange(t_n) / RATE_HZ).tolist()
    bank = SensorBank(
        n,
        (16, 16),
        pitch_mm=BONNEVILLE_16X16.array.pitch_mm,
        batch_frames=b,
        evaluate_every=args.evaluate_every,
    )
    per_push = []
    wall0, t_start = time.perf_counter(), clock()
    for j in range(t_n):
        t0 = clock()
        bank.push(frames[j], times[j])
        per_push.append(clock() - t0)
    bank.flush()
    t_bank = clock() - t_start
    wall = time.perf_counter() - wall0
    return {
        "rate": n * t_n / t_bank,
        "wall_rate": n * t_n / wall,
        "push_mean_ms": 1e3 * float(np.mean(per_push)),
        "push_max_ms": 1e3 * max(per_push),
    }


def separate_rate(frames: np.ndarray, n_measured: int) -> float:
    """Frames/s of one ``SmartSensor.push`` per array per frame, on the first arrays, scaled."""
    t_n, n = frames.shape[:2]
    times = (np.arange(t_n) / RATE_HZ).tolist()
    m = min(n_measured, n)
    pitch = BONNEVILLE_16X16.array.pitch_mm
    sensors = [SmartSensor((16, 16), pitch_mm=pitch) for _ in range(m)]
    t0 = clock()
    for j in range(t_n):
        t = times[j]
        for i in range(m):
            sensors[i].push(frames[j, i], t)
    return n * t_n / ((clock() - t0) * n / m)


def one_stream(pool: list[np.ndarray], batch_frames: int) -> dict[str, float]:
    """One ``SmartSensor`` over the rolls one after the other: batched, one at a time, batch."""
    pitch = BONNEVILLE_16X16.array.pitch_mm
    stream = np.concatenate(pool)
    ts = np.arange(stream.shape[0]) / RATE_HZ
    tl = ts.tolist()
    one = SmartSensor((16, 16), pitch_mm=pitch, batch_frames=batch_frames)
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
    return {"frames": s, "batched": s / t_one, "one_at_a_time": s / t_slow, "batch": s / t_batch}


FRACTION_NAMES = {0.1: "a tenth", 0.25: "a quarter", 0.5: "half", 1.0: "all"}
#: ``batch_frames`` of the README row; other values (and ``evaluate_every`` > 1)
#: are recorded as variants for the tutorial's table.
DEFAULT_BATCH_FRAMES = 256


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--arrays", type=int, default=1000)
    ap.add_argument("--frames", type=int, default=1024)
    ap.add_argument("--batch-frames", type=int, default=DEFAULT_BATCH_FRAMES)
    ap.add_argument("--stream-batch-frames", type=int, default=4096)
    ap.add_argument("--evaluate-every", type=int, default=1)
    ap.add_argument(
        "--active", type=float, nargs="+", default=[0.25, 0.1, 1.0],
        help="fractions of the arrays rolling objects, one skin each (the first is the headline)",
    )  # fmt: skip
    ap.add_argument("--rolls", type=int, default=12)
    ap.add_argument("--baseline-arrays", type=int, default=10)
    ap.add_argument("--runs", type=int, default=3, help="bank runs per skin (the range is quoted)")
    add_record_option(ap)
    args = ap.parse_args()
    pool = roll_pool(args.rolls)
    n, t_n, b = args.arrays, args.frames, args.batch_frames
    print(
        f"skin: {n:,} arrays of 16 x 16 at {RATE_HZ:.0f} frames/s, {t_n:,} frames each "
        f"({n * t_n:,} frames a run), faults 'all'; bank: SensorBank.push, batch_frames={b} "
        f"(latency bound {b} frames = {1e3 * b / RATE_HZ:.0f} ms), "
        f"evaluate_every={args.evaluate_every}; CPU time, {args.runs} runs"
    )
    skins = {}
    for active in args.active:
        frames = skin_frames(pool, n, t_n, active, np.random.default_rng(0))
        bank_run(frames, args)  # warm-up, not counted: the first run pays the page faults
        runs = [bank_run(frames, args) for _ in range(args.runs)]
        sep = separate_rate(frames, args.baseline_arrays)
        rates = [r["rate"] for r in runs]
        skins[active] = {"runs": runs, "separate": sep}
        print(
            f"{active:5.0%} of the arrays rolling: bank {span(rates)} frames/s "
            f"(target 2,000,000; wall clock {span([r['wall_rate'] for r in runs])}, load "
            f"{os.getloadavg()[0]:.1f}); per push mean "
            f"{span([r['push_mean_ms'] for r in runs], digits=2)} ms, longest "
            f"{span([r['push_max_ms'] for r in runs], digits=0)} ms; "
            f"{span(rates, 1, scale=RATE_HZ * n)}x real time"
        )
        print(
            f"       baseline {n:,} separate SmartSensor.push (measured on "
            f"{min(args.baseline_arrays, n)} arrays, scaled): {sep:,.0f} frames/s; "
            f"ratio bank / separate {span(rates, 1, scale=sep)}x"
        )
    streams = [one_stream(pool, args.stream_batch_frames) for _ in range(max(1, args.runs - 1))]
    s = streams[0]["frames"]
    sb = args.stream_batch_frames
    print(f"one stream: {s:,} frames (the rolls one after the other), {len(streams)} runs")
    print(f"  SmartSensor.push, batch_frames={sb}: "
          f"{span([r['batched'] for r in streams])} frames/s (target 200,000)")  # fmt: skip
    print(f"  SmartSensor.push, one frame at a time: "
          f"{span([r['one_at_a_time'] for r in streams])} frames/s")  # fmt: skip
    print(f"  recognise (batch, whole recording): {span([r['batch'] for r in streams])} frames/s")
    if args.record:
        write_record(args, skins, streams)


def target_text(skins: dict[float, dict[str, Any]]) -> str:
    """Whether the 2,000,000 frames/s target holds, skin by skin (met: in every run)."""
    words = []
    for active, skin in skins.items():
        rates = [r["rate"] for r in skin["runs"]]
        name = FRACTION_NAMES.get(active, f"{active:.0%}")
        hits = sum(rate >= 2e6 for rate in rates)
        state = "met" if hits == len(rates) else "missed" if hits == 0 else f"met in {hits}"
        words.append(
            f"{state} ({name})"
            if hits in (0, len(rates))
            else f"{state} of {len(rates)} runs ({name})"
        )
    return ", ".join(words)


def write_record(
    args: argparse.Namespace, skins: dict[float, dict[str, Any]], streams: list[dict[str, float]]
) -> None:
    """The README row of this run."""
    n, b = args.arrays, args.batch_frames
    parts, ratios = [], []
    for k, (active, skin) in enumerate(skins.items()):
        rates = [r["rate"] for r in skin["runs"]]
        name = FRACTION_NAMES.get(active, f"{active:.0%}")
        push = skin["runs"]
        text = f"{name} touched: {span(rates, step=1000)} frames/s"
        if k == 0:
            mean = span([r["push_mean_ms"] for r in push], digits=2)
            longest = span([r["push_max_ms"] for r in push])
            text = (
                f"{n:,} arrays of 16 x 16, {text} (`batch_frames={b}`: latency bound "
                f"{1e3 * b / RATE_HZ:.0f} ms; a push {mean} ms on average, the push that "
                f"runs a batch {longest} ms)"
            )
        parts.append(text)
        ratios.append(f"{span(rates, 1, scale=skin['separate'])}x ({name})")
    batched = [r["batched"] for r in streams]
    figure = (
        "; ".join(parts)
        + f" ({args.runs} runs each, CPU time; target 2,000,000 {target_text(skins)}); "
        f"one stream, `batch_frames={args.stream_batch_frames}`: {span(batched, step=1000)} "
        "frames/s "
        f"(target 200,000 {'met' if min(batched) >= 2e5 else 'missed'})"
    )
    one = [r["batched"] / r["one_at_a_time"] for r in streams]
    ratio = (
        f"{', '.join(ratios)} {n:,} separate `SmartSensor.push`; one stream "
        f"{span(one, digits=1)}x one frame at a time, "
        f"{span([r['batched'] / r['batch'] for r in streams], digits=2)}x batch `recognise`"
    )
    measured = {
        "arrays": n,
        "frames": args.frames,
        "batch_frames": b,
        "skins": {str(a): s for a, s in skins.items()},
        "one_stream": streams,
    }
    measured["evaluate_every"] = args.evaluate_every
    variant = None
    if (b, args.evaluate_every) != (DEFAULT_BATCH_FRAMES, 1):
        variant = f"batch{b}" + (f"-every{args.evaluate_every}" if args.evaluate_every > 1 else "")
    record(__file__, figure=figure, ratio=ratio, measured=measured, variant=variant)


if __name__ == "__main__":
    main()
