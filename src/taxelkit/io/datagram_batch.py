"""Decode many datagrams at once: frames of a live source as arrays, not one object each.

A UDP source at 50,000 frames/s receives hundreds of datagrams per read.
Decoding them one by one (:meth:`~taxelkit.io.frame_protocol.FrameDecoder.decode_datagram`)
costs a few microseconds of Python each; :func:`decode_datagrams` checks the
intact packets of the common size together: one structured NumPy view of all
of them for the header fields, one CRC-32 call per packet, one array of
frames. Anything else (another size, a damaged packet) goes through the
per-datagram decoder, so every packet is counted exactly as it would be one
by one, and the frames come out in arrival order.
"""

from __future__ import annotations

import struct
import zlib
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.io.frame_packet import _MAGICS, _WIRE_DTYPE, CRC_SIZE, MAGIC, MAGIC_V2
from taxelkit.io.frame_protocol import (
    DecodedFrame,
    FrameDecoder,
    PayloadType,
    _header_at,
    packet_size,
)

__all__ = ["FrameBatch", "batches_from_frames", "decode_datagrams"]


@dataclass(frozen=True, eq=False)
class FrameBatch:
    """Consecutive frames of one shape and payload type, as received.

    Attributes
    ----------
    index : (n,) int64
        Frame indices from the headers (the sender's count).
    t_s : (n,) float64, s
        Timestamps from the headers (the sender's clock).
    values : (n, rows, cols) bool, uint16 or float32
        The taxel values.
    payload_type : PayloadType
        How they were sent.
    array_id : (n,) int64, optional
        The array of each frame (version 2 packets); None: all array 0.
    """

    index: NDArray[np.int64]
    t_s: NDArray[np.float64]
    values: NDArray[Any]
    payload_type: PayloadType
    array_id: NDArray[np.int64] | None = None

    @property
    def array_ids(self) -> NDArray[np.int64]:
        """``(n,)`` int64: the array of each frame (0 for version 1 packets)."""
        if self.array_id is None:
            return np.zeros(self.index.size, np.int64)
        return self.array_id

    def take(self, keep: NDArray[Any]) -> FrameBatch:
        """The frames selected by ``keep`` (a boolean mask or indices), as a batch."""
        ids = None if self.array_id is None else self.array_id[keep]
        return FrameBatch(
            self.index[keep], self.t_s[keep], self.values[keep], self.payload_type, ids
        )

    @property
    def n_frames(self) -> int:
        """Frames in the batch."""
        return int(self.index.size)

    @property
    def shape(self) -> tuple[int, int]:
        """``(rows, cols)``."""
        return (int(self.values.shape[1]), int(self.values.shape[2]))


def batches_from_frames(frames: Sequence[DecodedFrame]) -> list[FrameBatch]:
    """Group consecutive frames of one shape and payload type into batches.

    Examples
    --------
    >>> one = DecodedFrame(0, 0.0, np.zeros((2, 2), bool), PayloadType.BOOL)
    >>> [b.n_frames for b in batches_from_frames([one, one])]
    [2]
    """
    out: list[FrameBatch] = []
    start = 0
    for k in range(1, len(frames) + 1):
        if k < len(frames):
            a, b = frames[k - 1], frames[k]
            if a.shape == b.shape and a.payload_type == b.payload_type:
                continue
        run = frames[start:k]
        ids = np.array([f.array_id for f in run], dtype=np.int64)
        out.append(
            FrameBatch(
                np.array([f.index for f in run], dtype=np.int64),
                np.array([f.t_s for f in run], dtype=np.float64),
                np.stack([f.values for f in run]),
                run[0].payload_type,
                ids if ids.any() else None,
            )
        )
        start = k
    return out


def _record_dtype(rows: int, cols: int, ptype: PayloadType, version: int) -> np.dtype[Any]:
    """One packet as a packed structured dtype (field offsets as in the protocol)."""
    array_id = [("array_id", "<u2")] if version == 2 else []
    return np.dtype(
        [
            ("magic", "S4"),
            ("index", "<u4"),
            ("t_s", "<f8"),
            *array_id,
            ("rows", "<u2"),
            ("cols", "<u2"),
            ("code", "u1"),
            ("payload", _WIRE_DTYPE[ptype], (rows, cols)),
            ("crc", "<u4"),
        ]
    )


