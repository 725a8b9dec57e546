"""The decoder of the live frame protocol: bytes or datagrams in, frames out.

The packet layout (versions 1 ``TXK1`` and 2 ``TXK2``, the latter with an
array id per frame) and the encoder are in :mod:`taxelkit.io.frame_packet`,
re-exported here. On a byte stream (serial) packets follow each other and the
magic delimits them; on UDP one datagram holds exactly one packet. Both
versions may be mixed on one stream; a version 1 packet is array 0. The full
specification, for people wiring real hardware, is ``docs/live-protocol.md``.

:class:`FrameDecoder` never raises on bad bytes: a damaged packet (bad header,
bad CRC, truncated) is counted and skipped, and decoding resumes at the next
magic, so every intact packet after the damage is recovered. It keeps a read
position into its buffer and compacts it only when at least half is consumed,
so decoding costs O(n) in the number of bytes however the stream is chunked.
Missing frames are counted from the index gaps of each array.
"""

from __future__ import annotations

import math
import zlib
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.io.frame_packet import (
    _HEADER,
    _HEADER_V2,
    _INDEX_MODULUS,
    _ITEMSIZE,
    _MAGIC_STEM,
    _MAGICS,
    _MAX_SIDE,
    _TRAILER,
    _WIRE_DTYPE,
    CRC_SIZE,
    DEFAULT_MAX_TAXELS,
    HEADER_SIZE,
    HEADER_SIZE_V2,
    MAGIC,
    MAGIC_V2,
    MAX_ARRAY_ID,
    MAX_DATAGRAM_BYTES,
    PayloadType,
    encode_frame,
    packet_size,
    to_wire,
)

__all__ = [
    "CRC_SIZE",
    "DEFAULT_MAX_TAXELS",
    "HEADER_SIZE",
    "HEADER_SIZE_V2",
    "MAGIC",
    "MAGIC_V2",
    "MAX_ARRAY_ID",
    "MAX_DATAGRAM_BYTES",
    "DecodedFrame",
    "DecoderStats",
    "FrameDecoder",
    "PayloadType",
    "encode_frame",
    "packet_size",
    "to_wire",
]

#: A parsed header: version, index, t_s, array id, rows, cols, payload code, header bytes.
_Header = tuple[int, int, float, int, int, int, int, int]


