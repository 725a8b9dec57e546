"""Live sources over a pseudo-terminal and loopback UDP, driven by the simulated device.

Everything stays on this machine (pipes, pseudo-terminals, 127.0.0.1) and
every wait is bounded.
"""

from __future__ import annotations

import importlib.util
import os
import socket
import sys
import time
from collections.abc import Callable

import numpy as np
import pytest

from taxelkit.cli.live import EXIT_OK, recognize_live
from taxelkit.errors import InputError, TaxelkitError
from taxelkit.io.frame_protocol import DecodedFrame, FrameDecoder, PayloadType, encode_frame
from taxelkit.io.live_device import SimulatedDevice, open_pseudo_terminal
from taxelkit.io.live_sources import (
    DEFAULT_BAUD,
    ByteStreamSource,
    FrameSource,
    LiveDependencyError,
    LiveSourceError,
    LiveTimeoutError,
    SourceSpec,
    SourceSpecError,
    open_source,
    parse_source,
)
from taxelkit.io.live_transports import SerialSource, UdpSource
from taxelkit.smart.recogniser import SmartSensor

HAS_PYSERIAL = importlib.util.find_spec("serial") is not None
needs_pyserial = pytest.mark.skipif(not HAS_PYSERIAL, reason="pyserial is not installed")
needs_pty = pytest.mark.skipif(not hasattr(os, "openpty"), reason="no pseudo-terminals")

#: Pitch of the Bonneville preset, mm: a 2 x 2 blob is then a point contact.
PITCH_MM = 1.7625
#: Hard limit on any reading loop of these tests, s.
LOOP_LIMIT_S = 30.0


def touches(n_frames: int, shape: tuple[int, int] = (16, 16), period: int = 50) -> np.ndarray:
    """Bool frames: a 2 x 2 point contact that slides down for 35 frames of every ``period``."""
    frames = np.zeros((n_frames, *shape), bool)
    phase = np.arange(n_frames) % period
    for t in np.flatnonzero((phase >= 10) & (phase < 45)):
        row = 3 + (phase[t] - 10) // 4
        frames[t, row : row + 2, 7:9] = True
    return frames


def free_udp_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def drain(
    src: FrameSource, device: SimulatedDevice, on_frame: Callable[[DecodedFrame], None]
) -> None:
    """Read until the device has finished and the source has gone quiet (bounded)."""
    deadline = time.monotonic() + LOOP_LIMIT_S
    while time.monotonic() < deadline:
        finished = device.finished
        before = src.stats.bytes_received
        for frame in src.poll(0.1):
            on_frame(frame)
        if finished and src.stats.bytes_received == before:
            return
    pytest.fail("the source did not go quiet in time")


def damage_counts(device: SimulatedDevice) -> dict[str, int]:
    counts = {"flip": 0, "truncate": 0, "drop": 0}
    for c in device.corruptions:
        counts[c.kind] += 1
    return counts


# ----------------------------------------------------------------------------- SOURCE strings
@pytest.mark.parametrize(
    ("text", "spec"),
    [
        ("serial:/dev/ttyUSB0", SourceSpec("serial", "/dev/ttyUSB0", baud=DEFAULT_BAUD)),
        ("serial:/dev/ttyACM0@921600", SourceSpec("serial", "/dev/ttyACM0", baud=921600)),
        ("serial:COM3@9600", SourceSpec("serial", "COM3", baud=9600)),
        ("udp:127.0.0.1:9000", SourceSpec("udp", "127.0.0.1", port=9000)),
        ("udp:0.0.0.0:0", SourceSpec("udp", "0.0.0.0", port=0)),
        ("udp:[::1]:9000", SourceSpec("udp", "::1", port=9000)),
        ("UDP:localhost:65535", SourceSpec("udp", "localhost", port=65535)),
    ],
)
def test_source_strings_parse(text: str, spec: SourceSpec) -> None:
    assert parse_source(text) == spec
    assert parse_source(str(spec)) == spec


@pytest.mark.parametrize(
    "text",
    ["", "ttyUSB0", "tcp:host:1", "serial:", "serial:/dev/ttyUSB0@", "serial:/dev/x@fast",
     "serial:@9600", "serial:/dev/tty USB0", "udp:9000", "udp:host:", "udp:host:70000",
     "udp::9000", "udp:host:-1", "udp:host:9000\nrm -rf"],
)  # fmt: skip
def test_bad_source_strings_give_a_one_line_typed_error(text: str) -> None:
    with pytest.raises(SourceSpecError) as info:
        parse_source(text)
    message = str(info.value)
    assert "\n" not in message
    assert "serial:PORT[@BAUD] or udp:HOST:PORT" in message and repr(text) in message
    assert isinstance(info.value, InputError) and isinstance(info.value, TaxelkitError)


