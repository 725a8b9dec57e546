"""Exact index sums of binary contact images: the kernel under Level 1's moments.

For each frame, ``n, sum u, sum v, sum u^2, sum v^2, sum u v`` over the
taxels in contact, ``u`` (columns) and ``v`` (rows) centred index coordinates
in pitch units. The sums are multiples of 1/4 and computed exactly (one
float32 matrix product per chunk of frames for arrays up to about 60 x 60,
separably by rows beyond), so they do not depend on how frames are batched:
:mod:`taxelkit.smart.moments` finishes them into physical statistics, and
:mod:`taxelkit.smart.area_moments` and the streaming path share them.
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "CHUNK_FRAMES",
    "ONE_THREAD_PRODUCT",
    "SEPARABLE_MAX_COLS",
    "centred_index",
    "index_basis",
    "index_sums",
    "index_sums_by_rows",
    "product_rows",
]

#: Frames processed together: the float copy of a chunk of binary images stays
#: in cache (0.5 MB for 16 x 16); measured 1.4 M frames/s against 1.0 M with
#: chunks of 32768 (benchmarks/bench_smart.py).
CHUNK_FRAMES = 512
#: Largest product ``m * n * k`` that OpenBLAS computes on one thread whatever
#: the number of cores: it splits a matrix product ``(m, k) @ (k, n)`` among
#: ``m n k / 262144`` threads (65536 times its ``GEMM_MULTITHREAD_THRESHOLD``
#: of 4), rounded down, so below twice that it uses one. Above it, on a 2-core
#: machine, the threads' hand-offs made the 512-frame product of 16 x 16
#: images up to 100 times slower (8 ms against 80 us, timed by hand), nearly
#: half the time of Levels 1-4 out of core (profiled), wherever
#: ``OPENBLAS_NUM_THREADS`` was not set to 1 (``benchmarks/bench_blas_threads.py``
#: measures both ways). Products here stay below it.
ONE_THREAD_PRODUCT = 2 * 262_144 - 1
#: Widest array whose row sums of ``u^2`` are exact in float32 (``cols^3 < 2^24``).
SEPARABLE_MAX_COLS = 256


def centred_index(n: int) -> NDArray[np.float64]:
    """Cell-centre coordinates ``k - (n - 1) / 2`` in pitch units (half integers)."""
    return np.arange(n, dtype=np.float64) - (n - 1) / 2.0


def index_basis(rows: int, cols: int) -> NDArray[np.float64]:
    """``(rows * cols, 6)``: ``1, u, v, u^2, v^2, u v`` at every taxel, row-major.

    ``u`` (columns) and ``v`` (rows) are centred index coordinates
    (:func:`centred_index`); one frame's row-major ravel times this basis
    gives the six sums of :func:`index_sums`.
    """
    uu, vv = np.meshgrid(centred_index(cols), centred_index(rows))
    return np.stack(
        [
            np.ones(uu.size),
            uu.ravel(),
            vv.ravel(),
            uu.ravel() ** 2,
            vv.ravel() ** 2,
            (uu * vv).ravel(),
        ],
        axis=1,
    )


@functools.lru_cache(maxsize=16)
def _basis(rows: int, cols: int, exact32: bool) -> NDArray[np.floating[Any]]:
    """:func:`index_basis` in float32 (``exact32``) or float64, kept (read-only)."""
    out: NDArray[np.floating[Any]] = index_basis(rows, cols).astype(
        np.float32 if exact32 else np.float64
    )
    out.flags.writeable = False
    return out


def index_sums(images: NDArray[np.bool_]) -> NDArray[np.float64]:
    """``(6, T)``: ``n, sum u, sum v, sum u^2, sum v^2, sum u v`` over the taxels in contact.

    ``u`` (columns) and ``v`` (rows) are centred index coordinates (half
    integers), so every sum is a multiple of 1/4 below ``rows * cols^3 / 4``
    and exact in float64 for arrays up to about 9000 x 9000 taxels; the result
    does not depend on the order of summation, hence not on how frames are
    batched. For arrays small enough that every sum stays below 2^24 / 4 (up to
    about 60 x 60 taxels), one float32 matrix product per chunk computes them
    exactly and fast.
    """
    n_t, rows, cols = images.shape
    u = centred_index(cols)
    v = centred_index(rows)
    if rows * cols * max(rows, cols) ** 2 >= 2**22 and cols < SEPARABLE_MAX_COLS:
        return index_sums_by_rows(images, u, v)
    exact32 = rows * cols * max(rows, cols) ** 2 < 2**22  # every partial sum exact in float32
    dtype: type[np.floating[Any]] = np.float32 if exact32 else np.float64
    basis_t = _basis(rows, cols, exact32)
    out = np.empty((6, n_t), dtype=np.float64)
    flat = images.reshape(n_t, rows * cols)
    step = product_rows(rows * cols, 6)
    for a in range(0, n_t, step):
        b = min(n_t, a + step)
        chunk: NDArray[np.floating[Any]] = flat[a:b].astype(dtype)
        out[:, a:b] = (chunk @ basis_t).T
    return out


def product_rows(inner: int, outer: int, most: int = CHUNK_FRAMES) -> int:
    """Rows of ``(rows, inner) @ (inner, outer)`` products that BLAS runs on one thread.

    At most ``most`` and at least 1, so that ``rows * inner * outer`` stays
    within :data:`ONE_THREAD_PRODUCT` (341 frames of 16 x 16 images with the
    six sums, 85 of 32 x 32).

    Examples
    --------
    >>> product_rows(16 * 16, 6), product_rows(32 * 32, 6), product_rows(8 * 8, 6)
    (341, 85, 512)
    """
    return max(1, min(int(most), ONE_THREAD_PRODUCT // max(1, int(inner) * int(outer))))


def index_sums_by_rows(
    images: NDArray[np.bool_], u: NDArray[np.float64], v: NDArray[np.float64]
) -> NDArray[np.float64]:
    """:func:`index_sums` of larger arrays, separably: rows first, then frames.

    Each row's ``sum 1, sum u, sum u^2`` is one float32 product with a
    ``(cols, 3)`` basis (exact: multiples of 1/4 below ``cols^3 / 4 < 2^22``
    for ``cols`` < :data:`SEPARABLE_MAX_COLS`); the sums over rows, weighted
    by ``1, v, v^2``, are float64 and exact as well, so the result is that of
    the one-product path. A ``(rows * cols, 6)`` product in float64 costs
    three times as much per taxel from 64 x 64 up.
    """
    n_t, rows, cols = images.shape
    row_basis = np.stack([np.ones(cols), u, u * u], axis=1).astype(np.float32)
    frame_basis = np.stack([np.ones(rows), v, v * v], axis=0)  # (3, rows)
    out = np.empty((6, n_t), dtype=np.float64)
    step = max(1, CHUNK_FRAMES * 256 // (rows * cols))  # the same bytes per chunk as 16 x 16
    for a in range(0, n_t, step):
        b = min(n_t, a + step)
        per_row = (images[a:b].astype(np.float32) @ row_basis).astype(np.float64)  # (t, rows, 3)
        n1 = per_row[:, :, 0] @ frame_basis.T  # (t, 3): sums of 1, v, v^2 over the taxels
        su = per_row[:, :, 1] @ frame_basis[:2].T  # (t, 2): sums of u, u v
        out[0, a:b] = n1[:, 0]
        out[1, a:b] = su[:, 0]
        out[2, a:b] = n1[:, 1]
        out[3, a:b] = per_row[:, :, 2].sum(axis=1)
        out[4, a:b] = n1[:, 2]
        out[5, a:b] = su[:, 1]
    return out