def _header_at(data: bytes | bytearray, pos: int) -> _Header:
    """The header of the packet at ``pos`` (its magic known to be one of :data:`_MAGICS`)."""
    if data[pos + 3 : pos + 4] == MAGIC_V2[3:]:
        _, index, t_s, array_id, rows, cols, code = _HEADER_V2.unpack_from(data, pos)
        return 2, index, t_s, array_id, rows, cols, code, HEADER_SIZE_V2
    _, index, t_s, rows, cols, code = _HEADER.unpack_from(data, pos)
    return 1, index, t_s, 0, rows, cols, code, HEADER_SIZE


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
    array_id : int
        The array it comes from (a version 2 packet); 0 for version 1.
    """

    index: int
    t_s: float
    values: NDArray[Any]
    payload_type: PayloadType
    array_id: int = 0

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
        Frame indices skipped between consecutive decoded frames of one array
        (lost or damaged packets; a jump backwards, e.g. a sender restart,
        counts none).
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
        self._last_index: dict[int, int] = {}  # per array id
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
            start = buf.find(_MAGIC_STEM, pos)
            if start < 0:
                end = len(buf) if final else len(buf) - _magic_prefix_len(buf, pos)
                counts["bytes_skipped"] += end - pos
                pos = end
                break
            counts["bytes_skipped"] += start - pos
            pos = start
            if len(buf) - pos < len(MAGIC) and not final:  # which version: wait and see
                break
            if bytes(buf[pos : pos + len(MAGIC)]) not in _MAGICS:  # noise that looks like one
                counts["bytes_skipped"] += 1
                pos += 1
                continue
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
        need = HEADER_SIZE_V2 if buf[pos + 3 : pos + 4] == MAGIC_V2[3:] else HEADER_SIZE
        if available < need:
            return "truncated" if final else None
        header = _header_at(buf, pos)
        version, _, t_s, _, rows, cols, code, _ = header
        if not self._header_ok(t_s, rows, cols, code):
            return "bad_header"
        size = packet_size(rows, cols, code, version=version)
        if available < size:
            return "truncated" if final else None
        frame = self._check_and_decode(buf, pos, size, header)
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
        header: _Header,
    ) -> DecodedFrame | None:
        """The frame of a complete packet with a valid header, or None on a CRC mismatch."""
        _, index, t_s, array_id, rows, cols, code, header_size = header
        payload_start, payload_end = pos + header_size, pos + size - CRC_SIZE
        payload = bytes(data[payload_start:payload_end])
        crc = zlib.crc32(payload, zlib.crc32(data[pos + len(MAGIC) : payload_start]))
        if crc != _TRAILER.unpack_from(data, payload_end)[0]:
            return None
        ptype = PayloadType(code)
        values = np.frombuffer(payload, dtype=_WIRE_DTYPE[ptype]).reshape(rows, cols)
        if ptype == PayloadType.BOOL:
            values = values != 0
            values.setflags(write=False)
        self._count_frame(index, array_id)
        return DecodedFrame(int(index), float(t_s), values, ptype, int(array_id))

    def record_frames(
        self,
        indices: NDArray[np.int64],
        n_bytes: int,
        array_ids: NDArray[np.int64] | None = None,
    ) -> None:
        """Count frames decoded outside this object (a batch of datagrams), in order.

        Parameters
        ----------
        indices : (n,) int
            Their frame indices, in arrival order.
        n_bytes : int
            Datagram bytes they took.
        array_ids : (n,) int, optional
            Their arrays (default: all array 0); gaps are counted per array.
        """
        counts = self._counts
        counts["bytes_received"] += int(n_bytes)
        if indices.size == 0:
            return
        counts["frames"] += int(indices.size)
        ids = np.zeros(indices.size, np.int64) if array_ids is None else array_ids
        order = np.argsort(ids, kind="stable")  # each array's frames together, in order
        a, x = ids[order].astype(np.int64), indices[order].astype(np.int64)
        starts = np.flatnonzero(np.concatenate([[True], a[1:] != a[:-1]]))
        prev = np.concatenate([x[:1], x[:-1]])
        last = self._last_index
        heads = zip(a[starts].tolist(), x[starts].tolist(), strict=True)
        prev[starts] = [last.get(k, i) for k, i in heads]  # each array's frame before
        steps = np.mod(x - prev, _INDEX_MODULUS)
        gaps = (steps > 1) & (steps < _INDEX_MODULUS // 2)
        counts["missing"] += int(np.sum(steps[gaps] - 1))
        ends = np.append(starts[1:], a.size) - 1
        last.update(zip(a[ends].tolist(), x[ends].tolist(), strict=True))

    def _count_frame(self, index: int, array_id: int = 0) -> None:
        counts = self._counts
        counts["frames"] += 1
        before = self._last_index.get(array_id)
        if before is not None:
            step = (index - before) % _INDEX_MODULUS
            if 1 < step < _INDEX_MODULUS // 2:
                counts["missing"] += step - 1
        self._last_index[array_id] = index

    # -- datagrams ------------------------------------------------------------------------
    def decode_datagram(self, data: bytes | bytearray | memoryview) -> DecodedFrame | None:
        """Decode one datagram holding exactly one packet; None (counted) if it is damaged."""
        raw = bytes(data)
        counts = self._counts
        counts["bytes_received"] += len(raw)
        blame: str
        magic = raw[: len(MAGIC)]
        if len(raw) < (HEADER_SIZE_V2 if magic == MAGIC_V2 else HEADER_SIZE):
            prefix = any(m[: len(magic)] == magic for m in _MAGICS)
            blame = "truncated" if prefix else "bad_header"
        elif magic not in _MAGICS:
            blame = "bad_header"
        else:
            header = _header_at(raw, 0)
            version, _, t_s, _, rows, cols, code, _ = header
            if not self._header_ok(t_s, rows, cols, code):
                blame = "bad_header"
            else:
                size = packet_size(rows, cols, code, version=version)
                if len(raw) < size:
                    blame = "truncated"
                elif len(raw) > size:
                    blame = "bad_header"
                else:
                    frame = self._check_and_decode(raw, 0, size, header)
                    if frame is not None:
                        return frame
                    blame = "bad_crc"
        counts[blame] += 1
        counts["bytes_skipped"] += len(raw)
        return None


def _magic_prefix_len(buf: bytearray, pos: int) -> int:
    """Length of the longest proper prefix of the magics' stem that ``buf[pos:]`` ends with."""
    for k in range(len(_MAGIC_STEM) - 1, 0, -1):
        if len(buf) - pos >= k and buf.endswith(_MAGIC_STEM[:k]):
            return k
    return 0
