"""Live recognition over UDP at 50,000 frames/s: frames lost, memory, against the streaming API.

A sender process offers ``--rate`` frames/s (16 x 16 contact frames of rolling
scenarios, the live protocol, one datagram each) for ``--seconds`` to
``recognize_live`` (the code of ``taxelkit recognize --live udp:...``), which
reads whatever has arrived, decodes it together and feeds it to the smart
sensor in batches. Prints the frames processed and lost (target: < 0.1 %
lost at 50,000 frames/s on this 2-core machine), the resident memory growth
(target: < 10 MB over 1,000,000 frames; from 2 s of traffic on, or, for a
stream longer than that, over its last 1,000,000 frames, the growth before
them printed beside: a bank's per-array state fills while each array meets
its first contacts, about 30 s at 240 frames/s, then stays bounded), and,
measured in the same run on the same frames
without a network, the throughput of the streaming API one frame per call
(``SmartSensor.push``, the baseline: what the live path used before) and of
the streaming chunked recogniser the live path uses
(``ChunkRecogniser(streaming=True).push`` in batches of 256).

With ``--arrays N`` the stream carries N arrays (version 2 packets, one frame
of each in turn, each at ``rate / N`` frames/s) and ``recognize_live`` runs
with ``arrays=N`` (a :class:`~taxelkit.smart.bank.SensorBank`); the offline
comparison adds the bank's own rate (``push_many`` of 25 frames per array).
The acceptance run: ``--arrays 1 200`` (one array at 50,000 frames/s for 4 s;
200 arrays at 240 frames/s, ``--bank-rate 48000 --bank-seconds 63``, 3,024,000 frames).

Each stream is run ``--runs`` times (the range is quoted); ``--arrays 1 200``
runs both (the bank at ``--bank-rate`` for ``--bank-seconds``); ``--record``
writes the README row (``docs/results/bench/bench_live_udp.json``).

Usage: ``python benchmarks/bench_live_udp.py [--rate 50000] [--seconds 4] [--arrays 1 ...]
[--runs 2] [--record]``.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

from _live_udp import run_live, write_packets  # noqa: E402
from _record import add_record_option, record  # noqa: E402
from bench_out_of_core import base_block  # noqa: E402
from taxelkit.experiments.readme_tables import span  # noqa: E402
from taxelkit.smart.bank import SensorBank  # noqa: E402
from taxelkit.smart.recognise_chunks import ChunkRecogniser  # noqa: E402
from taxelkit.smart.recogniser import SmartSensor  # noqa: E402

PITCH_MM = 1.7625
#: Frames over which the memory must stay flat (the last of a longer stream).
STEADY_FRAMES = 1_000_000


def offline_rates(frames: np.ndarray, rate_hz: float, n_stream: int) -> tuple[float, float]:
    """Frames/s of SmartSensor.push (one per call) and of the streaming chunks of 256."""
    t_s = np.arange(frames.shape[0]) / rate_hz
    sensor = SmartSensor(frames.shape[1:], pitch_mm=PITCH_MM)
    t0 = time.process_time()
    for f, t in zip(frames[:n_stream], t_s[:n_stream], strict=True):
        sensor.push(f, t)
    one = n_stream / (time.process_time() - t0)
    batched = ChunkRecogniser(frames.shape[1:], pitch_mm=PITCH_MM, streaming=True)
    t0 = time.process_time()
    for a in range(0, frames.shape[0], 256):
        batched.push(frames[a : a + 256], t_s[a : a + 256])
    many = frames.shape[0] / (time.process_time() - t0)
    return one, many


def bank_rate(frames: np.ndarray, rate_hz: float, arrays: int, per_push: int = 25) -> float:
    """Frames/s of ``SensorBank.push_many`` over ``arrays`` arrays, ``per_push`` frames each."""
    n = min(frames.shape[0], 2_000)
    idx = (np.arange(n)[None, :] + 997 * np.arange(arrays)[:, None]) % frames.shape[0]
    stack = frames[idx]  # (arrays, n, rows, cols)
    t_s = np.broadcast_to(np.arange(n) * arrays / rate_hz, (arrays, n))
    bank = SensorBank(arrays, frames.shape[1:], pitch_mm=PITCH_MM)
    t0 = time.process_time()
    for a in range(0, n, per_push):
        bank.push_many(stack[:, a : a + per_push], t_s[:, a : a + per_push])
    return arrays * n / (time.process_time() - t0)


def live_runs(
    frames: np.ndarray, rate: float, seconds: float, arrays: int, runs: int
) -> list[dict[str, float]]:
    """``runs`` live runs: frames sent, lost, RSS growth and load average of each."""
    out = []
    n = int(rate * seconds)
    for _ in range(runs):
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "packets.bin"
            write_packets(path, frames, rate, n, 0.0, arrays=arrays)
            run = run_live(path, rate, frames.shape[1:], arrays=arrays)
        # samples every 0.1 s from the start; the sender waits 1 s: from 2 s of traffic on,
        # or over the last STEADY_FRAMES of a longer stream
        start_s = max(2.0, (run.sent - STEADY_FRAMES) / rate)
        i0 = min(round(10 * (1.0 + start_s)), len(run.rss_mb) - 1)
        rss = run.rss_mb[i0:] or run.rss_mb
        warm = rss[0] - run.rss_mb[min(30, i0)]
        lost = run.sent - run.processed
        print(
            f"{arrays} array(s), {rate:,.0f} frames/s offered for {seconds:g} s (sent in "
            f"{run.send_s:.2f} s): sent {run.sent:,}, processed {run.processed:,}, lost "
            f"{lost:,} ({100 * lost / run.sent:.3f} %; target < 0.1 %); RSS after "
            f"{start_s:.0f} s {rss[0]:.1f} MB ({warm:+.1f} MB since 2 s), at the end "
            f"{rss[-1]:.1f} MB (growth {rss[-1] - rss[0]:+.1f} MB over "
            f"{min(run.sent, int(rate * (seconds - start_s))):,} frames, peak {max(rss):.1f} MB); "
            f"load average {os.getloadavg()[0]:.1f}"
        )
        print(f"  summary: {run.summary}")
        out.append(
            {
                "sent": run.sent,
                "processed": run.processed,
                "lost_pct": 100 * lost / run.sent,
                "rss_growth_mb": rss[-1] - rss[0],
                "rss_from_s": start_s,
                "rss_warmup_mb": warm,
                "sustained": run.processed / seconds,
                "load_average": os.getloadavg()[0],
            }
        )
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--rate", type=float, default=50_000.0, help="frames/s offered (one array)")
    ap.add_argument("--seconds", type=float, default=4.0)
    ap.add_argument("--scenarios", type=int, default=12)
    ap.add_argument(
        "--arrays", type=int, nargs="+", default=[1], help="arrays carried by the stream, per run"
    )
    ap.add_argument("--bank-rate", type=float, default=48_000.0, help="frames/s with N > 1")
    ap.add_argument("--bank-seconds", type=float, default=63.0)
    ap.add_argument("--runs", type=int, default=2, help="live runs per stream (range quoted)")
    add_record_option(ap)
    args = ap.parse_args()
    frames = base_block(args.scenarios)
    print("live UDP, 16 x 16 contact frames, 2-core machine")
    results = {}
    for arrays in args.arrays:
        rate, seconds = (
            (args.rate, args.seconds) if arrays == 1 else (args.bank_rate, args.bank_seconds)
        )
        results[arrays] = {
            "rate": rate,
            "seconds": seconds,
            "runs": live_runs(frames, rate, seconds, arrays, args.runs),
        }
    one, many = offline_rates(frames, args.rate, min(frames.shape[0], 20_000))
    print(f"{'same frames, no network (CPU time)':42s} {'frames/s':>12s} {'vs push':>9s}")
    print(f"{'SmartSensor.push, one frame per call':42s} {one:12,.0f} {1.0:8.1f}x")
    print(f"{'ChunkRecogniser(streaming), 256 per call':42s} {many:12,.0f} {many / one:8.1f}x")
    banks = {}
    for arrays, res in results.items():
        if arrays > 1:
            banks[arrays] = bank_rate(frames, res["rate"], arrays)
            print(f"{f'SensorBank.push_many, {arrays} arrays x 25':42s} {banks[arrays]:12,.0f} "
                  f"{banks[arrays] / one:8.1f}x")  # fmt: skip
        sustained = [r["sustained"] for r in res["runs"]]
        print(f"{f'live path, {arrays} array(s), sustained':42s} {span(sustained):>12s} "
              f"{span([x / one for x in sustained], 1):>8s}x")  # fmt: skip
    if args.record:
        write_record(args, results, one, banks)


def write_record(
    args: argparse.Namespace,
    results: dict[int, dict[str, Any]],
    one: float,
    banks: dict[int, float],
) -> None:
    """The README row of this run."""
    parts, ratios, lost_bad, rss_bad, n_runs = [], [], 0, 0, 0
    for arrays, res in results.items():
        runs = res["runs"]
        lost = [r["lost_pct"] for r in runs]
        growth = [r["rss_growth_mb"] for r in runs]
        warmup = [r["rss_warmup_mb"] for r in runs]
        load = [r["load_average"] for r in runs]
        frames = int(res["rate"] * res["seconds"])
        lost_bad += sum(x >= 0.1 for x in lost)
        rss_bad += sum(x >= 10 for x in growth)
        n_runs += len(runs)
        what = (
            f"`recognize --live udp:` offered {res['rate']:,.0f} frames/s for {res['seconds']:g} s"
            if arrays == 1
            else f"`--arrays {arrays}` (version 2 packets, {arrays} arrays at "
            f"{res['rate'] / arrays:,.0f} frames/s, {frames:,} frames)"
        )
        memory = (
            f"RSS {span(growth, 1, sign='+')} MB"
            if frames <= STEADY_FRAMES
            else f"RSS {span(growth, 1, sign='+')} MB over the last {STEADY_FRAMES:,} frames "
            f"({span(warmup, 1, sign='+')} MB before them, from 2 s on, while the arrays' "
            "state filled)"
        )
        parts.append(
            f"{what}: {span(lost, 3)} % lost, {memory} "
            f"({len(runs)} runs, load average {span(load, 1)})"
        )
        sustained = [r["sustained"] / one for r in runs]
        ratios.append(
            f"{span(sustained, 1)}x ({'one array' if arrays == 1 else f'{arrays} arrays'})"
        )

    def verdict(bad: int) -> str:
        return "met in every run" if bad == 0 else f"missed in {bad} of {n_runs} runs"

    figure = "; ".join(parts) + (
        f" (target < 0.1 % lost {verdict(lost_bad)}; < 10 MB growth {verdict(rss_bad)})"
    )
    ratio = f"the live path sustains {', '.join(ratios)} `SmartSensor.push` one frame per call"
    if banks:
        ratio += "; `SensorBank.push_many` offline " + ", ".join(
            f"{b / one:.1f}x ({a} arrays)" for a, b in banks.items()
        )
    measured = {
        "push_one_rate": one,
        "streams": {str(a): r for a, r in results.items()},
        "bank_push_many": {str(a): b for a, b in banks.items()},
    }
    record(__file__, figure=figure, ratio=ratio, measured=measured)


if __name__ == "__main__":
    main()
