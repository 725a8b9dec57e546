"""A UDP source drained in the background: the socket is read while frames are processed.

A UDP socket holds only a few megabytes of datagrams (about 4,000 packets of
a 16 x 16 frame at 48,000 frames/s: under 0.1 s); a recogniser that works on
a large batch for longer (a sensor bank running 128 frames of 200 arrays at
once) would lose the datagrams that arrive meanwhile. :class:`BackgroundReceiver`
reads the socket in the background into a bounded queue, and the reader takes
whatever has gathered, decoded together
(:func:`~taxelkit.io.datagram_batch.decode_datagrams`). Datagrams that find
the queue full are dropped and counted (:attr:`BackgroundReceiver.dropped`);
the decoder's index gaps count them as missing too.

Where processes can be forked (Linux, macOS), a small receiver process reads
the socket and passes whatever has arrived, packed into one message, through
a pipe to a thread of this process, which queues it. A thread reading the
socket itself needs the interpreter lock back after every ``recv``: while a
sensor bank of 200 arrays worked on its batches, such a thread took 170-220
ms to read 4,096 datagrams (the lock changing hands once per datagram), the
socket's buffer overflowed, and 0.05-0.6 % of the frames offered at 48,000
frames/s were lost in bursts (``benchmarks/bench_live_udp.py --arrays 200``);
through the process, none in four runs. Elsewhere (or with
``process=False``) the thread reads the socket.
"""

from __future__ import annotations

import multiprocessing
import os
import queue
import select
import signal
import socket
import struct
import threading
from multiprocessing.connection import Connection
from typing import Any

import numpy as np

from taxelkit.io.datagram_batch import FrameBatch, decode_datagrams
from taxelkit.io.frame_protocol import DecodedFrame
from taxelkit.io.live_sources import FrameSource, LiveSourceError
from taxelkit.io.live_transports import UdpSource

__all__ = ["DEFAULT_MAX_QUEUED", "BackgroundReceiver"]

#: Datagrams the queue holds at most (1.4 s at 48,000 frames/s; about 22 MB of
#: 16 x 16 bool packets).
DEFAULT_MAX_QUEUED = 65_536
#: Longest wait of one read in the thread, s: how soon it notices :meth:`close`.
_WAIT_S = 0.05
#: Datagrams the receiver process reads before it passes them on.
_BURST = 8192
#: Receive size of one datagram (larger than any).
_RECV_BYTES = 65_536


def _pack(grams: list[bytes]) -> bytes:
    """Datagrams as one message: their count (uint32), their lengths (uint32 each), their bytes."""
    lengths = np.fromiter(map(len, grams), np.uint32, len(grams))
    return struct.pack("<I", len(grams)) + lengths.tobytes() + b"".join(grams)


def _unpack(blob: bytes) -> list[bytes]:
    """The datagrams of a :func:`_pack` message."""
    n = struct.unpack_from("<I", blob)[0]
    ends = (4 + 4 * n + np.cumsum(np.frombuffer(blob, np.uint32, n, 4), dtype=np.int64)).tolist()
    out, start = [], 4 + 4 * n
    for end in ends:
        out.append(blob[start:end])
        start = end
    return out


