"""A simulated tactile device for live streams: a pseudo-terminal or loopback UDP.

Tests and demos drive :func:`taxelkit.cli.live.recognize_live` end to end with
it: a background thread encodes frames with the documented protocol
(:mod:`taxelkit.io.frame_protocol`), optionally corrupts a seeded fraction of
packets, and writes them to a file descriptor (the master side of a
pseudo-terminal, standing in for a serial port) or sends them as UDP
datagrams. It is bounded in count and time and stops by itself.
"""

from __future__ import annotations

import contextlib
import os
import select
import socket
import threading
import time
from dataclasses import dataclass
from types import TracebackType
from typing import Any, Self

import numpy as np
from numpy.typing import ArrayLike

from taxelkit.errors import InputError, check_in_range, check_ndim, check_positive
from taxelkit.io.frame_protocol import (
    MAGIC,
    PayloadType,
    encode_frame,
    to_wire,
)
from taxelkit.io.live_sources import LiveSourceError, one_line_message

__all__ = [
    "CORRUPTION_KINDS",
    "Corruption",
    "PseudoTerminal",
    "SimulatedDevice",
    "open_pseudo_terminal",
]

CORRUPTION_KINDS = ("flip", "truncate", "drop")
#: Bytes gathered before one write to a stream when no pacing is asked for.
_WRITE_CHUNK_BYTES = 65_536
#: Longest single wait of the device thread, s: how quickly it notices stop() or its deadline.
_WAKE_S = 0.05


@dataclass(frozen=True)
class Corruption:
    """One packet the simulated device damages.

    Attributes
    ----------
    packet : int
        Position in the transmission, 0-based.
    index : int
        Frame index in the packet's header.
    kind : {"flip", "truncate", "drop"}
        ``flip``: one byte after the magic is XOR-ed with a nonzero value;
        ``truncate``: the packet is cut after the magic and before its end;
        ``drop``: the packet is not sent.
    """

    packet: int
    index: int
    kind: str


@dataclass(frozen=True)
class PseudoTerminal:
    """A pseudo-terminal pair in raw mode: write to ``master_fd``, read ``slave_fd``.

    ``slave_name`` (e.g. ``/dev/pts/3``) can be opened as a serial port.
    Close it only after the reader has drained it: closing the master drops
    bytes still buffered for the slave.
    """

    master_fd: int
    slave_fd: int
    slave_name: str

    def close(self) -> None:
        """Close both ends (idempotent)."""
        for fd in (self.master_fd, self.slave_fd):
            with contextlib.suppress(OSError):  # already closed
                os.close(fd)

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.close()


def open_pseudo_terminal() -> PseudoTerminal:
    """Open a pseudo-terminal pair with the slave in raw mode (binary-safe, no echo).

    Raises
    ------
    LiveSourceError
        On systems without pseudo-terminals (Windows).
    """
    try:
        import tty

        master, slave = os.openpty()
    except (ImportError, AttributeError, OSError) as e:
        raise LiveSourceError(f"cannot open a pseudo-terminal: {one_line_message(e)}") from e
    tty.setraw(slave)
    return PseudoTerminal(master, slave, os.ttyname(slave))


