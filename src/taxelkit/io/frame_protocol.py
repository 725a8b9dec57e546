"""The binary frame protocol of live tactile streams: packets, encoder, decoder.

One packet carries one frame. All numbers are little-endian::

    offset  size  field
    0       4     magic b"TXK1"
    4       4     frame index, uint32
    8       8     timestamp, float64, s
    16      2     rows, uint16
    18      2     cols, uint16
    20      1     payload type, uint8 (0 bool, 1 uint16 counts, 2 float32 mm)
    21      N     payload: rows * cols values, row-major
    21 + N  4     CRC-32 (zlib.crc32) of bytes 4 .. 21 + N, uint32

On a byte stream (serial) packets follow each other and the magic delimits
them; on UDP one datagram holds exactly one packet. The full specification,
for people wiring real hardware, is ``docs/live-protocol.md``.

:class:`FrameDecoder` never raises on bad bytes: a damaged packet (bad header,
bad CRC, truncated) is counted and skipped, and decoding resumes at the next
magic, so every intact packet after the damage is recovered. It keeps a read
position into its buffer and compacts it only when at least half is consumed,
so decoding costs O(n) in the number of bytes however the stream is chunked.
"""

from __future__ import annotations

import math
import struct
import zlib
from dataclasses import dataclass
from enum import IntEnum
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_finite_array

__all__ = [
    "CRC_SIZE",
    "DEFAULT_MAX_TAXELS",
    "HEADER_SIZE",
    "MAGIC",
    "MAX_DATAGRAM_BYTES",
    "DecodedFrame",
    "DecoderStats",
    "FrameDecoder",
    "PayloadType",
    "encode_frame",
    "packet_size",
    "to_wire",
]

#: First four bytes of every packet.
MAGIC = b"TXK1"
#: Magic, index, timestamp, rows, cols, payload type: 4 + 4 + 8 + 2 + 2 + 1 bytes.
_HEADER = struct.Struct("<4sIdHHB")
#: Bytes before the payload, magic included.
HEADER_SIZE = _HEADER.size
#: The CRC-32 trailer.
_TRAILER = struct.Struct("<I")
#: Bytes after the payload.
CRC_SIZE = _TRAILER.size
#: Largest rows * cols the decoder accepts by default: a 256 x 256 array. It
#: bounds how many bytes a damaged header can make the decoder wait for before
#: its CRC is checked (at most 262,169 bytes, a float32 packet of that size).
DEFAULT_MAX_TAXELS = 65_536
#: Largest UDP payload over IPv4 (65,535 - 8 UDP - 20 IP header bytes); a
#: packet sent over UDP must fit in one datagram.
MAX_DATAGRAM_BYTES = 65_507
#: Frame indices are uint32 and wrap around.
_INDEX_MODULUS = 2**32
#: Largest rows or cols (uint16).
_MAX_SIDE = 2**16 - 1


class PayloadType(IntEnum):
    """What the payload values are (the header's payload type byte)."""

    #: One byte per taxel: 0 no contact, 1 contact (any nonzero byte reads as contact).
    BOOL = 0
    #: Two bytes per taxel: raw sensor counts, uint16.
    UINT16 = 1
    #: Four bytes per taxel: deflection in mm, float32.
    FLOAT32 = 2


#: Wire dtype of each payload type.
_WIRE_DTYPE: dict[PayloadType, np.dtype[Any]] = {
    PayloadType.BOOL: np.dtype("u1"),
    PayloadType.UINT16: np.dtype("<u2"),
    PayloadType.FLOAT32: np.dtype("<f4"),
}
#: Bytes per taxel, indexed by payload type code.
_ITEMSIZE = {int(k): v.itemsize for k, v in _WIRE_DTYPE.items()}


@dataclass(frozen=True, eq=False)
class DecodedFrame:
    """One frame as received.

    Attributes
    ----------
    index : int
        Frame index from the header (uint32, as counted by the sender).
    t_s : float
        Timestamp from the header, s (sender's clock).
    values : (rows, cols) bool, uint16 or float32
        The taxel values, read-only: contact, raw counts, or mm.
    payload_type : PayloadType
        How ``values`` were sent.
    """

    index: int
    t_s: float
    values: NDArray[Any]
    payload_type: PayloadType

    @property
    def shape(self) -> tuple[int, int]:
        """``(rows, cols)``."""
        return (int(self.values.shape[0]), int(self.values.shape[1]))