def _receive_forever(fd: int, pipe: Connection, parent: int) -> None:
    """The receiver process: socket ``fd`` to ``pipe`` in bursts, until its parent ends."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the parent stops the run, then this process
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    sock = socket.socket(fileno=fd)
    sock.setblocking(False)
    recv = sock.recv
    try:
        while os.getppid() == parent:
            ready, _, _ = select.select([sock], [], [], _WAIT_S)
            if not ready:
                continue
            grams: list[bytes] = []
            try:
                for _ in range(_BURST):
                    grams.append(recv(_RECV_BYTES))
            except BlockingIOError:
                pass
            pipe.send_bytes(_pack(grams))
    except OSError:
        pass  # the socket or the pipe closed: the parent sees the pipe end
    finally:
        pipe.close()


class BackgroundReceiver(FrameSource):
    """A :class:`~taxelkit.io.live_transports.UdpSource` read in the background.

    Parameters
    ----------
    source : UdpSource
        The bound socket; closed with this object.
    max_queued : int
        Datagrams held at most between two reads; more are dropped and counted.
    process : bool, optional
        Read the socket in a receiver process (see the module docstring);
        default: where processes can be forked. False: a thread reads it.

    Examples
    --------
    >>> udp = UdpSource("127.0.0.1", 0)
    >>> with BackgroundReceiver(udp) as src:
    ...     src.poll_batches(0.01)
    []
    """

    def __init__(
        self,
        source: UdpSource,
        max_queued: int = DEFAULT_MAX_QUEUED,
        *,
        process: bool | None = None,
    ) -> None:
        super().__init__(source.description, source.decoder)
        self.source = source
        self.max_queued = int(max_queued)
        self.dropped = 0
        if process is None:
            process = "fork" in multiprocessing.get_all_start_methods()
        self._pipe: Connection | None = None
        self._proc: Any = None
        if process:
            ctx = multiprocessing.get_context("fork")
            self._pipe, sender = ctx.Pipe(duplex=False)
            self._proc = ctx.Process(
                target=_receive_forever,
                args=(source.fileno(), sender, os.getpid()),
                name="taxelkit-udp-rx",
                daemon=True,
            )
            self._proc.start()
            sender.close()  # the process holds the sending end
        self._queue: queue.Queue[list[bytes]] = queue.Queue()
        self._queued = 0
        self._lock = threading.Lock()
        self._error: LiveSourceError | None = None
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._drain, name="taxelkit-udp-rx", daemon=True)
        self._thread.start()

    def _read(self) -> list[bytes]:
        """Datagrams arrived (waiting up to ``_WAIT_S``), from the process or the socket."""
        if self._pipe is None:
            return self.source.receive(_WAIT_S)
        try:
            return _unpack(self._pipe.recv_bytes()) if self._pipe.poll(_WAIT_S) else []
        except (EOFError, OSError) as e:
            raise LiveSourceError(
                f"cannot read {self.description}: the receiver process ended"
            ) from e

    def _drain(self) -> None:
        try:
            while not self._stop.is_set():
                got = self._read()
                if not got:
                    continue
                with self._lock:
                    if self._queued + len(got) > self.max_queued:
                        self.dropped += len(got)
                        continue
                    self._queued += len(got)
                self._queue.put(got)
        except LiveSourceError as e:
            self._error = e
            self._queue.put([])  # wake the reader

    def _take(self, timeout_s: float) -> list[bytes]:
        """Every datagram queued, waiting up to ``timeout_s`` for the first."""
        try:
            first = (
                self._queue.get(timeout=timeout_s) if timeout_s > 0 else self._queue.get_nowait()
            )
        except queue.Empty:
            first = []
        grams = list(first)
        while True:
            try:
                grams += self._queue.get_nowait()
            except queue.Empty:
                break
        with self._lock:
            self._queued -= len(grams)
        if self._error is not None and not grams:
            raise self._error
        return grams

    def poll(self, timeout_s: float) -> list[DecodedFrame]:
        frames = (self.decoder.decode_datagram(g) for g in self._take(timeout_s))
        return [f for f in frames if f is not None]

    def poll_batches(self, timeout_s: float) -> list[FrameBatch]:
        """Every datagram received since the last call, decoded together."""
        return decode_datagrams(self.decoder, self._take(timeout_s))

    def close(self) -> None:
        self._stop.set()
        self._thread.join(2 * _WAIT_S + 1.0)
        if self._proc is not None:
            self._proc.kill()  # it ignores SIGINT and SIGTERM
            self._proc.join(1.0)
        if self._pipe is not None:
            self._pipe.close()
        self.source.close()
