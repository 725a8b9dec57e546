"""Version 2 packets (``TXK2``, an array id per frame): encoder, decoders, mixed with version 1."""

from __future__ import annotations

import binascii

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.io.datagram_batch import decode_datagrams
from taxelkit.io.frame_protocol import (
    HEADER_SIZE_V2,
    MAGIC_V2,
    FrameDecoder,
    encode_frame,
    packet_size,
)


def test_golden_v2_packet_matches_the_documented_example() -> None:
    values = np.array([[1, 0, 0], [0, 1, 1]], dtype=bool)
    packet = encode_frame(values, index=7, t_s=0.5, array_id=3)
    assert packet.hex(" ") == (
        "54 58 4b 32 07 00 00 00 00 00 00 00 00 00 e0 3f 03 00 02 00 03 00 00 "
        "01 00 00 00 01 01 85 8c 0f af"
    )  # the bytes of docs/live-protocol.md
    assert len(packet) == packet_size(2, 3, 0, version=2) == HEADER_SIZE_V2 + 6 + 4
    assert binascii.crc32(packet[4:-4]) == 0xAF0F8C85


@pytest.mark.parametrize("bad", [-1, 65536, 1.5, "3"])
def test_array_id_out_of_range_is_refused(bad: object) -> None:
    with pytest.raises(InputError, match="array_id"):
        encode_frame(np.zeros((2, 2), bool), index=0, t_s=0.0, array_id=bad)  # type: ignore[arg-type]


def _mixed_stream(rng: np.random.Generator) -> tuple[bytes, list[tuple[int, int, int]]]:
    """Version 1 and 2 packets of three arrays with noise between them; (array, index, sum)."""
    out, want = bytearray(), []
    for j in range(60):
        arr = j % 3
        values = rng.random((4, 5)) < 0.3
        v2 = arr > 0 or j % 2 == 0
        out += encode_frame(values, index=j // 3, t_s=j * 0.01, array_id=arr if v2 else None)
        want.append((arr, j // 3, int(values.sum())))
        if j % 7 == 0:
            out += b"TXK" + bytes(rng.integers(0, 256, 5, dtype=np.uint8))  # noise like a magic
    return bytes(out), want


@pytest.mark.parametrize("chunk", [1, 13, 4096])
def test_a_stream_mixing_both_versions_decodes_in_any_chunking(chunk: int) -> None:
    data, want = _mixed_stream(np.random.default_rng(0))
    dec = FrameDecoder()
    frames = []
    for a in range(0, len(data), chunk):
        frames += dec.feed(data[a : a + chunk])
    frames += dec.flush()
    assert [(f.array_id, f.index, int(f.values.sum())) for f in frames] == want
    assert dec.stats.missing == 0  # indices count per array: no gap
    assert dec.stats.corrupted == 0 and dec.stats.bytes_skipped == 9 * 8


def test_missing_frames_are_counted_per_array() -> None:
    dec = FrameDecoder()
    blank = np.zeros((2, 2), bool)
    for index, arr in [(0, 0), (0, 1), (1, 0), (1, 1), (2, 1), (4, 0), (3, 1)]:
        dec.decode_datagram(encode_frame(blank, index=index, t_s=0.0, array_id=arr))
    assert dec.stats.frames == 7 and dec.stats.missing == 2  # array 0 lost 2 and 3


def test_datagram_batches_carry_array_ids_as_one_by_one() -> None:
    rng = np.random.default_rng(1)
    grams = [
        encode_frame(rng.random((16, 16)) < 0.2, index=i // 4, t_s=i / 960, array_id=i % 4)
        for i in range(200)
    ]
    grams[17] = grams[17][:-1] + bytes([grams[17][-1] ^ 1])  # a bad CRC
    grams[18] = encode_frame(np.ones((16, 16), bool), index=4, t_s=0.1)  # version 1: array 0
    grams[41] = grams[41][:10]  # truncated
    fast, slow = FrameDecoder(), FrameDecoder()
    batches = decode_datagrams(fast, grams)
    one = [f for f in (slow.decode_datagram(g) for g in grams) if f is not None]
    assert sum(b.n_frames for b in batches) == len(one) == 198
    got = np.concatenate([b.array_ids for b in batches])
    np.testing.assert_array_equal(got, [f.array_id for f in one])
    np.testing.assert_array_equal(
        np.concatenate([b.values for b in batches]), np.stack([f.values for f in one])
    )
    assert fast.stats == slow.stats
    # lost: array 1's frames 4 (bad CRC) and 10 (truncated), array 2's frame 4 (replaced)
    assert fast.stats.missing == slow.stats.missing == 3


def test_a_version_2_datagram_starts_with_its_magic() -> None:
    packet = encode_frame(np.eye(3, dtype=bool), index=1, t_s=2.0, array_id=65535)
    frame = FrameDecoder().decode_datagram(packet)
    assert packet[:4] == MAGIC_V2 and frame is not None and frame.array_id == 65535