# ----------------------------------------------------------------------------- byte streams
def test_byte_stream_source_reads_a_pipe_to_its_end() -> None:
    frames = touches(30, (4, 6))
    r, w = os.pipe()
    data = b"noise" + b"".join(encode_frame(f, index=i, t_s=i) for i, f in enumerate(frames))
    with ByteStreamSource(r, close_fd=True) as src:
        os.write(w, data[:1000])
        os.write(w, data[1000:])
        os.close(w)
        got = list(src.frames(idle_timeout_s=5.0))
    assert src.at_end and [f.index for f in got] == list(range(30))
    np.testing.assert_array_equal(np.stack([f.values for f in got]), frames)
    assert src.stats.bytes_skipped == 5 and src.stats.corrupted == 0
    assert src.description == f"fd:{r}"


def test_consecutive_frame_iterations_see_every_frame_once() -> None:
    r, w = os.pipe()
    os.write(w, b"".join(encode_frame(np.ones((2, 2), bool), index=i, t_s=i) for i in range(10)))
    os.close(w)
    with ByteStreamSource(r, close_fd=True) as src:
        first = [f.index for f in src.frames(max_frames=3)]  # one read decodes all ten
        second = [f.index for f in src.frames(max_frames=3)]
        rest = [f.index for f in src.frames()]
    assert (first, second, rest) == ([0, 1, 2], [3, 4, 5], [6, 7, 8, 9])


def test_idle_timeout_names_the_source_and_its_counts() -> None:
    r, w = os.pipe()
    try:
        with ByteStreamSource(r, description="test-pipe") as src:
            os.write(w, b"\x00" * 17)
            t0 = time.monotonic()
            with pytest.raises(LiveTimeoutError, match=r"test-pipe for 0.2 s \(17 bytes"):
                next(src.frames(idle_timeout_s=0.2))
            assert 0.15 < time.monotonic() - t0 < 2.0
    finally:
        os.close(r)
        os.close(w)


@needs_pty
def test_ten_thousand_frames_over_a_pseudo_terminal_into_the_smart_sensor() -> None:
    n = 10_000
    frames = touches(n)
    # stamped at 20 Hz: each touch lasts 1.75 s, well above the recogniser's time-based debounce
    device = SimulatedDevice(frames, np.arange(n) / 20.0, corrupt_fraction=0.02, rng=7)
    damage = damage_counts(device)
    assert sum(damage.values()) == 200 and min(damage.values()) > 0
    damaged = {c.index for c in device.corruptions}
    sensor = SmartSensor((16, 16), pitch_mm=PITCH_MM)
    received: list[int] = []
    events = []

    def on_frame(f: DecodedFrame) -> None:
        received.append(f.index)
        assert np.array_equal(f.values, frames[f.index])
        events.extend(sensor.push(f.values, f.t_s))

    with open_pseudo_terminal() as pty, ByteStreamSource(pty.slave_fd, shape=(16, 16)) as src:
        device.start_fd(pty.master_fd)
        drain(src, device, on_frame)
        leftover = src.decoder.flush()
    assert leftover == []
    assert device.completed and device.error is None
    # every intact frame arrived, in order, and nothing else did:
    assert received == [i for i in range(n) if i not in damaged]
    assert sensor.frame_index == n - 200
    s = src.stats
    assert s.frames == n - 200
    assert s.corrupted == damage["flip"] + damage["truncate"]  # drops leave no trace ...
    assert s.missing == 200  # ... but the index gaps show every lost frame
    assert sum(e.kind == "contact" for e in events) >= 150  # 200 touches, a few damaged
    assert sensor.result().classes.size == n - 200


@needs_pty
@needs_pyserial
def test_pyserial_reads_the_pseudo_terminal() -> None:
    n = 2_000
    frames = touches(n, (8, 12))
    device = SimulatedDevice(frames, corrupt_fraction=0.02, corruption_kinds=("flip",), rng=3)
    damaged = {c.index for c in device.corruptions}
    with open_pseudo_terminal() as pty:
        src = open_source(f"serial:{pty.slave_name}@921600")
        assert isinstance(src, SerialSource)
        with src:
            device.start_fd(pty.master_fd)
            got: list[int] = []
            drain(src, device, lambda f: got.append(f.index))
    assert got == [i for i in range(n) if i not in damaged]
    assert src.stats.corrupted == 40 and src.stats.bad_header + src.stats.bad_crc == 40


@needs_pyserial
def test_a_missing_serial_port_is_a_one_line_error() -> None:
    with pytest.raises(LiveSourceError, match=r"cannot open serial:/nonexistent/ttyX@115200") as e:
        SerialSource("/nonexistent/ttyX")
    assert "\n" not in str(e.value)


