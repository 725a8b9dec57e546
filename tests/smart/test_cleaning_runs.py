"""Work done once per run (of equal frames, of a segment's anchors): the per-frame results."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.smart.cleaning import CleaningConfig, _clean, clean_images
from taxelkit.smart.cleaning_chunks import ChunkCleaner, _held_along_time
from taxelkit.smart.cleaning_runs import clean_runs, clean_runs_if_worth, run_starts
from taxelkit.smart.cleaning_stream import ImageCleaner
from taxelkit.smart.gather import take_rows
from taxelkit.smart.packed_rows import backend_for
from taxelkit.smart.segment_runs import Runs, run_anchors
from taxelkit.smart.track_geometry import anchors


def held_frames(rng: np.random.Generator, m: int, t: int, shape: tuple[int, int]) -> np.ndarray:
    """Random sparse frames ``(m, t, rows, cols)``, each held for a random number of frames."""
    out = np.empty((m, t, *shape), bool)
    for i in range(m):
        k = 0
        while k < t:
            frame = rng.random(shape) < rng.choice([0.0, 0.05, 0.2, 0.5])
            n = int(rng.integers(1, 8))
            out[i, k : k + n] = frame
            k += n
    return out


def per_frame(ops, a, prev, prev_passed, cfg, m, t):  # type: ignore[no-untyped-def]
    """_clean over ``m`` arrays of ``t`` frames, each from its own previous frames."""
    word = a.shape[1:]

    def after(first, frames):  # type: ignore[no-untyped-def]
        f3 = frames.reshape(m, t, *word)
        return np.concatenate([first[:, None], f3[:, :-1]], axis=1).reshape(frames.shape)

    out, passed = _clean(ops, a, prev, prev_passed, cfg, after)
    return out, passed.reshape(m, t, *word)[:, -1]


@pytest.mark.parametrize("shape", [(16, 16), (8, 8), (6, 12), (4, 70)])
@pytest.mark.parametrize("depth", [1, 2])
@pytest.mark.parametrize("strays", [True, False])
def test_runs_give_the_frame_by_frame_images(
    shape: tuple[int, int], depth: int, strays: bool
) -> None:
    rng = np.random.default_rng(sum(shape) + 10 * depth + strays)
    cfg = CleaningConfig(persistence_depth=depth, strays=strays)
    ops = backend_for(shape[1])
    for m, t in [(1, 1), (1, 40), (3, 25), (5, 1)]:
        a = ops.pack(held_frames(rng, m, t, shape).reshape(m * t, *shape))
        prev = ops.pack(rng.random((m, *shape)) < 0.3)
        prev_passed = prev & ops.pack(rng.random((m, *shape)) < 0.5)
        new = run_starts(a, t)
        if new is None:  # rows that do not fill 64-bit words: the per-frame rules only
            assert (a.shape[1] * a.itemsize) % 8
            continue
        assert new[::t].all()
        first, run = np.flatnonzero(new), np.cumsum(new) - 1
        got = clean_runs(ops, take_rows(a, first), first, run, t, prev, prev_passed, cfg)
        want = per_frame(ops, a, prev, prev_passed, cfg, m, t)
        np.testing.assert_array_equal(got[0], want[0])
        np.testing.assert_array_equal(got[1], want[1])


def test_the_chunk_cleaner_goes_by_runs_and_cleans_as_before() -> None:
    rng = np.random.default_rng(5)
    img = held_frames(rng, 2, 300, (16, 16))
    img[:, :, :4, :4] = img[:, :, 12:, 12:] = False
    img[:, 40:250, 1, 1] = True  # isolated for more than stuck_s: masked, then released
    img[:, :100, 14, 14] = True  # on from the start: masked until it reads off
    t = np.broadcast_to(np.arange(300) / 20.0, (2, 300))
    cfg = CleaningConfig()
    by_runs = ChunkCleaner(2, (16, 16), config=cfg)
    chunks = [by_runs.push(img[:, a : a + 70], t[:, a : a + 70]) for a in range(0, 300, 70)]
    alone = [ChunkCleaner(1, (16, 16), config=cfg) for _ in range(2)]
    # one frame a push: no run longer than one frame, the rules frame by frame
    frames = [
        np.concatenate(
            [c.push(img[i : i + 1, k : k + 1], t[i : i + 1, k : k + 1]) for k in range(300)], axis=1
        )
        for i, c in enumerate(alone)
    ]
    np.testing.assert_array_equal(np.concatenate(chunks, axis=1), np.concatenate(frames))


def test_take_rows_is_fancy_indexing() -> None:
    rng = np.random.default_rng(0)
    for x in [rng.random(7), rng.random((7, 2)), rng.random((7, 3, 4)) < 0.5, rng.random((0, 3))]:
        idx = rng.integers(0, max(1, x.shape[0]), 9) if x.shape[0] else np.zeros(0, np.intp)
        np.testing.assert_array_equal(take_rows(x, idx), x[idx])
        np.testing.assert_array_equal(take_rows(x[::2], idx // 2), x[::2][idx // 2])


@pytest.mark.parametrize("k", [1, 3, 8])
@pytest.mark.parametrize("tolerance", [0.05, 0.3])
def test_run_anchors_are_each_segments_anchors(k: int, tolerance: float) -> None:
    rng = np.random.default_rng(k)
    lengths = rng.integers(1, 60, 40)
    runs = Runs(lengths)
    # areas that step now and then (a face landing), elongations that drift
    area = np.exp(np.cumsum(rng.normal(0, 0.08, runs.size) * (rng.random(runs.size) < 0.3)))
    elong = 1.0 + np.abs(np.cumsum(rng.normal(0, 0.05, runs.size)))
    got = run_anchors(runs, area, elong, k, tolerance)
    for a, n in zip(runs.starts.tolist(), lengths.tolist(), strict=True):
        want = anchors(area[a : a + n], elong[a : a + n], k, tolerance)
        np.testing.assert_array_equal(got[a : a + n], want)


@pytest.mark.parametrize("depth", [1, 2])
def test_batch_cleaning_by_runs_is_the_streamed_cleaning(depth: int) -> None:
    rng = np.random.default_rng(depth)
    img = held_frames(rng, 1, 400, (16, 16))[0]
    img[:, :4, :4] = img[:, 12:, 12:] = False
    img[30:300, 1, 1] = True  # isolated for more than stuck_s: masked, then released
    img[:120, 14, 14] = True  # on from the start
    t = np.arange(400) / 20.0
    cfg = CleaningConfig(persistence_depth=depth)
    ops = backend_for(16)
    a = ops.pack(img)
    assert clean_runs_if_worth(ops, a, 400, a[:1] * 0, a[:1] * 0, cfg) is not None  # by runs
    cleaner = ImageCleaner((16, 16), config=cfg)
    stream = np.stack([cleaner.push(f, ts) for f, ts in zip(img, t, strict=True)])
    np.testing.assert_array_equal(clean_images(img, t, config=cfg), stream)


def test_held_along_time_is_the_and_over_each_window() -> None:
    rng = np.random.default_rng(3)
    for _ in range(200):
        m, t = int(rng.integers(1, 3)), int(rng.integers(1, 60))
        a = (rng.random((m, t, 2)) < rng.choice([0.5, 0.95, 1.0])).astype(np.uint16)
        a |= (rng.random((m, t, 2)) < 0.9).astype(np.uint16) << np.uint16(5)
        for n in [1, 2, 5, 17, 80]:
            want = np.zeros_like(a)
            for j in range(n - 1, t):
                want[:, j] = np.bitwise_and.reduce(a[:, j - n + 1 : j + 1], axis=1)
            np.testing.assert_array_equal(_held_along_time(a, n), want)
