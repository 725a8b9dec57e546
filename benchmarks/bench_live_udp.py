"""Live recognition over UDP at 50,000 frames/s: frames lost, memory, against the streaming API.

A sender process offers ``--rate`` frames/s (16 x 16 contact frames of rolling
scenarios, the live protocol, one datagram each) for ``--seconds`` to
``recognize_live`` (the code of ``taxelkit recognize --live udp:...``), which
reads whatever has arrived, decodes it together and feeds it to the smart
sensor in batches. Prints the frames processed and lost (target: < 0.1 %
lost at 50,000 frames/s on this 2-core machine), the resident memory growth
after the first second, and, measured in the same run on the same frames
without a network, the throughput of the streaming API one frame per call
(``SmartSensor.push``, the baseline: what the live path used before) and of
the streaming chunked recogniser the live path uses
(``ChunkRecogniser(streaming=True).push`` in batches of 256).

With ``--arrays N`` the stream carries N arrays (version 2 packets, one frame
of each in turn, each at ``rate / N`` frames/s) and ``recognize_live`` runs
with ``arrays=N`` (a :class:`~taxelkit.smart.bank.SensorBank`); the offline
comparison adds the bank's own rate (``push_many`` of 25 frames per array).
The acceptance run: ``--rate 48000 --arrays 200 --seconds 21`` (200 arrays at
240 frames/s, 1,008,000 frames).

Usage: ``python benchmarks/bench_live_udp.py [--rate 50000] [--seconds 4] [--arrays 1]``.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from _live_udp import run_live, write_packets  # noqa: E402
from bench_out_of_core import base_block  # noqa: E402
from taxelkit.smart.bank import SensorBank  # noqa: E402
from taxelkit.smart.recognise_chunks import ChunkRecogniser  # noqa: E402
from taxelkit.smart.recogniser import SmartSensor  # noqa: E402

PITCH_MM = 1.7625


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


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--rate", type=float, default=50_000.0, help="frames/s offered")
    ap.add_argument("--seconds", type=float, default=4.0)
    ap.add_argument("--scenarios", type=int, default=12)
    ap.add_argument("--arrays", type=int, default=1, help="arrays carried by the stream")
    args = ap.parse_args()
    frames = base_block(args.scenarios)
    n = int(args.rate * args.seconds)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "packets.bin"
        write_packets(path, frames, args.rate, n, 0.0, arrays=args.arrays)
        run = run_live(path, args.rate, frames.shape[1:], arrays=args.arrays)
    one, many = offline_rates(frames, args.rate, min(frames.shape[0], 20_000))
    lost = run.sent - run.processed
    rss = run.rss_mb[30:] or run.rss_mb  # from 2 s of traffic on (the sender waits 1 s)
    print(f"live UDP, 16 x 16 contact frames, {args.rate:,.0f} frames/s offered for "
          f"{args.seconds:g} s (sent in {run.send_s:.2f} s), 2-core machine")  # fmt: skip
    if args.arrays > 1:
        print(f"as {args.arrays} arrays of a bank, each at {args.rate / args.arrays:,.0f} frames/s")
    print(f"sent {run.sent:,}, processed {run.processed:,}, lost {lost:,} "
          f"({100 * lost / run.sent:.3f} %; target < 0.1 %)")  # fmt: skip
    print(f"resident memory after 2 s of traffic: {rss[0]:.1f} MB, at the end {rss[-1]:.1f} MB "
          f"(growth {rss[-1] - rss[0]:+.1f} MB, peak {max(rss):.1f} MB)")  # fmt: skip
    print(f"summary: {run.summary}")
    print(f"{'same frames, no network':42s} {'frames/s':>12s} {'vs push':>9s}")
    print(f"{'SmartSensor.push, one frame per call':42s} {one:12,.0f} {1.0:8.1f}x")
    print(f"{'ChunkRecogniser(streaming), 256 per call':42s} {many:12,.0f} {many / one:8.1f}x")
    if args.arrays > 1:
        bank = bank_rate(frames, args.rate, args.arrays)
        print(f"{f'SensorBank.push_many, {args.arrays} arrays x 25':42s} {bank:12,.0f} "
              f"{bank / one:8.1f}x")  # fmt: skip
    print(f"{'live path, offered rate sustained':42s} {run.processed / args.seconds:12,.0f} "
          f"{run.processed / args.seconds / one:8.1f}x")  # fmt: skip


if __name__ == "__main__":
    main()
