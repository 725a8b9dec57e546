"""Small products of vectors and matrices in a fixed order of operations.

NumPy's ``@`` hands float64 products, even 3 x 3 ones, to its BLAS, and the
BLAS picks a kernel for the CPU at run time: with or without fused
multiply-adds, summing a dot product in one order or another. The results
differ in the last bit from one machine to the next (and under
``OPENBLAS_CORETYPE``). A physics rollout under feedback control (the MuJoCo
scenes' hand reads the body's state at every step) amplifies such a bit into
another motion. The functions here multiply and add element by element, index
by index, so that the same inputs give the same bits on every CPU. They are
meant for the few small products on such paths, not for large arrays. A
single small vector or matrix (a physics step's 3 x 3 products) is multiplied
in Python floats, in the same order and with the same bits as the array code
but without its per-call overhead.

NumPy's own loops are chosen by CPU too: on a CPU with AVX-512 (``X86_V4``)
its ``arctan2`` and ``arccos`` (and ``exp``, ``log``, ``arcsin``,
``arctan``) come from vectorised approximations that differ in the last bit
from the C library's, which NumPy calls elsewhere. :func:`arctan2` and
:func:`arccos` here call the C library element by element (``math.atan2``,
``math.acos``), for the angles the motion scripts and the rollouts'
sampling decide on: one such bit made a MuJoCo truncated cone's script take
another path.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "arccos",
    "arctan2",
    "dot",
    "matmul",
    "matvec",
    "norm",
    "rotate_points",
    "scalar_dot",
    "scalar_norm",
]


#: Largest single matrix (elements) multiplied in Python floats.
_SMALL = 16


def _sum_of_products(x: list[float], y: list[float]) -> float:
    """``x[0] * y[0] + x[1] * y[1] + ...`` from the left (the array code's order)."""
    if len(x) == 3:
        return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]
    acc = x[0] * y[0]
    for k in range(1, len(x)):
        acc = acc + x[k] * y[k]
    return acc


def dot(a: ArrayLike, b: ArrayLike) -> NDArray[np.float64]:
    """Dot products over the last axis, ``sum_k a[..., k] * b[..., k]`` from ``k = 0``.

    Parameters
    ----------
    a, b : (..., K) float
        Broadcast against each other.

    Returns
    -------
    (...) float64
    """
    x = np.asarray(a, dtype=np.float64)
    y = np.asarray(b, dtype=np.float64)
    if x.ndim == 1 and y.ndim == 1:
        return np.array(_sum_of_products(x.tolist(), y.tolist()))
    out: NDArray[np.float64] = x[..., 0] * y[..., 0]
    for k in range(1, x.shape[-1]):
        out = out + x[..., k] * y[..., k]
    return out


def matvec(m: ArrayLike, v: ArrayLike) -> NDArray[np.float64]:
    """Matrix times vector, ``m @ v`` summed from the first column.

    Parameters
    ----------
    m : (..., N, K) float
    v : (..., K) float

    Returns
    -------
    (..., N) float64
    """
    a = np.asarray(m, dtype=np.float64)
    if a.ndim == 2 and np.ndim(v) == 1 and a.size <= _SMALL:
        xs = np.asarray(v, dtype=np.float64).tolist()
        if len(xs) == 3:  # the physics step's case, written out (same order)
            x0, x1, x2 = xs
            rows = [r[0] * x0 + r[1] * x1 + r[2] * x2 for r in a.tolist()]
        else:
            rows = [_sum_of_products(row, xs) for row in a.tolist()]
        return np.array(rows, dtype=np.float64) if rows else np.zeros(0)
    x = np.asarray(v, dtype=np.float64)[..., None, :]
    out: NDArray[np.float64] = a[..., :, 0] * x[..., 0]
    for k in range(1, a.shape[-1]):
        out = out + a[..., :, k] * x[..., k]
    return out


def matmul(a: ArrayLike, b: ArrayLike) -> NDArray[np.float64]:
    """Matrix product ``a @ b`` summed from the first inner index.

    Parameters
    ----------
    a : (..., N, K) float
    b : (..., K, M) float

    Returns
    -------
    (..., N, M) float64
    """
    x = np.asarray(a, dtype=np.float64)
    y = np.asarray(b, dtype=np.float64)
    if x.ndim == 2 and y.ndim == 2 and x.size <= _SMALL and y.size <= _SMALL:
        cols = y.T.tolist()
        if x.shape[1] == 3:  # the physics step's case, written out (same order)
            cells = [[r[0] * c[0] + r[1] * c[1] + r[2] * c[2] for c in cols] for r in x.tolist()]
        else:
            cells = [[_sum_of_products(row, c) for c in cols] for row in x.tolist()]
        return np.array(cells, dtype=np.float64) if cells else np.zeros((0, y.shape[1]))
    out: NDArray[np.float64] = x[..., :, 0, None] * y[..., None, 0, :]
    for k in range(1, x.shape[-1]):
        out = out + x[..., :, k, None] * y[..., None, k, :]
    return out


def rotate_points(points: ArrayLike, rotation: ArrayLike) -> NDArray[np.float64]:
    """Points turned by rotations, ``points @ rotation.T`` (``R p`` per point).

    Parameters
    ----------
    points : (..., P, 3) float
    rotation : (..., 3, 3) float

    Returns
    -------
    (..., P, 3) float64
    """
    r: Any = np.asarray(rotation, dtype=np.float64)
    return matmul(points, np.swapaxes(r, -1, -2))


def norm(v: ArrayLike) -> NDArray[np.float64]:
    """Euclidean length over the last axis, ``sqrt(dot(v, v))``.

    Parameters
    ----------
    v : (..., K) float

    Returns
    -------
    (...) float64
    """
    return np.sqrt(dot(v, v))


def scalar_dot(a: ArrayLike, b: ArrayLike) -> float:
    """:func:`dot` of two vectors as a Python float."""
    return float(dot(a, b))


def scalar_norm(v: ArrayLike) -> float:
    """:func:`norm` of one vector as a Python float."""
    return math.sqrt(scalar_dot(v, v))


_ATAN2 = np.frompyfunc(math.atan2, 2, 1)
_ACOS = np.frompyfunc(math.acos, 1, 1)


def arctan2(y: ArrayLike, x: ArrayLike) -> NDArray[np.float64]:
    """``np.arctan2(y, x)`` (radians), element by element with the C library's ``atan2``.

    The same bits on every CPU (NumPy's AVX-512 loop differs in the last
    place). For the small arrays of the motion scripts, not for images.

    Parameters
    ----------
    y, x : array_like of float
        Broadcast together.

    Returns
    -------
    ndarray of float64
        Shaped as ``y`` and ``x`` broadcast.
    """
    out: NDArray[np.float64] = np.asarray(
        _ATAN2(np.asarray(y, dtype=np.float64), np.asarray(x, dtype=np.float64)), dtype=np.float64
    )
    return out


def arccos(x: ArrayLike) -> NDArray[np.float64]:
    """``np.arccos(x)`` (radians), element by element with the C library's ``acos``.

    ``x`` must lie in [-1, 1] (clip it first): ``math.acos`` raises where
    NumPy would give NaN.
    """
    out: NDArray[np.float64] = np.asarray(_ACOS(np.asarray(x, dtype=np.float64)), dtype=np.float64)
    return out