def test_serial_without_pyserial_tells_how_to_install_it(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "serial", None)  # import serial -> ImportError
    with pytest.raises(LiveDependencyError) as e:
        open_source("serial:/dev/ttyUSB0")
    assert 'pip install "taxelkit[live]"' in str(e.value) and "\n" not in str(e.value)
    assert isinstance(e.value, TaxelkitError) and isinstance(e.value, ImportError)


# ----------------------------------------------------------------------------- UDP
def test_udp_loopback_with_damaged_packets() -> None:
    n = 2_000
    frames = touches(n, (16, 16))
    device = SimulatedDevice(frames, corrupt_fraction=0.02, interval_s=1e-4, rng=11)
    damage = damage_counts(device)
    damaged = {c.index for c in device.corruptions}
    got: list[int] = []

    def on_frame(f: DecodedFrame) -> None:
        got.append(f.index)
        assert np.array_equal(f.values, frames[f.index])

    with UdpSource("127.0.0.1", 0, shape=(16, 16)) as src:
        assert src.address[0] == "127.0.0.1" and src.address[1] > 0
        device.start_udp(src.address)
        drain(src, device, on_frame)
    assert device.completed and device.error is None
    s = src.stats
    sent = n - damage["drop"]
    lost = sent - (s.frames + s.corrupted)  # each datagram is one frame or one damaged packet
    assert 0 <= lost <= n // 20, f"loopback lost {lost} of {sent} datagrams"
    assert set(got) <= set(range(n)) - damaged and got == sorted(got)
    assert s.frames + s.missing == got[-1] - got[0] + 1
    if lost == 0:  # the usual case on loopback: then everything is exact
        assert got == [i for i in range(n) if i not in damaged]
        assert s.corrupted == damage["flip"] + damage["truncate"]


def test_udp_port_in_use_is_a_one_line_error() -> None:
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as taken:
        taken.bind(("127.0.0.1", 0))
        port = taken.getsockname()[1]
        with pytest.raises(LiveSourceError, match=f"cannot listen on udp:127.0.0.1:{port}"):
            UdpSource("127.0.0.1", port)


# ----------------------------------------------------------------------------- the device
def test_device_damage_plan_is_seeded() -> None:
    frames = touches(500, (4, 4))
    a = SimulatedDevice(frames, corrupt_fraction=0.1, rng=5)
    b = SimulatedDevice(frames, corrupt_fraction=0.1, rng=5)
    c = SimulatedDevice(frames, corrupt_fraction=0.1, rng=6)
    assert a.corruptions == b.corruptions != c.corruptions
    assert len(a.corruptions) == 50
    assert [a.packet(k) for k in range(500)] == [b.packet(k) for k in range(500)]
    kinds = {x.kind for x in a.corruptions}
    assert kinds == {"flip", "truncate", "drop"}
    for x in a.corruptions:
        clean = encode_frame(frames[x.packet], index=x.index, t_s=float(x.packet))
        sent = a.packet(x.packet)
        if x.kind == "drop":
            assert sent == b""
        elif x.kind == "truncate":
            assert 4 <= len(sent) < len(clean) and clean.startswith(sent)
        else:
            assert len(sent) == len(clean) and sent[:4] == clean[:4] and sent != clean


def test_device_cycles_keep_counting() -> None:
    device = SimulatedDevice(np.zeros((3, 2, 2)), [0.0, 0.5, 1.0], cycles=2, start_index=2**32 - 2)
    dec = [decode_one(device.packet(k)) for k in range(device.n_packets)]
    assert [f.index for f in dec] == [2**32 - 2, 2**32 - 1, 0, 1, 2, 3]
    assert [f.t_s for f in dec] == [0.0, 0.5, 1.0, 1.5, 2.0, 2.5]
    assert dec[0].payload_type == PayloadType.FLOAT32


def decode_one(packet: bytes) -> DecodedFrame:
    frame = FrameDecoder().decode_datagram(packet)
    assert frame is not None
    return frame


@needs_pty
def test_device_stops_by_itself_when_nobody_reads() -> None:
    device = SimulatedDevice(np.ones((2_000, 64, 64), bool), max_duration_s=0.3)
    with open_pseudo_terminal() as pty:
        t0 = time.monotonic()
        device.start_fd(pty.master_fd)
        assert device.join(5.0)
        assert time.monotonic() - t0 < 2.0
    assert not device.completed and device.packets_done < device.n_packets
    with pytest.raises(LiveSourceError, match="only once"):
        device.start_udp(("127.0.0.1", 9))


