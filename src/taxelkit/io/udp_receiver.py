"""A UDP source drained by a background thread: the socket is read while frames are processed.

A UDP socket holds only a few megabytes of datagrams (about 4,000 packets of
a 16 x 16 frame at 48,000 frames/s: under 0.1 s); a recogniser that works on
a large batch for longer (a sensor bank running 128 frames of 200 arrays at
once) would lose the datagrams that arrive meanwhile. :class:`BackgroundReceiver`
reads the socket in a thread of its own (its ``recv`` calls release the
interpreter lock while waiting) into a bounded queue, and the reader takes
whatever has gathered, decoded together
(:func:`~taxelkit.io.datagram_batch.decode_datagrams`). Datagrams that find
the queue full are dropped and counted (:attr:`BackgroundReceiver.dropped`);
the decoder's index gaps count them as missing too.
"""

from __future__ import annotations

import queue
import threading

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


class BackgroundReceiver(FrameSource):
    """A :class:`~taxelkit.io.live_transports.UdpSource` read by a background thread.

    Parameters
    ----------
    source : UdpSource
        The bound socket; closed with this object.
    max_queued : int
        Datagrams held at most between two reads; more are dropped and counted.

    Examples
    --------
    >>> udp = UdpSource("127.0.0.1", 0)
    >>> with BackgroundReceiver(udp) as src:
    ...     src.poll_batches(0.01)
    []
    """

    def __init__(self, source: UdpSource, max_queued: int = DEFAULT_MAX_QUEUED) -> None:
        super().__init__(source.description, source.decoder)
        self.source = source
        self.max_queued = int(max_queued)
        self.dropped = 0
        self._queue: queue.Queue[list[bytes]] = queue.Queue()
        self._queued = 0
        self._lock = threading.Lock()
        self._error: LiveSourceError | None = None
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._drain, name="taxelkit-udp-rx", daemon=True)
        self._thread.start()

    def _drain(self) -> None:
        try:
            while not self._stop.is_set():
                got = self.source.receive(_WAIT_S)
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
        self.source.close()
