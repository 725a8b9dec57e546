"""Soak: 1,000,000 frames through UDP with 1 % damaged packets; memory flat, no valid frame lost.

A sender process offers ``--frames`` 16 x 16 contact frames (rolling
scenarios: contacts held, rolled and lifted, over and over) at ``--rate``
frames/s, 1 % of the packets with a flipped payload byte (a bad CRC), to
``recognize_live`` (the code of ``taxelkit recognize --live udp:...``).
Prints the frames processed against the valid frames sent (target: all), the
damaged packets counted, and the resident memory from the end of the first
second to the end (target: < 10 MB growth). The baseline is the target
itself; the live path before this benchmark grew about 110 bytes a frame
with a contact held (110 MB over 1,000,000 frames).

Runs ``--runs`` soaks in a row in one process (default 3: one run on a loaded
machine says little about the frames lost); the second and later start with
the memory the earlier ones left, and their growth is measured the same way.

Usage: ``python benchmarks/bench_live_soak.py [--frames 1000000] [--rate 50000] [--runs 3]
[--record]`` (``--record`` writes the README row, ``docs/results/bench/bench_live_soak.json``).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402

from _live_udp import run_live, write_packets  # noqa: E402
from _record import add_record_option, record  # noqa: E402
from bench_out_of_core import base_block  # noqa: E402


def soak(path: Path, rate: float, damaged: int) -> tuple[int, int, float]:
    """One run over the packets of ``path``: valid frames sent, processed, RSS growth (MB)."""
    run = run_live(path, rate, (16, 16))
    valid = run.sent - damaged
    rss = run.rss_mb[30:] or run.rss_mb  # from 2 s of traffic on (the sender waits 1 s)
    print(f"live UDP soak: {run.sent:,} frames of 16 x 16 offered at {rate:,.0f} frames/s "
          f"(sent in {run.send_s:.1f} s), {damaged:,} packets damaged")  # fmt: skip
    lost = "all" if run.processed == valid else f"{valid - run.processed:,} lost"
    print(f"valid frames sent {valid:,}, processed {run.processed:,} ({lost})")
    growth = rss[-1] - rss[0]
    print(f"resident memory after 2 s of traffic: {rss[0]:.1f} MB, at the end {rss[-1]:.1f} MB, "
          f"peak {max(rss):.1f} MB: growth {growth:+.1f} MB (target < 10 MB)")  # fmt: skip
    print(f"summary: {run.summary}")
    return valid, run.processed, growth


def record_row(
    runs: list[tuple[int, int, float]], offered: int, rate: float, corrupt: float
) -> None:
    """Write the README row from the runs of this process."""
    valid = runs[0][0]
    lost = [v - p for v, p, _ in runs]
    growth = [g for _, _, g in runs]
    span = f"{min(lost):,}" if min(lost) == max(lost) else f"{min(lost):,}-{max(lost):,}"
    pct = f"{100.0 * min(lost) / valid:.1f}-{100.0 * max(lost) / valid:.1f} %"
    record(
        __file__,
        figure=f"{offered:,} frames offered at {rate:,.0f}/s with {100.0 * corrupt:g} % damaged "
        f"packets, {len(runs)} runs: {span} of {valid:,} valid frames lost ({pct}; target none "
        f"{'met' if max(lost) == 0 else 'missed'}), RSS {min(growth):+.1f} to "
        f"{max(growth):+.1f} MB after 2 s of traffic (target < 10 MB "
        f"{'met' if max(growth) < 10.0 else 'missed'})",
        ratio="the targets themselves (every valid frame, < 10 MB growth); the live path "
        "before grew about 110 bytes a frame with a contact held (an earlier session's "
        "figure, not re-measured)",
        measured={
            "offered": offered,
            "rate_frames_s": rate,
            "valid": valid,
            "processed": [p for _, p, _ in runs],
            "rss_growth_mb": growth,
        },
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--frames", type=int, default=1_000_000)
    ap.add_argument("--rate", type=float, default=50_000.0, help="frames/s offered")
    ap.add_argument("--corrupt", type=float, default=0.01, help="fraction of damaged packets")
    ap.add_argument("--scenarios", type=int, default=12)
    ap.add_argument("--runs", type=int, default=3, help="soaks in a row (the row gives the range)")
    add_record_option(ap)
    args = ap.parse_args()
    frames = base_block(args.scenarios)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "packets.bin"
        damaged = write_packets(path, frames, args.rate, args.frames, args.corrupt)
        del frames
        runs = [soak(path, args.rate, damaged) for _ in range(max(1, args.runs))]
    if args.record:
        record_row(runs, args.frames, args.rate, args.corrupt)


if __name__ == "__main__":
    main()