def test_device_stop_ends_a_paced_transmission() -> None:
    device = SimulatedDevice(np.ones((100, 2, 2), bool), interval_s=0.05, max_duration_s=20)
    device.start_udp(("127.0.0.1", free_udp_port()))
    time.sleep(0.1)
    device.stop()
    assert device.join(2.0) and not device.completed


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"corrupt_fraction": 1.5}, "corrupt_fraction"),
        ({"corruption_kinds": ("melt",)}, "corruption_kinds"),
        ({"cycles": 0}, "cycles"),
        ({"interval_s": -1.0}, "interval_s"),
        ({"t_s": [0.0]}, "t_s"),
    ],
)
def test_device_validates_its_parameters(kwargs: dict[str, object], match: str) -> None:
    with pytest.raises(InputError, match=match):
        SimulatedDevice(np.zeros((2, 2, 2), bool), **kwargs)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="frames"):
        SimulatedDevice(np.zeros((2, 2), bool))


# ----------------------------------------------------------------------------- recognize --live
def test_recognize_live_over_udp_prints_events_and_stops_after_max_frames() -> None:
    frames = np.zeros((20, 16, 16), bool)
    frames[5:15, 7:9, 7:9] = True  # a 2 x 2 blob: a point contact, then lift-off
    port = free_udp_port()
    device = SimulatedDevice(frames, np.arange(20) * 0.05, cycles=200, interval_s=0.002)
    device.start_udp(("127.0.0.1", port))  # cycles: frames sent before the bind do not matter
    lines: list[str] = []
    try:
        code = recognize_live(
            f"udp:127.0.0.1:{port}", pitch_mm=PITCH_MM, max_frames=60, timeout_s=5.0,
            echo=lines.append,
        )  # fmt: skip
    finally:
        device.stop()
        device.join(2.0)
    assert code == EXIT_OK
    assert any(line.endswith("contact point") for line in lines), lines
    assert any(" tacteme PC" in line for line in lines)
    assert lines[-1].startswith("stopped after 60 frames: 60 frames processed")
    assert all("\n" not in line for line in lines)


def test_recognize_live_with_a_bad_source_string() -> None:
    with pytest.raises(SourceSpecError, match=r"got 'usb0'$"):
        recognize_live("usb0", pitch_mm=1.0, echo=print)


def test_recognize_live_needs_a_pitch() -> None:
    with pytest.raises(InputError, match="--pitch-mm is required"):
        recognize_live("udp:127.0.0.1:0", pitch_mm=None, echo=print)
    with pytest.raises(InputError, match="pitch_mm must be finite and > 0"):
        recognize_live("udp:127.0.0.1:0", pitch_mm=-1.0, echo=print)


def test_recognize_live_times_out_when_nothing_arrives() -> None:
    lines: list[str] = []
    with pytest.raises(LiveTimeoutError, match=r"no frame from udp:127\.0\.0\.1:"):
        recognize_live(
            f"udp:127.0.0.1:{free_udp_port()}", pitch_mm=1.0, timeout_s=0.3, echo=lines.append
        )
    assert lines == []


@needs_pty
@needs_pyserial
def test_recognize_live_on_a_serial_port_with_raw_counts() -> None:
    counts = np.full((30, 8, 8), 100, np.uint16)
    counts[5:25, 3:5, 3:5] = 3000  # a point contact in raw counts
    lines: list[str] = []

    def device() -> SimulatedDevice:  # keeps sending: pyserial flushes its input on opening
        return SimulatedDevice(counts, np.arange(30) * 0.02, cycles=100, interval_s=0.002)

    with open_pseudo_terminal() as pty:
        source = f"serial:{pty.slave_name}"
        first, second = device(), device()
        first.start_fd(pty.master_fd)
        try:
            with pytest.raises(InputError, match="threshold in counts"):
                recognize_live(source, pitch_mm=PITCH_MM, max_frames=30, echo=lines.append)
        finally:
            first.stop()
            first.join(2.0)
        second.start_fd(pty.master_fd)
        try:
            code = recognize_live(
                source, pitch_mm=PITCH_MM, threshold=1000, max_frames=90, echo=lines.append
            )
        finally:
            second.stop()
            second.join(2.0)
    assert code == EXIT_OK
    kinds = [" ".join(line.split()[-2:]) for line in lines[:-1]]
    assert kinds.count("contact point") >= 2 and kinds.count("tacteme PC") >= 2
    assert lines[-1].startswith(
        "stopped after 90 frames: 90 frames processed, damaged packets skipped: 0,"
    )


def test_the_transports_are_still_found_under_their_old_module() -> None:
    import taxelkit.io.live_sources as old

    assert old.UdpSource is UdpSource and old.SerialSource is SerialSource
    with pytest.raises(AttributeError, match="no attribute 'Nothing'"):
        _ = old.Nothing
