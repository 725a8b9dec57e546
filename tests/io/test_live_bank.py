"""``recognize --live ... --arrays N``: one stream carrying many arrays, recognised in a bank."""

from __future__ import annotations

import socket
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from taxelkit.cli.live import EXIT_OK, format_event, recognize_live
from taxelkit.errors import InputError
from taxelkit.frames import TactileFrames
from taxelkit.io.frame_protocol import encode_frame
from taxelkit.smart.recogniser import recognise

PITCH_MM = 1.7625
RATE_HZ = 20.0


def moving_contacts(seed: int, n_frames: int) -> np.ndarray:
    """A 16 x 16 stream: bars and blobs that appear, move and lift, at random."""
    rng = np.random.default_rng(seed)
    frames = np.zeros((n_frames, 16, 16), bool)
    j = int(rng.integers(0, 15))
    while j < n_frames:
        length, width = int(rng.integers(20, 80)), int(rng.integers(1, 4))
        row, col, step = int(rng.integers(2, 12)), int(rng.integers(1, 6)), int(rng.integers(0, 2))
        for k in range(j, min(n_frames, j + length)):
            c = min(col + step * (k - j) // 6, 12)
            frames[k, row : row + width, c : c + 4] = True
        j += length + int(rng.integers(5, 30))
    return frames


def interleaved(streams: list[np.ndarray]) -> bytes:
    """Version 2 packets, one frame of each array in turn, each array counting its own frames."""
    out = bytearray()
    for j in range(streams[0].shape[0]):
        for k, frames in enumerate(streams):
            out += encode_frame(frames[j], index=j, t_s=j / RATE_HZ, array_id=k)
    return bytes(out)


def own_events(k: int, frames: np.ndarray) -> list[str]:
    """The lines array ``k`` should print: ``recognise`` of its frames alone, at 20 frames/s."""
    t_s = np.arange(frames.shape[0]) / RATE_HZ
    want = recognise(TactileFrames(frames, t_s, pitch_mm=PITCH_MM))
    return [f"array {k}: {format_event(e, e.frame, t_s[e.frame])}" for e in want.events]


def printed(lines: list[str], k: int) -> list[str]:
    """The event lines of array ``k`` (the summary left out)."""
    return [line for line in lines[:-1] if line.startswith(f"array {k}: ")]


def test_each_array_gets_the_events_of_its_own_recording(tmp_path: Path) -> None:
    streams = [moving_contacts(seed, 240) for seed in range(4)]
    path = tmp_path / "bank.bin"
    path.write_bytes(interleaved(streams))
    lines: list[str] = []
    code = recognize_live(f"file:{path}", pitch_mm=PITCH_MM, arrays=4, echo=lines.append)
    assert code == EXIT_OK
    for k, frames in enumerate(streams):
        expected = own_events(k, frames)
        assert printed(lines, k) == expected, k
        assert len(expected) > 2
    assert lines[-1].startswith("end of stream: 960 frames processed from 4 arrays, ")


def test_frames_of_unknown_arrays_and_late_frames_are_counted(tmp_path: Path) -> None:
    blank = np.zeros((16, 16), bool)
    packets = [encode_frame(blank, index=j // 3, t_s=j * 0.05, array_id=j % 3) for j in range(30)]
    packets.append(encode_frame(blank, index=99, t_s=0.0, array_id=1))  # back in time
    path = tmp_path / "odd.bin"
    path.write_bytes(b"".join(packets))
    lines: list[str] = []
    recognize_live(f"file:{path}", pitch_mm=PITCH_MM, arrays=2, echo=lines.append)
    assert lines[-1].startswith(
        "end of stream: 20 frames processed from 2 arrays, 10 of array ids >= 2, "
        "1 out of time order, "
    ), lines[-1]
    one: list[str] = []
    recognize_live(f"file:{path}", pitch_mm=PITCH_MM, echo=one.append)  # one array: array 0
    assert ", 21 of array ids > 0 (use --arrays)" in one[-1]
    assert one[-1].startswith("end of stream: 10 frames processed")


def test_a_frame_lost_on_the_way_is_filled_and_holds_no_array_back(tmp_path: Path) -> None:
    streams = [moving_contacts(seed, 240) for seed in range(2)]
    packets = []
    for j in range(240):
        for k, frames in enumerate(streams):
            if not (k == 1 and 100 <= j < 103):  # three datagrams of array 1 lost
                packets.append(encode_frame(frames[j], index=j, t_s=j / RATE_HZ, array_id=k))
    path = tmp_path / "lossy.bin"
    path.write_bytes(b"".join(packets))
    lines: list[str] = []
    recognize_live(f"file:{path}", pitch_mm=PITCH_MM, arrays=2, echo=lines.append)
    assert lines[-1].startswith(
        "end of stream: 480 frames processed from 2 arrays, 3 repeated for missing frames, "
    ), lines[-1]
    assert printed(lines, 0) == own_events(0, streams[0])
    held = streams[1].copy()
    held[100:103] = held[99]  # what array 1 was recognised from: its frame 99 held
    assert printed(lines, 1) == own_events(1, held)


def test_arrays_is_checked_and_takes_no_recording(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="arrays must be in"):
        recognize_live("udp:127.0.0.1:0", pitch_mm=1.0, arrays=0, echo=print)
    with pytest.raises(InputError, match="not with --arrays"):
        recognize_live(
            "udp:127.0.0.1:0", pitch_mm=1.0, arrays=2, record=tmp_path / "r.h5", echo=print
        )


def test_a_bank_over_udp_on_the_loopback() -> None:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        port = int(s.getsockname()[1])
    streams = [moving_contacts(seed, 100) for seed in range(3)]
    stop = threading.Event()

    def send() -> None:  # cycles until stopped: datagrams sent before the bind are lost
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as out:
            cycle = 0
            while not stop.is_set() and cycle < 200:
                for j in range(100):
                    for k, frames in enumerate(streams):
                        n = cycle * 100 + j
                        packet = encode_frame(frames[j], index=n, t_s=n / 240, array_id=k)
                        out.sendto(packet, ("127.0.0.1", port))
                    if j % 10 == 0:
                        stop.wait(0.002)
                cycle += 1

    sender = threading.Thread(target=send, daemon=True)
    sender.start()
    lines: list[str] = []
    try:
        code = recognize_live(
            f"udp:127.0.0.1:{port}", pitch_mm=PITCH_MM, arrays=3, max_frames=900,
            timeout_s=5.0, echo=lines.append,
        )  # fmt: skip
    finally:
        stop.set()
        sender.join(5.0)
    assert code == EXIT_OK
    assert lines[-1].startswith("stopped after 900 frames: ")
    assert " frames processed from 3 arrays" in lines[-1]
    assert {line.split(":")[0] for line in lines[:-1]} <= {"array 0", "array 1", "array 2"}
    assert any(line.startswith("array ") for line in lines[:-1])


@pytest.mark.parametrize("process", [False, True])
def test_background_receiver_counts_what_its_full_queue_drops(process: bool) -> None:
    from taxelkit.io.live_transports import UdpSource
    from taxelkit.io.udp_receiver import BackgroundReceiver

    blank = np.zeros((4, 4), bool)
    with BackgroundReceiver(UdpSource("127.0.0.1", 0), max_queued=10, process=process) as src:
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as out:
            for j in range(100):
                out.sendto(encode_frame(blank, index=j, t_s=j * 0.01), src.source.address)
        got = 0
        deadline = time.monotonic() + 5.0
        while got + src.dropped < 100 and time.monotonic() < deadline:
            got += sum(b.n_frames for b in src.poll_batches(0.05))
    assert got + src.dropped == 100 and src.dropped > 0
    assert src.stats.frames == got


def test_the_receiver_process_passes_every_datagram_in_order_and_ends_with_close() -> None:
    from taxelkit.io.live_transports import UdpSource
    from taxelkit.io.udp_receiver import BackgroundReceiver

    frames = np.random.default_rng(3).random((500, 4, 4)) < 0.5
    src = BackgroundReceiver(UdpSource("127.0.0.1", 0), process=True)
    proc = src._proc
    with src, socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as out:
        for j, f in enumerate(frames):
            out.sendto(encode_frame(f, index=j, t_s=j * 0.01), src.source.address)
        batches = []
        deadline = time.monotonic() + 5.0
        while sum(b.n_frames for b in batches) < 500 and time.monotonic() < deadline:
            batches += src.poll_batches(0.05)
    assert np.concatenate([b.index for b in batches]).tolist() == list(range(500))
    np.testing.assert_array_equal(np.concatenate([b.values for b in batches]), frames)
    assert src.dropped == 0 and not proc.is_alive()