@dataclass(frozen=True)
class DecoderStats:
    """What a :class:`FrameDecoder` has seen so far.

    Attributes
    ----------
    bytes_received : int
        Bytes fed in (streams) or datagram bytes (UDP).
    frames : int
        Intact packets decoded.
    bad_header : int
        Packets refused for their header: unknown payload type, zero or too
        many taxels, a non-finite timestamp, an unexpected shape; on UDP also a
        datagram that does not start with the magic or is longer than its header says.
    bad_crc : int
        Packets whose CRC-32 did not match.
    truncated : int
        Packets cut short: a datagram shorter than its header says, or a
        packet still incomplete when a stream ended.
    bytes_skipped : int
        Bytes discarded as noise or damaged packets.
    missing : int
        Frame indices skipped between consecutive decoded frames (lost or
        damaged packets; a jump backwards, e.g. a sender restart, counts none).
    """

    bytes_received: int = 0
    frames: int = 0
    bad_header: int = 0
    bad_crc: int = 0
    truncated: int = 0
    bytes_skipped: int = 0
    missing: int = 0

    @property
    def corrupted(self) -> int:
        """Damaged packets seen: ``bad_header + bad_crc + truncated``."""
        return self.bad_header + self.bad_crc + self.truncated


def packet_size(rows: int, cols: int, payload_type: PayloadType | int) -> int:
    """Bytes in one packet of a ``rows x cols`` frame, header and CRC included.

    Examples
    --------
    >>> packet_size(16, 16, PayloadType.BOOL)
    281
    """
    return HEADER_SIZE + int(rows) * int(cols) * _ITEMSIZE[int(payload_type)] + CRC_SIZE


def _payload_type_for(values: NDArray[Any], payload_type: PayloadType | int | None) -> PayloadType:
    if payload_type is None:
        kind = values.dtype.kind
        if kind == "b":
            return PayloadType.BOOL
        if kind in "ui":
            return PayloadType.UINT16
        if kind == "f":
            return PayloadType.FLOAT32
        raise InputError(f"values must be bool, integer or float, got dtype {values.dtype}")
    try:
        return PayloadType(int(payload_type))
    except ValueError:
        known = ", ".join(f"{p.value} ({p.name.lower()})" for p in PayloadType)
        raise InputError(f"payload_type must be one of {known}, got {payload_type!r}") from None


def to_wire(
    values: ArrayLike, payload_type: PayloadType | int | None = None
) -> tuple[NDArray[Any], PayloadType]:
    """Values as the protocol carries them, checked to be representable.

    Parameters
    ----------
    values : array of bool, integer or float, any shape
    payload_type : PayloadType or int, optional
        Default from the dtype: bool -> ``BOOL``, integer -> ``UINT16``,
        float -> ``FLOAT32``.

    Returns
    -------
    wire : array, same shape
        uint8 (0/1), little-endian uint16 or little-endian float32.
    payload_type : PayloadType

    Raises
    ------
    InputError
        If the dtype is not numeric, integers fall outside ``[0, 1]`` (bool)
        or ``[0, 65535]`` (uint16), or floats are not finite as float32.
    """
    arr = np.asarray(values)
    if arr.dtype.kind not in "buif":
        raise InputError(f"values must be bool, integer or float, got dtype {arr.dtype}")
    ptype = _payload_type_for(arr, payload_type)
    if ptype == PayloadType.FLOAT32:
        check_finite_array("values", arr)
        with np.errstate(over="ignore"):  # overflow becomes inf, refused just below
            out = arr.astype(_WIRE_DTYPE[ptype])
        check_finite_array("values (as float32)", out)
        return out, ptype
    if arr.dtype.kind == "f":
        raise InputError(f"values must be bool or integer for payload type {ptype.name}, got float")
    high = 1 if ptype == PayloadType.BOOL else 2**16 - 1
    if arr.size and (int(arr.min()) < 0 or int(arr.max()) > high):
        raise InputError(
            f"values must lie in [0, {high}] for payload type {ptype.name}, "
            f"got [{arr.min()}, {arr.max()}]"
        )
    return arr.astype(_WIRE_DTYPE[ptype]), ptype


def encode_frame(
    values: ArrayLike,
    *,
    index: int,
    t_s: float,
    payload_type: PayloadType | int | None = None,
) -> bytes:
    """One frame as a packet of the live protocol.

    Parameters
    ----------
    values : (rows, cols) bool, integer or float
        The frame; ``1 <= rows, cols <= 65535``.
    index : int
        Frame index, ``0 <= index < 2**32`` (wrap it yourself on long runs).
    t_s : float
        Timestamp, s; finite.
    payload_type : PayloadType or int, optional
        Default from the dtype: bool -> ``BOOL``, integer -> ``UINT16``
        (values in [0, 65535]), float -> ``FLOAT32`` (finite, in mm).

    Returns
    -------
    bytes
        ``packet_size(rows, cols, payload_type)`` bytes.

    Raises
    ------
    InputError
        On a wrong shape, an index or timestamp out of range, or values that
        the payload type cannot carry.

    Examples
    --------
    >>> packet = encode_frame(np.eye(2, dtype=bool), index=7, t_s=0.5)
    >>> packet[:4], len(packet)
    (b'TXK1', 29)
    """
    arr = np.asarray(values)
    if arr.ndim != 2 or not (1 <= arr.shape[0] <= _MAX_SIDE and 1 <= arr.shape[1] <= _MAX_SIDE):
        raise InputError(
            f"values must have shape (rows, cols) with 1..{_MAX_SIDE} each, got shape {arr.shape}"
        )
    wire, ptype = to_wire(arr, payload_type)
    if not (isinstance(index, int | np.integer) and 0 <= int(index) < _INDEX_MODULUS):
        raise InputError(f"index must be an integer in [0, 2**32), got {index!r}")
    t = float(t_s)
    if not math.isfinite(t):
        raise InputError(f"t_s must be finite, got {t_s!r}")
    payload = np.ascontiguousarray(wire).tobytes()
    header = _HEADER.pack(MAGIC, int(index), t, arr.shape[0], arr.shape[1], int(ptype))
    crc = zlib.crc32(payload, zlib.crc32(header[len(MAGIC) :]))
    return b"".join((header, payload, _TRAILER.pack(crc)))


