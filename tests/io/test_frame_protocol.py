"""The live frame protocol: layout, round trips, damage handling, resynchronisation."""

from __future__ import annotations

import struct
import zlib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from taxelkit.errors import InputError, TaxelkitError
from taxelkit.io.frame_protocol import (
    CRC_SIZE,
    HEADER_SIZE,
    MAGIC,
    DecodedFrame,
    FrameDecoder,
    PayloadType,
    encode_frame,
    packet_size,
    to_wire,
)

#: The worked example of docs/live-protocol.md: a 2 x 3 bool frame, index 7, t = 0.5 s.
GOLDEN_BOOL_HEX = (
    "54 58 4b 31 07 00 00 00 00 00 00 00 00 00 e0 3f 02 00 03 00 00 01 00 00 00 01 01 a0 bd 9c 08"
)
GOLDEN_BOOL_VALUES = np.array([[1, 0, 0], [0, 1, 1]], bool)


def _frames(n: int, shape: tuple[int, int] = (4, 5), seed: int = 0) -> list[np.ndarray]:
    rng = np.random.default_rng(seed)
    return [rng.random(shape) < 0.3 for _ in range(n)]


def _stream(frames: list[np.ndarray]) -> list[bytes]:
    return [encode_frame(f, index=i, t_s=0.01 * i) for i, f in enumerate(frames)]


def _decode_all(data: bytes, chunk: int | None = None) -> tuple[list[DecodedFrame], FrameDecoder]:
    dec = FrameDecoder()
    out: list[DecodedFrame] = []
    step = len(data) if chunk is None else chunk
    for i in range(0, len(data), max(step, 1)):
        out += dec.feed(data[i : i + step])
    out += dec.flush()
    return out, dec


# ----------------------------------------------------------------------------- layout
def test_golden_packet_matches_the_documented_example() -> None:
    packet = encode_frame(GOLDEN_BOOL_VALUES, index=7, t_s=0.5)
    assert packet.hex(" ") == GOLDEN_BOOL_HEX
    # The layout, field by field, built without the encoder:
    header = struct.pack("<4sIdHHB", b"TXK1", 7, 0.5, 2, 3, 0)
    payload = bytes([1, 0, 0, 0, 1, 1])
    crc = zlib.crc32(header[4:] + payload)
    assert packet == header + payload + struct.pack("<I", crc)
    (frame,) = FrameDecoder().feed(bytes.fromhex(GOLDEN_BOOL_HEX))
    np.testing.assert_array_equal(frame.values, GOLDEN_BOOL_VALUES)
    assert HEADER_SIZE == 21 and CRC_SIZE == 4 and MAGIC == b"TXK1"
    assert len(packet) == packet_size(2, 3, PayloadType.BOOL) == 31


def test_uint16_and_float32_payloads_are_little_endian() -> None:
    counts = np.array([[1, 2], [300, 65535]], np.uint16)
    packet = encode_frame(counts, index=1, t_s=0.25)
    assert packet[20] == PayloadType.UINT16
    assert packet[HEADER_SIZE:-CRC_SIZE] == bytes.fromhex("0100 0200 2c01 ffff")
    mm = np.array([[0.5, -1.0]], np.float64)
    packet = encode_frame(mm, index=2, t_s=0.0)
    assert packet[20] == PayloadType.FLOAT32
    assert packet[HEADER_SIZE:-CRC_SIZE] == struct.pack("<2f", 0.5, -1.0)


@pytest.mark.parametrize(
    ("values", "ptype"),
    [
        (np.array([[True, False, True], [False, False, True]]), PayloadType.BOOL),
        (np.array([[0, 1, 65535], [1000, 7, 42]], np.uint16), PayloadType.UINT16),
        (np.array([[0.0, 0.031, -0.5], [1e-6, 2.5, 100.0]], np.float32), PayloadType.FLOAT32),
    ],
)
def test_round_trip_each_payload_type(values: np.ndarray, ptype: PayloadType) -> None:
    packet = encode_frame(values, index=4_000_000_000, t_s=123.456789)
    frames, dec = _decode_all(packet)
    assert len(frames) == 1
    f = frames[0]
    assert (f.index, f.t_s, f.payload_type, f.shape) == (4_000_000_000, 123.456789, ptype, (2, 3))
    np.testing.assert_array_equal(f.values, values)
    assert f.values.dtype == values.dtype
    assert not f.values.flags.writeable
    assert dec.stats.frames == 1 and dec.stats.corrupted == 0 and dec.stats.bytes_skipped == 0
    assert FrameDecoder().decode_datagram(packet) is not None


