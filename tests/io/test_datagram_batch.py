"""Decoding datagrams in batches: the frames and counters of one-by-one decoding."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.io.datagram_batch import decode_datagrams
from taxelkit.io.frame_protocol import FrameDecoder, encode_frame


def _datagrams(seed: int) -> list[bytes]:
    rng = np.random.default_rng(seed)
    out: list[bytes] = []
    for i in range(300):
        if i % 50 == 7:  # a frame of another shape
            out.append(encode_frame(np.ones((3, 5), bool), index=i, t_s=0.01 * i))
            continue
        if i % 40 == 3:  # a lost packet
            continue
        values = rng.random((6, 4)) < 0.3 if seed % 2 else rng.random((6, 4)).astype(np.float32)
        raw = bytearray(encode_frame(values, index=i, t_s=0.01 * i))
        damage = rng.random()
        if damage < 0.03:
            raw[rng.integers(len(raw))] ^= 0xFF  # a flipped byte: bad CRC or header
        elif damage < 0.05:
            raw = raw[: rng.integers(1, len(raw))]  # truncated
        elif damage < 0.06:
            raw += b"x"  # too long
        out.append(bytes(raw))
    out.append(b"junk")
    return out


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_batch_decoding_equals_one_by_one(seed: int) -> None:
    datagrams = _datagrams(seed)
    one = FrameDecoder()
    frames = [f for f in (one.decode_datagram(d) for d in datagrams) if f is not None]
    batched = FrameDecoder()
    batches = []
    for a in range(0, len(datagrams), 64):  # several reads
        batches.extend(decode_datagrams(batched, datagrams[a : a + 64]))
    assert batched.stats == one.stats
    assert sum(b.n_frames for b in batches) == len(frames)
    flat = [
        (int(i), float(t), v)
        for b in batches
        for i, t, v in zip(b.index, b.t_s, b.values, strict=True)
    ]
    for (i, t, v), f in zip(flat, frames, strict=True):
        assert (i, t) == (f.index, f.t_s)
        assert v.dtype == f.values.dtype and np.array_equal(v, f.values)


def test_nothing_decodable() -> None:
    decoder = FrameDecoder()
    assert decode_datagrams(decoder, [b"", b"TXK", b"noise" * 10]) == []
    assert decoder.stats.corrupted == 3
