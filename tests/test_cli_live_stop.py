"""``taxelkit recognize --live``: clean stops on SIGINT and SIGTERM, a valid --record file,
and memory that does not grow over a long stream with damaged packets."""

from __future__ import annotations

import os
import queue
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from taxelkit.cli.live import EXIT_INTERRUPTED, EXIT_TERMINATED, recognize_live
from taxelkit.io.frame_protocol import encode_frame
from taxelkit.io.recordings import read_recording

PITCH_MM = 1.7625

pytestmark = pytest.mark.skipif(os.name != "posix", reason="POSIX signals and /proc")


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _touch(n: int) -> np.ndarray:
    frames = np.zeros((n, 16, 16), bool)
    frames[n // 5 : 4 * n // 5, 7:9, 7:9] = True  # a point contact, then lift-off
    return frames


@pytest.mark.parametrize(("sig", "code", "why"), [
    (signal.SIGINT, EXIT_INTERRUPTED, "interrupted"),
    (signal.SIGTERM, EXIT_TERMINATED, "terminated"),
])  # fmt: skip
def test_a_signal_ends_a_waiting_live_run_with_its_summary_and_recording(
    tmp_path: Path, sig: signal.Signals, code: int, why: str
) -> None:
    port = _free_port()
    record = tmp_path / "live.h5"
    proc = subprocess.Popen(
        [sys.executable, "-m", "taxelkit", "recognize", "--live", f"udp:127.0.0.1:{port}",
         "--pitch-mm", str(PITCH_MM), "--timeout-s", "60", "--record", str(record)],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_IGN),  # as a shell's `cmd &`
    )  # fmt: skip
    assert proc.stdout is not None
    lines: queue.Queue[str] = queue.Queue()
    reader = threading.Thread(target=lambda: [lines.put(x) for x in proc.stdout], daemon=True)
    reader.start()
    frames = _touch(100)
    seen: list[str] = []
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as out:
        deadline, sent = time.monotonic() + 20, 0
        while not any("contact point" in x for x in seen) and time.monotonic() < deadline:
            for f in frames:  # until the run is up and has seen the contact
                out.sendto(encode_frame(f, index=sent, t_s=0.01 * sent), ("127.0.0.1", port))
                sent += 1
            time.sleep(0.2)
            while not lines.empty():
                seen.append(lines.get())
    assert any("contact point" in x for x in seen), seen
    time.sleep(0.3)  # the run now waits for data
    t0 = time.monotonic()
    proc.send_signal(sig)
    proc.wait(timeout=10)
    assert time.monotonic() - t0 < 2.0  # at once, not after --timeout-s
    reader.join(5)
    assert proc.stderr is not None
    assert proc.returncode == code, proc.stderr.read()
    while not lines.empty():
        seen.append(lines.get())
    summary = seen[-1].strip()
    assert summary.startswith(f"{why}: "), summary
    processed = int(summary.split(": ")[1].split()[0])
    assert f"{processed} frames recorded to {record}" in summary
    rec = read_recording(record)
    assert rec.n_frames == processed and rec.is_contact and rec.pitch_mm == PITCH_MM
    assert sorted(p.name for p in tmp_path.iterdir()) == ["live.h5"]  # no temporary file


def _rss_bytes() -> int:
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def test_memory_stays_flat_over_a_stream_with_damaged_packets() -> None:
    """60,000 frames (a contact held, lifted, held again) with 1 % of packets damaged."""
    n, port = 60_000, _free_port()
    frames = _touch(1_000)
    rng = np.random.default_rng(0)
    packets = [encode_frame(frames[i % 1000], index=i, t_s=i / 240) for i in range(n)]
    damaged = set(rng.choice(n, size=n // 100, replace=False).tolist())
    for i in damaged:
        raw = bytearray(packets[i])
        raw[30] ^= 0xFF  # a payload byte: the CRC no longer matches
        packets[i] = bytes(raw)
    rss: list[int] = []
    lines: list[str] = []

    def send() -> None:
        time.sleep(0.5)
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as out:
            start = time.monotonic()
            for i, p in enumerate(packets):
                if i % 1000 == 0:
                    rss.append(_rss_bytes())
                    while time.monotonic() - start < i / 25_000:  # 25,000 frames/s
                        time.sleep(0.001)
                out.sendto(p, ("127.0.0.1", port))

    sender = threading.Thread(target=send)
    sender.start()
    code = recognize_live(
        f"udp:127.0.0.1:{port}", pitch_mm=PITCH_MM, timeout_s=2.0, echo=lines.append
    )
    sender.join()
    assert code == 0
    summary = lines[-1]
    assert f"{n - len(damaged)} frames processed" in summary, summary
    assert f"damaged packets skipped: {len(damaged)}" in summary
    growth = max(rss[len(rss) // 3 :]) - rss[len(rss) // 3]
    assert growth < 10 * 2**20, f"RSS grew {growth / 2**20:.1f} MiB"