def test_explicit_payload_type_and_bad_values_are_refused() -> None:
    packet = encode_frame(np.array([[0, 1]], np.int64), index=0, t_s=0, payload_type=0)
    assert packet[20] == PayloadType.BOOL
    with pytest.raises(InputError, match=r"\[0, 1\]"):
        encode_frame(np.array([[0, 2]]), index=0, t_s=0, payload_type=PayloadType.BOOL)
    with pytest.raises(InputError, match="65535"):
        encode_frame(np.array([[-1, 2]]), index=0, t_s=0)
    with pytest.raises(InputError, match="finite"):
        encode_frame(np.array([[np.nan]]), index=0, t_s=0)
    with pytest.raises(InputError, match="finite"):
        encode_frame(np.array([[1e39]]), index=0, t_s=0)  # overflows float32
    with pytest.raises(InputError, match="payload type UINT16, got float"):
        encode_frame(np.array([[0.5]]), index=0, t_s=0, payload_type=1)
    with pytest.raises(InputError, match="payload_type must be one of"):
        encode_frame(np.zeros((1, 1)), index=0, t_s=0, payload_type=9)
    with pytest.raises(InputError, match=r"shape \(rows, cols\)"):
        encode_frame(np.zeros(4), index=0, t_s=0)
    with pytest.raises(InputError, match="index"):
        encode_frame(np.zeros((1, 1)), index=2**32, t_s=0)
    with pytest.raises(InputError, match="t_s"):
        encode_frame(np.zeros((1, 1)), index=0, t_s=float("inf"))
    with pytest.raises(TaxelkitError, match="dtype"):
        to_wire(np.array([["a"]]))


# ----------------------------------------------------------------------------- damage
def test_garbage_between_packets_is_skipped_and_counted() -> None:
    frames = _frames(3)
    p = _stream(frames)
    data = b"\x00junk" + p[0] + b"TXK" + b"zz" + p[1] + b"\xff" * 10 + p[2] + b"tail"
    out, dec = _decode_all(data)
    assert [f.index for f in out] == [0, 1, 2]
    for f, ref in zip(out, frames, strict=True):
        np.testing.assert_array_equal(f.values, ref)
    s = dec.stats
    assert s.frames == 3 and s.corrupted == 0 and s.missing == 0
    assert s.bytes_skipped == 5 + 5 + 10 + 4
    assert s.bytes_received == len(data) == sum(map(len, p)) + s.bytes_skipped


@pytest.mark.parametrize("where", [4, 10, 17, HEADER_SIZE + 3, -2])
def test_a_flipped_byte_costs_one_packet_only(where: int) -> None:
    p = _stream(_frames(3))
    bad = bytearray(p[1])
    bad[where] ^= 0x40
    out, dec = _decode_all(p[0] + bytes(bad) + p[2])
    assert [f.index for f in out] == [0, 2]
    s = dec.stats
    assert s.corrupted == 1 and s.bad_header + s.bad_crc == 1
    assert s.missing == 1
    assert s.bytes_skipped == len(bad)


def test_bad_header_fields_are_refused_at_once() -> None:
    good = encode_frame(np.ones((2, 2), bool), index=1, t_s=0.0)
    headers = [
        struct.pack("<4sIdHHB", MAGIC, 0, 0.0, 2, 2, 7),  # unknown payload type
        struct.pack("<4sIdHHB", MAGIC, 0, 0.0, 0, 2, 0),  # zero rows
        struct.pack("<4sIdHHB", MAGIC, 0, float("nan"), 2, 2, 0),  # NaN timestamp
        struct.pack("<4sIdHHB", MAGIC, 0, 0.0, 60000, 60000, 2),  # too many taxels
    ]
    for header in headers:
        out, dec = _decode_all(header + good)
        assert [f.index for f in out] == [1]
        assert dec.stats.bad_header == 1 and dec.stats.corrupted == 1


def test_truncated_packet_followed_by_valid_ones_is_recovered() -> None:
    p = _stream(_frames(4))
    data = p[0] + p[1][:15] + p[2] + p[3][:-1]
    for chunk in (None, 1, 7, 64):
        out, dec = _decode_all(data, chunk)
        assert [f.index for f in out] == [0, 2]
        s = dec.stats
        assert s.corrupted == 2 and s.truncated == 1  # p[3] is still incomplete at the end
        assert s.bytes_received == len(p[0]) + len(p[2]) + s.bytes_skipped


def test_expected_shape_rejects_other_shapes() -> None:
    a = encode_frame(np.ones((2, 2), bool), index=0, t_s=0)
    b = encode_frame(np.ones((3, 2), bool), index=1, t_s=0)
    dec = FrameDecoder(shape=(2, 2))
    assert [f.index for f in dec.feed(b + a)] == [0]
    assert dec.stats.bad_header == 1
    with pytest.raises(InputError, match="shape"):
        FrameDecoder(shape=(0, 2))
    with pytest.raises(InputError, match="max_taxels"):
        FrameDecoder(max_taxels=0)


