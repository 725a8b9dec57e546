"""Shared by the live benchmarks: a paced UDP sender in its own process, and a measured receiver.

The sender (a subprocess, so that it does not share the receiver's core or
interpreter lock) sends pre-encoded packets at a fixed rate, catching up in
bursts every millisecond. The receiver is ``recognize_live`` (the code of
``taxelkit recognize --live udp:...``) in this process; a thread samples its
resident memory (``/proc/self/statm``) every 0.1 s.
"""

from __future__ import annotations

import os
import re
import socket
import subprocess
import sys
import threading
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from taxelkit.cli.live import recognize_live
from taxelkit.io.frame_protocol import encode_frame, packet_size

_SENDER = """
import socket, sys, time
path, port, rate, n, size = sys.argv[1], *map(float, sys.argv[2:])
port, n, size = int(port), int(n), int(size)
data = open(path, "rb").read()
count = len(data) // size
view = memoryview(data)  # packets cut as they are sent: a long file starts at once
out = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
out.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, 4 << 20)
address = ("127.0.0.1", port)
time.sleep(1.0)  # the receiver binds meanwhile
start = time.perf_counter()
sent = 0
while sent < n:
    due = min(n, int((time.perf_counter() - start) * rate) + 1)
    while sent < due:
        i = sent % count
        out.sendto(view[i * size:(i + 1) * size], address)
        sent += 1
    time.sleep(0.0005)
print(time.perf_counter() - start, flush=True)
"""


@dataclass(frozen=True)
class LiveRun:
    """What one measured live run saw."""

    sent: int
    processed: int  # frames received and recognised (a bank's repeats of missing ones left out)
    summary: str
    send_s: float
    rss_mb: tuple[float, ...]


def free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def write_packets(
    path: Path,
    frames: np.ndarray,
    rate_hz: float,
    n_packets: int,
    corrupt: float,
    seed: int = 0,
    arrays: int = 1,
) -> int:
    """Write ``n_packets`` packets cycling through ``frames``, a fraction damaged (bad CRC).

    With ``arrays > 1``: version 2 packets, one frame of each array in turn
    (each at ``rate_hz / arrays``, its own frame count as index), array ``k``
    playing ``frames`` from its own offset. Returns the number damaged.
    """
    rng = np.random.default_rng(seed)
    bad = np.zeros(n_packets, bool)
    bad[rng.choice(n_packets, size=round(corrupt * n_packets), replace=False)] = True
    with path.open("wb") as out:
        block = bytearray()
        for i in range(n_packets):
            if arrays == 1:
                raw = bytearray(encode_frame(frames[i % len(frames)], index=i, t_s=i / rate_hz))
            else:
                k, j = i % arrays, i // arrays
                raw = bytearray(
                    encode_frame(
                        frames[(j + 997 * k) % len(frames)],
                        index=j,
                        t_s=j * arrays / rate_hz,
                        array_id=k,
                    )
                )
            if bad[i]:
                raw[30] ^= 0xFF  # a payload byte: the CRC no longer matches
            block += raw
            if len(block) > 2**24:
                out.write(block)
                block = bytearray()
        out.write(block)
    return int(bad.sum())


def rss_mb() -> float:
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def run_live(path: Path, rate_hz: float, shape: tuple[int, int], arrays: int = 1) -> LiveRun:
    """Send the packets of ``path`` at ``rate_hz`` from a subprocess into ``recognize_live``."""
    size = packet_size(*shape, 0, version=1 if arrays == 1 else 2)
    n = path.stat().st_size // size
    port = free_port()
    lines: list[str] = []
    rss: list[float] = []
    done = threading.Event()

    def sample() -> None:
        while not done.wait(0.1):
            rss.append(rss_mb())

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    sender = subprocess.Popen(
        [sys.executable, "-c", _SENDER, str(path), str(port), str(rate_hz), str(n), str(size)],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        recognize_live(
            f"udp:127.0.0.1:{port}",
            pitch_mm=1.7625,
            timeout_s=3.0,
            echo=lines.append,
            arrays=arrays,
        )
    finally:
        out, _ = sender.communicate(timeout=120)
        done.set()
        sampler.join()
    summary = lines[-1]
    processed = int(summary.split(": ")[1].split()[0])
    repeats = re.search(r"(\d+) repeated for missing frames", summary)
    if repeats:  # a bank fills the frames lost on the way: they were not received
        processed -= int(repeats.group(1))
    return LiveRun(n, processed, summary, float(out.strip()), tuple(rss))