class SimulatedDevice:
    """A tactile sensor that sends frames in the live protocol from a background thread.

    Parameters
    ----------
    frames : (T, rows, cols) bool, integer or float
        Frames to send, in order.
    t_s : (T,) float, s, optional
        Their timestamps; default ``0, 1, 2, ...`` s.
    payload_type : PayloadType, optional
        Default from the dtype (see :func:`~taxelkit.io.frame_protocol.to_wire`).
    corrupt_fraction : float
        Fraction of packets to damage, in [0, 1]; exactly
        ``round(corrupt_fraction * n_packets)`` are chosen.
    corruption_kinds : sequence of {"flip", "truncate", "drop"}
        Damage drawn uniformly for each chosen packet.
    cycles : int
        Times to play the frames; indices keep counting and timestamps shift
        by one recording length per cycle.
    start_index : int
        Frame index of the first packet.
    interval_s : float
        Pace, s between packets; 0 sends as fast as the receiver takes them.
    max_duration_s : float
        The thread stops after this long whatever is left.
    rng : int, Generator or None
        Seed of the damage plan; same seed, same plan and same bytes.

    Attributes
    ----------
    corruptions : tuple of Corruption
        The damage plan, known before sending.
    n_packets : int
        ``T * cycles``.
    packets_done : int
        Packets written, damaged or dropped so far.
    error : OSError or None
        What stopped the thread early, if anything.
    """

    def __init__(
        self,
        frames: ArrayLike,
        t_s: ArrayLike | None = None,
        *,
        payload_type: PayloadType | int | None = None,
        corrupt_fraction: float = 0.0,
        corruption_kinds: tuple[str, ...] = CORRUPTION_KINDS,
        cycles: int = 1,
        start_index: int = 0,
        interval_s: float = 0.0,
        max_duration_s: float = 30.0,
        rng: int | np.random.Generator | None = None,
    ) -> None:
        arr = check_ndim("frames", frames, 3, "(T, rows, cols)")
        if arr.shape[0] < 1:
            raise InputError("frames must hold at least one frame, got 0")
        self._wire, self.payload_type = to_wire(arr, payload_type)
        n = int(arr.shape[0])
        times = np.arange(n, dtype=np.float64) if t_s is None else np.asarray(t_s, np.float64)
        if times.shape != (n,) or not np.all(np.isfinite(times)):
            raise InputError(f"t_s must be {n} finite timestamps, got shape {times.shape}")
        self._t_s = times
        self._period_s = float(times[-1] - times[0]) + (
            float(np.median(np.diff(times))) if n > 1 else 1.0
        )
        if int(cycles) < 1:
            raise InputError(f"cycles must be >= 1, got {cycles!r}")
        bad = [k for k in corruption_kinds if k not in CORRUPTION_KINDS]
        if bad or not corruption_kinds:
            raise InputError(
                f"corruption_kinds must be a non-empty subset of {CORRUPTION_KINDS}, "
                f"got {corruption_kinds!r}"
            )
        fraction = check_in_range("corrupt_fraction", corrupt_fraction, 0.0, 1.0)
        self.interval_s = check_positive("interval_s", interval_s, allow_zero=True)
        self.max_duration_s = check_positive("max_duration_s", max_duration_s)
        self.start_index = int(start_index)
        self.n_packets = n * int(cycles)
        gen = np.random.default_rng(rng)
        chosen = np.sort(
            gen.choice(self.n_packets, round(fraction * self.n_packets), replace=False)
        )
        kinds = gen.integers(0, len(corruption_kinds), chosen.size)
        where = gen.random((chosen.size, 2))
        self.corruptions = tuple(
            Corruption(int(p), self._index(int(p)), corruption_kinds[int(k)])
            for p, k in zip(chosen, kinds, strict=True)
        )
        self._damage = {
            c.packet: (c.kind, float(u), float(v))
            for c, (u, v) in zip(self.corruptions, where, strict=True)
        }
        self.packets_done = 0
        self.error: OSError | None = None
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def _index(self, packet: int) -> int:
        return (self.start_index + packet) % 2**32

    def packet(self, k: int) -> bytes:
        """Packet ``k`` of the transmission, as sent (damaged per the plan; b"" if dropped)."""
        n = self._wire.shape[0]
        t = float(self._t_s[k % n]) + (k // n) * self._period_s
        data = encode_frame(
            self._wire[k % n], index=self._index(k), t_s=t, payload_type=self.payload_type
        )
        if k not in self._damage:
            return data
        kind, u, v = self._damage[k]
        head = len(MAGIC)
        if kind == "drop":
            return b""
        if kind == "truncate":
            return data[: head + int(u * (len(data) - head))]
        damaged = bytearray(data)
        damaged[head + int(u * (len(data) - head))] ^= 1 + int(v * 255)
        return bytes(damaged)

    # -- running -----------------------------------------------------------------------
    @property
    def finished(self) -> bool:
        """The thread has ended (all sent, stopped, out of time, or failed)."""
        return self._thread is not None and not self._thread.is_alive()

    @property
    def completed(self) -> bool:
        """Every packet has been written (or dropped per the plan)."""
        return self.packets_done == self.n_packets

    def start_fd(self, fd: int) -> None:
        """Send to a writable descriptor, e.g. a pty master (it is made non-blocking)."""
        self._check_not_started()
        os.set_blocking(fd, False)
        self._start(self._run_stream, fd)

    def start_udp(self, address: tuple[str, int]) -> None:
        """Send one datagram per packet to ``(host, port)``."""
        self._check_not_started()
        family = socket.AF_INET6 if ":" in address[0] else socket.AF_INET
        self._start(self._run_udp, family, (address[0], int(address[1])))

    def _check_not_started(self) -> None:
        if self._thread is not None:
            raise LiveSourceError("a SimulatedDevice can be started only once")

    def _start(self, target: Any, *args: Any) -> None:
        self._deadline = time.monotonic() + self.max_duration_s
        self._thread = threading.Thread(target=target, args=args, daemon=True, name="taxelkit-sim")
        self._thread.start()

    def stop(self) -> None:
        """Ask the thread to stop; returns at once (use :meth:`join` to wait)."""
        self._stop.set()

    def join(self, timeout_s: float | None = None) -> bool:
        """Wait for the thread to end; True if it has."""
        if self._thread is not None:
            self._thread.join(timeout_s)
        return self.finished

    def _halted(self) -> bool:
        return self._stop.is_set() or time.monotonic() >= self._deadline

    def _pace(self, k: int, t0: float) -> bool:
        """Wait until packet ``k`` is due; False if told to stop meanwhile."""
        if self.interval_s > 0:
            delay = t0 + k * self.interval_s - time.monotonic()
            if delay > 0 and self._stop.wait(
                min(delay, max(0.0, self._deadline - time.monotonic()))
            ):
                return False
        return not self._halted()

    def _run_stream(self, fd: int) -> None:
        pending = bytearray()
        t0 = time.monotonic()
        try:
            for k in range(self.n_packets):
                if not self._pace(k, t0):
                    return
                pending += self.packet(k)
                if (
                    self.interval_s > 0
                    or len(pending) >= _WRITE_CHUNK_BYTES
                    or k == self.n_packets - 1
                ):
                    if not self._write_all(fd, bytes(pending)):
                        return
                    pending.clear()
                    self.packets_done = k + 1
        except OSError as e:
            self.error = e

    def _write_all(self, fd: int, data: bytes) -> bool:
        view = memoryview(data)
        while view:
            if self._halted():
                return False
            _, ready, _ = select.select([], [fd], [], _WAKE_S)
            if ready:
                try:
                    view = view[os.write(fd, view) :]
                except BlockingIOError:
                    continue
        return True

    def _run_udp(self, family: socket.AddressFamily, address: tuple[str, int]) -> None:
        t0 = time.monotonic()
        try:
            with socket.socket(family, socket.SOCK_DGRAM) as sock:
                sock.settimeout(_WAKE_S)
                for k in range(self.n_packets):
                    if not self._pace(k, t0):
                        return
                    data = self.packet(k)
                    while data and not self._halted():
                        try:
                            sock.sendto(data, address)
                            break
                        except TimeoutError:
                            continue
                    self.packets_done = k + 1
        except OSError as e:
            self.error = e