def _common_header(
    decoder: FrameDecoder, datagrams: Sequence[bytes]
) -> tuple[int, int, int, int] | None:
    """``(version, rows, cols, code)`` of the first datagram with a valid header, if any."""
    for raw in datagrams:
        if len(raw) >= len(MAGIC) and raw[: len(MAGIC)] in _MAGICS:
            try:
                version, _, t_s, _, rows, cols, code, _ = _header_at(raw, 0)
            except struct.error:  # shorter than its header
                continue
            if decoder._header_ok(t_s, rows, cols, code):
                return version, int(rows), int(cols), int(code)
    return None


def decode_datagrams(decoder: FrameDecoder, datagrams: Sequence[bytes]) -> list[FrameBatch]:
    """Decode datagrams (one packet each) into batches of frames, in arrival order.

    Parameters
    ----------
    decoder : FrameDecoder
        Its counters are updated as if each datagram had been decoded alone.
    datagrams : sequence of bytes
        As received.

    Returns
    -------
    list of FrameBatch
        Consecutive frames of one shape and payload type per batch (usually
        one batch); damaged datagrams are skipped and counted.
    """
    if not datagrams:
        return []
    header = _common_header(decoder, datagrams)
    if header is None:
        frames = [decoder.decode_datagram(raw) for raw in datagrams]
        return batches_from_frames([f for f in frames if f is not None])
    version, rows, cols, code = header
    ptype = PayloadType(code)
    size = packet_size(rows, cols, code, version=version)
    fast = np.fromiter((len(raw) == size for raw in datagrams), bool, len(datagrams))
    picked = [raw for raw, ok in zip(datagrams, fast.tolist(), strict=True) if ok]
    buf = b"".join(picked)
    records = np.frombuffer(buf, dtype=_record_dtype(rows, cols, ptype, version))
    view = memoryview(buf)
    crc = np.fromiter(
        (
            zlib.crc32(view[i * size + len(MAGIC) : (i + 1) * size - CRC_SIZE])
            for i in range(len(picked))
        ),
        np.uint32,
        len(picked),
    )
    good = (
        (records["magic"] == (MAGIC_V2 if version == 2 else MAGIC))
        & (records["rows"] == rows)
        & (records["cols"] == cols)
        & (records["code"] == code)
        & np.isfinite(records["t_s"])
        & (records["crc"] == crc)
    )
    ok = np.zeros(len(datagrams), bool)
    ok[np.flatnonzero(fast)[good]] = True
    slot = np.cumsum(fast) - 1  # position of each fast datagram among the records
    out: list[FrameBatch] = []
    pending_odd: list[DecodedFrame] = []
    k = 0
    n = len(datagrams)
    while k < n:
        if not ok[k]:
            frame = decoder.decode_datagram(datagrams[k])
            if frame is not None:
                pending_odd.append(frame)
            k += 1
            continue
        stop = k + 1
        while stop < n and ok[stop]:
            stop += 1
        out.extend(batches_from_frames(pending_odd))
        pending_odd = []
        run = records[slot[k] : slot[stop - 1] + 1]
        index = run["index"].astype(np.int64)
        ids = run["array_id"].astype(np.int64) if version == 2 else None
        decoder.record_frames(index, (stop - k) * size, ids)
        values = run["payload"].copy()
        out.append(
            FrameBatch(
                index,
                run["t_s"].astype(np.float64),
                values != 0 if ptype == PayloadType.BOOL else values,
                ptype,
                ids,
            )
        )
        k = stop
    out.extend(batches_from_frames(pending_odd))
    return _merged(out)


def _merged(batches: list[FrameBatch]) -> list[FrameBatch]:
    """Join neighbouring batches of one shape and payload type."""
    out: list[FrameBatch] = []
    for b in batches:
        last = out[-1] if out else None
        if last is not None and last.shape == b.shape and last.payload_type == b.payload_type:
            ids = None
            if last.array_id is not None or b.array_id is not None:
                ids = np.concatenate([last.array_ids, b.array_ids])
            out[-1] = FrameBatch(
                np.concatenate([last.index, b.index]),
                np.concatenate([last.t_s, b.t_s]),
                np.concatenate([last.values, b.values]),
                b.payload_type,
                ids,
            )
        else:
            out.append(b)
    return out
