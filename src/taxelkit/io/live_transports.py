"""The serial and UDP frame sources (:func:`~taxelkit.io.live_sources.open_source` opens them).

:class:`SerialSource` reads a serial port with pyserial (the optional
``taxelkit[live]`` extra); :class:`UdpSource` listens for one packet per
datagram on a local address and can drain and decode whatever has arrived in
one call (:meth:`UdpSource.poll_batches`). Both yield
:class:`~taxelkit.io.frame_protocol.DecodedFrame` objects like every
:class:`~taxelkit.io.live_sources.FrameSource`.
"""

from __future__ import annotations

import importlib
import select
import socket
from types import ModuleType
from typing import Any

from taxelkit.errors import InputError
from taxelkit.io.datagram_batch import FrameBatch, decode_datagrams
from taxelkit.io.frame_protocol import DEFAULT_MAX_TAXELS, DecodedFrame, FrameDecoder
from taxelkit.io.live_sources import (
    DEFAULT_BAUD,
    FrameSource,
    LiveDependencyError,
    LiveSourceError,
    StreamSource,
    one_line_message,
)

__all__ = ["SerialSource", "UdpSource"]

_INSTALL_HINT = 'pip install "taxelkit[live]"'
#: Receive buffer asked for on UDP sockets, bytes (the kernel may grant less).
_UDP_RCVBUF_BYTES = 4 * 2**20
#: Datagrams drained per :meth:`UdpSource.poll`, bounding the latency of one call.
_MAX_DATAGRAMS_PER_POLL = 4096
#: Receive size: larger than any datagram, so that none is cut short by the read.
_MAX_DATAGRAM_RECV = 65_536


def _import_pyserial() -> ModuleType:
    try:
        return importlib.import_module("serial")
    except ImportError:
        raise LiveDependencyError(
            f"serial sources need pyserial, which is not installed: {_INSTALL_HINT}"
        ) from None


class SerialSource(StreamSource):
    """Frames from a serial port, read with pyserial.

    Parameters
    ----------
    port : str
        ``/dev/ttyUSB0``, ``/dev/ttyACM0``, ``COM3``, a pseudo-terminal name, ...
    baud : int
        Baud rate, 8 data bits, no parity, 1 stop bit.
    shape, max_taxels
        Passed to the :class:`~taxelkit.io.frame_protocol.FrameDecoder`.

    Raises
    ------
    LiveDependencyError
        If pyserial is not installed (``pip install "taxelkit[live]"``).
    LiveSourceError
        If the port cannot be opened.
    """

    def __init__(
        self,
        port: str,
        baud: int = DEFAULT_BAUD,
        *,
        shape: tuple[int, int] | None = None,
        max_taxels: int = DEFAULT_MAX_TAXELS,
    ) -> None:
        if int(baud) < 1:
            raise InputError(f"baud must be a positive integer, got {baud!r}")
        serial = _import_pyserial()
        description = f"serial:{port}@{int(baud)}"
        super().__init__(description, FrameDecoder(shape=shape, max_taxels=max_taxels))
        self._error: type[BaseException] = serial.SerialException
        try:
            self._port: Any = serial.Serial(port, baudrate=int(baud), timeout=0)
        except (self._error, OSError, ValueError) as e:
            raise LiveSourceError(f"cannot open {description}: {one_line_message(e)}") from e

    def _read(self, timeout_s: float) -> bytes | None:
        try:
            self._port.timeout = max(0.0, timeout_s)
            first: bytes = self._port.read(1)  # waits up to timeout_s for a byte
            if not first:
                return b""
            return first + bytes(self._port.read(self._port.in_waiting))
        except (self._error, OSError) as e:
            raise LiveSourceError(f"cannot read {self.description}: {one_line_message(e)}") from e

    def close(self) -> None:
        self._port.close()


class UdpSource(FrameSource):
    """Frames from UDP datagrams sent to a local address, one packet per datagram.

    Parameters
    ----------
    host : str
        Local address to listen on: ``"0.0.0.0"`` (all IPv4 interfaces),
        ``"127.0.0.1"``, ``"::1"``, ...
    port : int
        UDP port; 0 lets the system choose (see :attr:`address`).
    shape, max_taxels
        Passed to the :class:`~taxelkit.io.frame_protocol.FrameDecoder`.

    Raises
    ------
    LiveSourceError
        If the address cannot be bound (in use, not local, ...).
    """

    def __init__(
        self,
        host: str,
        port: int,
        *,
        shape: tuple[int, int] | None = None,
        max_taxels: int = DEFAULT_MAX_TAXELS,
    ) -> None:
        if not 0 <= int(port) <= 65_535:
            raise InputError(f"port must be in 0..65535, got {port!r}")
        family = socket.AF_INET6 if ":" in host else socket.AF_INET
        shown = f"[{host}]" if family == socket.AF_INET6 else host
        super().__init__(f"udp:{shown}:{port}", FrameDecoder(shape=shape, max_taxels=max_taxels))
        self._sock = socket.socket(family, socket.SOCK_DGRAM)
        try:
            self._sock.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, _UDP_RCVBUF_BYTES)
            self._sock.bind((host, int(port)))
        except OSError as e:
            self._sock.close()
            why = one_line_message(e)
            raise LiveSourceError(f"cannot listen on {self.description}: {why}") from e
        self._sock.setblocking(False)
        bound = self._sock.getsockname()
        self.address: tuple[str, int] = (str(bound[0]), int(bound[1]))
        self.description = f"udp:{shown}:{self.address[1]}"

    def fileno(self) -> int:
        """The socket's file descriptor (read by :mod:`taxelkit.io.udp_receiver`'s process)."""
        return self._sock.fileno()

    def poll(self, timeout_s: float) -> list[DecodedFrame]:
        out: list[DecodedFrame] = []
        try:
            ready, _, _ = select.select([self._sock], [], [], max(0.0, timeout_s))
            if not ready:
                return out
            for _ in range(_MAX_DATAGRAMS_PER_POLL):
                data = self._sock.recv(_MAX_DATAGRAM_RECV)
                frame = self.decoder.decode_datagram(data)
                if frame is not None:
                    out.append(frame)
        except BlockingIOError:
            pass  # drained
        except OSError as e:
            raise LiveSourceError(f"cannot read {self.description}: {one_line_message(e)}") from e
        return out

    def receive(
        self, timeout_s: float, max_datagrams: int = _MAX_DATAGRAMS_PER_POLL
    ) -> list[bytes]:
        """Datagrams that have arrived (at most ``max_datagrams``), waiting up to ``timeout_s``."""
        out: list[bytes] = []
        recv = self._sock.recv
        try:
            ready, _, _ = select.select([self._sock], [], [], max(0.0, timeout_s))
            if not ready:
                return out
            for _ in range(max_datagrams):
                out.append(recv(_MAX_DATAGRAM_RECV))
        except BlockingIOError:
            pass  # drained
        except OSError as e:
            raise LiveSourceError(f"cannot read {self.description}: {one_line_message(e)}") from e
        return out

    def poll_batches(self, timeout_s: float) -> list[FrameBatch]:
        """Every datagram that has arrived (up to 4096), decoded together."""
        left = super().poll_batches(0.0) if self._backlog else []
        if left:
            return left
        return decode_datagrams(self.decoder, self.receive(timeout_s))

    def close(self) -> None:
        self._sock.close()