class FrameDecoder:
    """Turn received bytes into frames, skipping and counting damaged packets.

    Parameters
    ----------
    shape : (rows, cols), optional
        If given, packets of any other shape count as ``bad_header``: a
        damaged size field is then caught at once instead of after waiting for
        the bytes it announces.
    max_taxels : int
        Largest ``rows * cols`` accepted (default :data:`DEFAULT_MAX_TAXELS`).

    Notes
    -----
    Byte streams: call :meth:`feed` with whatever arrived (any chunking gives
    the same frames) and :meth:`flush` at the end of the stream. Datagrams:
    call :meth:`decode_datagram` once per datagram. Neither raises on bad bytes.

    A packet that is still incomplete is held back until its bytes arrive, so
    a packet damaged in its size field delays (never loses) the packets after
    it by at most one maximal packet.

    Examples
    --------
    >>> dec = FrameDecoder()
    >>> stream = b"noise" + encode_frame(np.ones((2, 2), bool), index=0, t_s=0.0)
    >>> [f.index for f in dec.feed(stream)], dec.stats.bytes_skipped
    ([0], 5)
    """

    def __init__(
        self, *, shape: tuple[int, int] | None = None, max_taxels: int = DEFAULT_MAX_TAXELS
    ) -> None:
        if shape is not None:
            rows, cols = int(shape[0]), int(shape[1])
            if not (1 <= rows <= _MAX_SIDE and 1 <= cols <= _MAX_SIDE):
                raise InputError(f"shape must be two integers in 1..{_MAX_SIDE}, got {shape!r}")
            shape = (rows, cols)
        if int(max_taxels) < 1:
            raise InputError(f"max_taxels must be >= 1, got {max_taxels!r}")
        self.shape = shape
        self.max_taxels = int(max_taxels)
        self._buf = bytearray()
        self._pos = 0
        self._last_index: int | None = None
        self._counts = {name: 0 for name in DecoderStats.__dataclass_fields__}

    @property
    def stats(self) -> DecoderStats:
        """A snapshot of the counters."""
        return DecoderStats(**self._counts)

    @property
    def pending_bytes(self) -> int:
        """Bytes held back: an incomplete packet, or up to 3 bytes of a possible magic."""
        return len(self._buf) - self._pos

    # -- streams -------------------------------------------------------------------------
    def feed(self, data: bytes | bytearray | memoryview) -> list[DecodedFrame]:
        """Add bytes from a stream; return the frames they completed (in order)."""
        self._counts["bytes_received"] += len(data)
        self._buf += data
        return self._scan(final=False)

    def flush(self) -> list[DecodedFrame]:
        """The stream has ended: decode what can be, count the rest as truncated or noise."""
        frames = self._scan(final=True)
        self._counts["bytes_skipped"] += len(self._buf) - self._pos
        self._buf.clear()
        self._pos = 0
        return frames

    def _scan(self, *, final: bool) -> list[DecodedFrame]:
        buf, pos, counts = self._buf, self._pos, self._counts
        out: list[DecodedFrame] = []
        while True:
            start = buf.find(MAGIC, pos)
            if start < 0:
                end = len(buf) if final else len(buf) - _magic_prefix_len(buf, pos)
                counts["bytes_skipped"] += end - pos
                pos = end
                break
            counts["bytes_skipped"] += start - pos
            pos = start
            result = self._parse_at(pos, final=final)
            if result is None:  # incomplete: wait for more bytes
                break
            if isinstance(result, str):  # damaged: skip one byte, look for the next magic
                counts[result] += 1
                counts["bytes_skipped"] += 1
                pos += 1
                continue
            frame, size = result
            out.append(frame)
            pos += size
        if pos and 2 * pos >= len(buf):  # amortised O(1) per byte
            del buf[:pos]
            pos = 0
        self._pos = pos
        return out

    def _parse_at(self, pos: int, *, final: bool) -> tuple[DecodedFrame, int] | str | None:
        """Parse the packet whose magic is at ``pos``.

        Returns ``(frame, size)``, the name of the counter to blame, or None if
        more bytes are needed.
        """
        buf = self._buf
        available = len(buf) - pos
        if available < HEADER_SIZE:
            return "truncated" if final else None
        _, index, t_s, rows, cols, code = _HEADER.unpack_from(buf, pos)
        if not self._header_ok(t_s, rows, cols, code):
            return "bad_header"
        size = packet_size(rows, cols, code)
        if available < size:
            return "truncated" if final else None
        frame = self._check_and_decode(buf, pos, size, index, t_s, rows, cols, code)
        return "bad_crc" if frame is None else (frame, size)

    def _header_ok(self, t_s: float, rows: int, cols: int, code: int) -> bool:
        return (
            code in _ITEMSIZE
            and rows >= 1
            and cols >= 1
            and rows * cols <= self.max_taxels
            and math.isfinite(t_s)
            and (self.shape is None or self.shape == (rows, cols))
        )

    def _check_and_decode(
        self,
        data: bytes | bytearray,
        pos: int,
        size: int,
        index: int,
        t_s: float,
        rows: int,
        cols: int,
        code: int,
    ) -> DecodedFrame | None:
        """The frame of a complete packet with a valid header, or None on a CRC mismatch."""
        payload_start, payload_end = pos + HEADER_SIZE, pos + size - CRC_SIZE
        payload = bytes(data[payload_start:payload_end])
        crc = zlib.crc32(payload, zlib.crc32(data[pos + len(MAGIC) : payload_start]))
        if crc != _TRAILER.unpack_from(data, payload_end)[0]:
            return None
        ptype = PayloadType(code)
        values = np.frombuffer(payload, dtype=_WIRE_DTYPE[ptype]).reshape(rows, cols)
        if ptype == PayloadType.BOOL:
            values = values != 0
            values.setflags(write=False)
        self._count_frame(index)
        return DecodedFrame(int(index), float(t_s), values, ptype)

    def record_frames(self, indices: NDArray[np.int64], n_bytes: int) -> None:
        """Count frames decoded outside this object (a batch of datagrams), in order.

        Parameters
        ----------
        indices : (n,) int
            Their frame indices, in arrival order.
        n_bytes : int
            Datagram bytes they took.
        """
        counts = self._counts
        counts["bytes_received"] += int(n_bytes)
        if indices.size == 0:
            return
        counts["frames"] += int(indices.size)
        first = indices[:1] if self._last_index is None else np.array([self._last_index])
        steps = np.mod(np.diff(np.concatenate([first, indices]).astype(np.int64)), _INDEX_MODULUS)
        gaps = (steps > 1) & (steps < _INDEX_MODULUS // 2)
        counts["missing"] += int(np.sum(steps[gaps] - 1))
        self._last_index = int(indices[-1])

    def _count_frame(self, index: int) -> None:
        counts = self._counts
        counts["frames"] += 1
        if self._last_index is not None:
            step = (index - self._last_index) % _INDEX_MODULUS
            if 1 < step < _INDEX_MODULUS // 2:
                counts["missing"] += step - 1
        self._last_index = index

    # -- datagrams ------------------------------------------------------------------------
    def decode_datagram(self, data: bytes | bytearray | memoryview) -> DecodedFrame | None:
        """Decode one datagram holding exactly one packet; None (counted) if it is damaged."""
        raw = bytes(data)
        counts = self._counts
        counts["bytes_received"] += len(raw)
        blame: str
        if len(raw) < HEADER_SIZE:
            blame = "truncated" if raw[: len(MAGIC)] == MAGIC[: len(raw)] else "bad_header"
        else:
            magic, index, t_s, rows, cols, code = _HEADER.unpack_from(raw, 0)
            if magic != MAGIC or not self._header_ok(t_s, rows, cols, code):
                blame = "bad_header"
            else:
                size = packet_size(rows, cols, code)
                if len(raw) < size:
                    blame = "truncated"
                elif len(raw) > size:
                    blame = "bad_header"
                else:
                    frame = self._check_and_decode(raw, 0, size, index, t_s, rows, cols, code)
                    if frame is not None:
                        return frame
                    blame = "bad_crc"
        counts[blame] += 1
        counts["bytes_skipped"] += len(raw)
        return None


def _magic_prefix_len(buf: bytearray, pos: int) -> int:
    """Length of the longest proper prefix of the magic that ``buf[pos:]`` ends with."""
    for k in range(len(MAGIC) - 1, 0, -1):
        if len(buf) - pos >= k and buf.endswith(MAGIC[:k]):
            return k
    return 0