def test_a_damaged_size_field_delays_but_does_not_lose_later_packets() -> None:
    p = _stream(_frames(20, (8, 8)))
    bad = bytearray(p[0])
    bad[16:18] = struct.pack("<H", 200)  # rows 8 -> 200: announces 1,625 bytes
    dec = FrameDecoder()
    got = [f.index for f in dec.feed(bytes(bad) + b"".join(p[1:5]))]
    assert got == [] and dec.pending_bytes > 0  # waiting for the announced bytes
    got += [f.index for f in dec.feed(b"".join(p[5:]))]
    got += [f.index for f in dec.flush()]
    assert got == list(range(1, 20))
    assert dec.stats.bad_crc == 1 and dec.stats.missing == 0


def test_missing_indices_count_gaps_and_wrap_around() -> None:
    f = np.ones((1, 1), bool)
    dec = FrameDecoder()
    for i in (2**32 - 2, 2**32 - 1, 1, 2, 5, 0, 1):  # wrap skips 0, then 3-4, then a restart
        dec.feed(encode_frame(f, index=i, t_s=0))
    assert dec.stats.frames == 7 and dec.stats.missing == 1 + 2


def test_garbage_alone_keeps_the_buffer_bounded() -> None:
    dec = FrameDecoder()
    rng = np.random.default_rng(3)
    for _ in range(200):
        dec.feed(rng.integers(0, 256, 1000, dtype=np.uint8).tobytes().replace(b"TX", b"tx"))
        assert dec.pending_bytes <= 3
    dec.feed(b"TXK")
    assert dec.pending_bytes == 3
    assert dec.flush() == [] and dec.stats.bytes_skipped == 200_003


def test_byte_by_byte_feeding_of_a_large_frame() -> None:
    values = np.random.default_rng(0).random((64, 64)).astype(np.float32)
    packet = encode_frame(values, index=9, t_s=1.0)
    dec = FrameDecoder()
    got = [f for i in range(len(packet)) for f in dec.feed(packet[i : i + 1])]
    assert len(got) == 1 and got[0].index == 9
    np.testing.assert_array_equal(got[0].values, values)


# ----------------------------------------------------------------------------- datagrams
def test_datagrams_are_one_packet_each() -> None:
    p = encode_frame(np.ones((3, 3), bool), index=5, t_s=0.0)
    dec = FrameDecoder()
    frame = dec.decode_datagram(p)
    assert frame is not None and frame.index == 5
    assert dec.decode_datagram(p[:-1]) is None  # truncated
    assert dec.decode_datagram(p[:10]) is None  # truncated inside the header
    assert dec.decode_datagram(p + b"\x00") is None  # longer than announced
    assert dec.decode_datagram(b"hello world, not a packet") is None  # no magic
    flipped = bytearray(p)
    flipped[-1] ^= 1
    assert dec.decode_datagram(bytes(flipped)) is None  # CRC
    s = dec.stats
    assert (s.frames, s.truncated, s.bad_header, s.bad_crc) == (1, 2, 2, 1)
    assert s.bytes_skipped == s.bytes_received - len(p)


# ----------------------------------------------------------------------------- properties
@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=600), st.integers(1, 50))
def test_random_bytes_never_raise(data: bytes, chunk: int) -> None:
    dec = FrameDecoder()
    n = 0
    for i in range(0, len(data), chunk):
        n += len(dec.feed(data[i : i + chunk]))
    n += len(dec.flush())
    assert dec.decode_datagram(data) is None or len(data) >= HEADER_SIZE + CRC_SIZE
    s = dec.stats
    assert s.bytes_received >= len(data) and s.frames >= n


@settings(max_examples=200, deadline=None)
@given(
    st.lists(st.binary(max_size=40), min_size=4, max_size=4),
    st.lists(st.sampled_from([b"TXK1", b"TX", b"TXK1\x00\x00", b""]), min_size=4, max_size=4),
    st.integers(1, 97),
)
def test_valid_packets_survive_any_garbage_between_them(
    noise: list[bytes], traps: list[bytes], chunk: int
) -> None:
    frames = _frames(4, (3, 3), seed=1)
    packets = _stream(frames)
    data = b"".join(t + n + p for t, n, p in zip(traps, noise, packets, strict=True))
    out, dec = _decode_all(data, chunk)
    assert [f.index for f in out] == [0, 1, 2, 3]
    for f, ref in zip(out, frames, strict=True):
        np.testing.assert_array_equal(f.values, ref)
    s = dec.stats
    assert s.bytes_received == len(data) == sum(map(len, packets)) + s.bytes_skipped


@settings(max_examples=100, deadline=None)
@given(st.lists(st.integers(1, 96), min_size=1, max_size=30))
def test_chunking_does_not_change_the_frames(cuts: list[int]) -> None:
    data = b"".join(_stream(_frames(6, (4, 4), seed=2)))
    dec = FrameDecoder()
    got: list[int] = []
    pos = 0
    for c in cuts:
        got += [f.index for f in dec.feed(data[pos : pos + c])]
        pos += c
    got += [f.index for f in dec.feed(data[pos:])]
    assert got == list(range(6)) and dec.pending_bytes == 0
