"""Packets of the live frame protocol: layout, versions, encoder.

One packet carries one frame. All numbers are little-endian. Version 1
(magic ``TXK1``), one array per stream::

    offset  size  field
    0       4     magic b"TXK1"
    4       4     frame index, uint32
    8       8     timestamp, float64, s
    16      2     rows, uint16
    18      2     cols, uint16
    20      1     payload type, uint8 (0 bool, 1 uint16 counts, 2 float32 mm)
    21      N     payload: rows * cols values, row-major
    21 + N  4     CRC-32 (zlib.crc32) of bytes 4 .. 21 + N, uint32

Version 2 (magic ``TXK2``), many arrays on one stream: the same fields with
an array id after the timestamp, and the frame index counted per array::

    0       4     magic b"TXK2"
    4       4     frame index of this array, uint32
    8       8     timestamp, float64, s
    16      2     array id, uint16
    18      2     rows, uint16
    20      2     cols, uint16
    22      1     payload type, uint8
    23      N     payload
    23 + N  4     CRC-32 of bytes 4 .. 23 + N, uint32

A decoder reads both versions, mixed on one stream; a version 1 packet is
array 0. The specification for firmware writers is ``docs/live-protocol.md``;
the decoder is :mod:`taxelkit.io.frame_protocol`.
"""

from __future__ import annotations

import math
import struct
import zlib
from enum import IntEnum
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_finite_array

__all__ = [
    "CRC_SIZE",
    "DEFAULT_MAX_TAXELS",
    "HEADER_SIZE",
    "HEADER_SIZE_V2",
    "MAGIC",
    "MAGIC_V2",
    "MAX_ARRAY_ID",
    "MAX_DATAGRAM_BYTES",
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
#: First four bytes of a version 2 packet (an array id per frame).
MAGIC_V2 = b"TXK2"
#: Magic, index, timestamp, array id, rows, cols, payload type: 4 + 4 + 8 + 2 + 2 + 2 + 1 bytes.
_HEADER_V2 = struct.Struct("<4sIdHHHB")
#: Bytes before the payload of a version 2 packet.
HEADER_SIZE_V2 = _HEADER_V2.size
#: Both magics; their first three bytes are shared (:data:`_MAGIC_STEM`).
_MAGICS = (MAGIC, MAGIC_V2)
_MAGIC_STEM = b"TXK"
#: Largest array id (uint16).
MAX_ARRAY_ID = 2**16 - 1
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


def packet_size(rows: int, cols: int, payload_type: PayloadType | int, *, version: int = 1) -> int:
    """Bytes in one packet of a ``rows x cols`` frame, header and CRC included.

    ``version`` 2 packets (an array id per frame) are 2 bytes longer.

    Examples
    --------
    >>> packet_size(16, 16, PayloadType.BOOL), packet_size(16, 16, 0, version=2)
    (281, 283)
    """
    header = HEADER_SIZE_V2 if version == 2 else HEADER_SIZE
    return header + int(rows) * int(cols) * _ITEMSIZE[int(payload_type)] + CRC_SIZE


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
    array_id: int | None = None,
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
    array_id : int, optional
        Which array of a bank the frame comes from, ``0 <= array_id < 65536``:
        a version 2 packet (``TXK2``), whose ``index`` counts that array's
        frames. None (default): a version 1 packet (``TXK1``).

    Returns
    -------
    bytes
        ``packet_size(rows, cols, payload_type, version=...)`` bytes.

    Raises
    ------
    InputError
        On a wrong shape, an index, array id or timestamp out of range, or
        values that the payload type cannot carry.

    Examples
    --------
    >>> packet = encode_frame(np.eye(2, dtype=bool), index=7, t_s=0.5)
    >>> packet[:4], len(packet)
    (b'TXK1', 29)
    >>> encode_frame(np.eye(2, dtype=bool), index=7, t_s=0.5, array_id=3)[:4]
    b'TXK2'
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
    rows, cols = arr.shape
    if array_id is None:
        header = _HEADER.pack(MAGIC, int(index), t, rows, cols, int(ptype))
    elif isinstance(array_id, int | np.integer) and 0 <= int(array_id) <= MAX_ARRAY_ID:
        header = _HEADER_V2.pack(MAGIC_V2, int(index), t, int(array_id), rows, cols, int(ptype))
    else:
        raise InputError(f"array_id must be an integer in [0, {MAX_ARRAY_ID}], got {array_id!r}")
    crc = zlib.crc32(payload, zlib.crc32(header[len(MAGIC) :]))
    return b"".join((header, payload, _TRAILER.pack(crc)))
