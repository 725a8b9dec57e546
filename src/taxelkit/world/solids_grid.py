"""Batched evaluation of convex bodies along vertical lines: the engine behind the solids.

A convex body is an intersection of constraints. Along the vertical line
through ``(x, y)`` each constraint allows an interval of heights ``z``; the
body's bottom on that line is the largest lower end, valid where it does not
exceed the smallest upper end. Every solid in :mod:`taxelkit.world.solids`
reduces its constraints to a handful of per-pose functions of the line
position that are combinations of the four *basis functions*

    1,  x,  y,  q = x**2 + y**2

(planes give ``z = alpha + beta x + gamma y``; spheres, cylinders and cones
need ``q`` as well). The sensor samples every pose on the same grid, shifted
by the pose's position, so all these functions are evaluated for a whole batch
by one matrix product ``(poses x functions, 4) @ (4, grid points)`` against a
shared basis (summed term by term in a fixed order, the same bits on every
CPU); the per-solid combination that follows (maxima, minima, a square
root) runs on contiguous blocks that stay in cache. Per-pose coefficients are
computed in float64 and cast to the grid's dtype before the grid work, so a
float32 grid is evaluated in float32 (a solid may ask for float64 on the few
poses where a float32 formula would lose accuracy, see
:attr:`PoseGroup.float64`).

Grids that are not translates of one another (within
:data:`SHARED_GRID_ULPS` units in the last place) are evaluated with a
per-pose basis instead: the same results, only slower.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit._fixed_order import matmul as fo_matmul
from taxelkit.errors import InputError, check_finite_array

__all__ = [
    "BASIS_SIZE",
    "BLOCK_ELEMENTS",
    "SHARED_GRID_ULPS",
    "TILT_EPS",
    "Combine",
    "LineGrid",
    "PoseGroup",
    "as_rotation_batch",
    "evaluate_bottom",
    "finish_interval",
    "line_grid",
]

#: Number of basis functions: 1, x, y, x**2 + y**2.
BASIS_SIZE = 4

#: Poses x grid points evaluated together: 128 KB per float32 temporary, so a
#: block's temporaries stay in a core's L2 cache (tuned on the 20 x 20 grid of
#: the Bonneville array: 2**14 to 2**15 is fastest, 2**17 is 1.5-2x slower).
BLOCK_ELEMENTS = 1 << 15

#: Grids whose rows differ from a common pattern by at most this many units in
#: the last place (of the grid's dtype, relative to its largest coordinate)
#: share one basis; the sensor's grids differ by rounding only.
SHARED_GRID_ULPS = 16.0

#: Smallest ``|n_z|`` of a bounding plane: a vertical plane is tilted by this
#: much (a lateral shift below 1e-7 mm over a 100 mm tall body), which turns
#: its restriction of ``(x, y)`` into a very steep height bound and keeps every
#: constraint in the same form.
TILT_EPS = 1e-9

#: A per-solid combination step for one block of ``n`` poses: ``slabs`` holds
#: the evaluated functions ``(R, n, H*W)``, ``work`` scratch arrays ``(n,
#: H*W)``, ``out`` receives the bottom ``(n, H*W)`` and ``pose_values`` holds
#: per-pose scalars ``(n, S)``.
Combine = Callable[[NDArray[Any], Sequence[NDArray[Any]], NDArray[Any], NDArray[Any]], None]


@dataclass(frozen=True, eq=False)
class LineGrid:
    """The vertical lines of a batch, decomposed into a shared pattern and offsets.

    Attributes
    ----------
    dtype : numpy.dtype
        Working precision (float32 or float64), taken from ``x_mm``.
    n_poses, rows, cols : int
        ``P``, ``H`` and ``W``.
    origin_x_mm, origin_y_mm : (P,) float64, mm
        Per-pose origin of the pattern (middle of the first and last column/row).
    basis : (4, H*W) float64 or None
        Shared basis ``1, X, Y, X**2 + Y**2`` with ``(X, Y)`` relative to the
        origin; ``None`` when the grids are not translates of one another.
    pose_basis : (P, 4, H*W) float64 or None
        Per-pose basis, used when ``basis`` is ``None``.
    """

    dtype: np.dtype[Any]
    n_poses: int
    rows: int
    cols: int
    origin_x_mm: NDArray[np.float64]
    origin_y_mm: NDArray[np.float64]
    basis: NDArray[np.float64] | None
    pose_basis: NDArray[np.float64] | None


def as_rotation_batch(rotations: ArrayLike) -> NDArray[np.float64]:
    """Return ``rotations`` as a finite ``(P, 3, 3)`` float64 array.

    A single ``(3, 3)`` matrix becomes ``(1, 3, 3)``. Orthonormality is not
    re-checked here (the simulator checks it once with
    :func:`taxelkit.world.pose.check_rotations`).

    Raises
    ------
    InputError
        If the shape is wrong or a value is not finite.
    """
    r = np.asarray(rotations, dtype=np.float64)
    if r.shape == (3, 3):
        r = r[None]
    if r.ndim != 3 or r.shape[1:] != (3, 3):
        raise InputError(f"rotations must have shape (P, 3, 3), got {r.shape}")
    check_finite_array("rotations", r)
    return r


def _working_dtype(x: NDArray[Any]) -> np.dtype[Any]:
    if x.dtype == np.float32 or x.dtype == np.float64:
        return x.dtype
    return np.dtype(np.float64)


def line_grid(x_mm: ArrayLike, y_mm: ArrayLike, n_poses: int) -> LineGrid:
    """Validate a batch of grids and build its basis.

    Parameters
    ----------
    x_mm : (P, W) float, mm
        x of the grid columns per pose, relative to the body's reference point.
    y_mm : (P, H) float, mm
        y of the grid rows per pose.
    n_poses : int
        ``P``, the number of rotations.

    Returns
    -------
    LineGrid

    Raises
    ------
    InputError
        If a shape does not match or a coordinate is not finite.
    """
    x = np.asarray(x_mm)
    y = np.asarray(y_mm)
    if x.ndim != 2 or x.shape[0] != n_poses:
        raise InputError(f"x_mm must have shape ({n_poses}, W), got {x.shape}")
    if y.ndim != 2 or y.shape[0] != n_poses:
        raise InputError(f"y_mm must have shape ({n_poses}, H), got {y.shape}")
    dtype = _working_dtype(x)
    x = x.astype(dtype, copy=False)
    y = y.astype(dtype, copy=False)
    rows, cols = y.shape[1], x.shape[1]
    if n_poses == 0 or rows == 0 or cols == 0:
        check_finite_array("x_mm", x)
        check_finite_array("y_mm", y)
        empty = np.zeros(n_poses)
        return LineGrid(dtype, n_poses, rows, cols, empty, empty, None, None)
    # Shared pattern test in the grid's own precision (cheap): NaN or inf
    # anywhere makes a deviation NaN, the test fails and the explicit finite
    # check below names the culprit.
    dev_x = x - x[:, :1]
    dev_x -= dev_x[0]
    dev_y = y - y[:, :1]
    dev_y -= dev_y[0]
    dev = max(float(np.abs(dev_x).max()), float(np.abs(dev_y).max()))
    ox = 0.5 * (x[:, 0].astype(np.float64) + x[:, -1])
    oy = 0.5 * (y[:, 0].astype(np.float64) + y[:, -1])
    dx0 = x[0].astype(np.float64) - ox[0]
    dy0 = y[0].astype(np.float64) - oy[0]
    scale = max(1.0, float(np.abs(ox).max() + np.abs(dx0).max()))
    scale = max(scale, float(np.abs(oy).max() + np.abs(dy0).max()))
    tol = SHARED_GRID_ULPS * float(np.finfo(dtype).eps) * scale
    if dev <= tol:
        gx = np.broadcast_to(dx0[None, :], (rows, cols)).ravel()
        gy = np.broadcast_to(dy0[:, None], (rows, cols)).ravel()
        basis = np.stack([np.ones_like(gx), gx, gy, gx * gx + gy * gy])
        return LineGrid(dtype, n_poses, rows, cols, ox, oy, basis, None)
    check_finite_array("x_mm", x)
    check_finite_array("y_mm", y)
    dx = x.astype(np.float64) - ox[:, None]
    dy = y.astype(np.float64) - oy[:, None]
    gx3 = np.broadcast_to(dx[:, None, :], (n_poses, rows, cols)).reshape(n_poses, -1)
    gy3 = np.broadcast_to(dy[:, :, None], (n_poses, rows, cols)).reshape(n_poses, -1)
    pose_basis = np.stack([np.ones_like(gx3), gx3, gy3, gx3 * gx3 + gy3 * gy3], axis=1)
    return LineGrid(dtype, n_poses, rows, cols, ox, oy, None, pose_basis)


def _basis_coefficients(
    grid: LineGrid, funcs: NDArray[np.float64], indices: NDArray[np.intp] | None
) -> NDArray[np.float64]:
    """Coefficients on the grid's basis of functions given on ``(1, x, y, q)``.

    With ``x = X + ox`` and ``y = Y + oy``: ``q = Q + 2 ox X + 2 oy Y + ox**2 + oy**2``.
    """
    ox = grid.origin_x_mm if indices is None else grid.origin_x_mm[indices]
    oy = grid.origin_y_mm if indices is None else grid.origin_y_mm[indices]
    ox, oy = ox[:, None], oy[:, None]
    a, b, g, d = funcs[..., 0], funcs[..., 1], funcs[..., 2], funcs[..., 3]
    out = np.empty_like(funcs)
    out[..., 0] = a + b * ox + g * oy + d * (ox * ox + oy * oy)
    out[..., 1] = b + 2.0 * d * ox
    out[..., 2] = g + 2.0 * d * oy
    out[..., 3] = d
    return out


@dataclass(frozen=True, eq=False)
class PoseGroup:
    """Poses evaluated with the same function table layout and combination.

    Attributes
    ----------
    indices : (n,) int or None
        Sorted pose indices; ``None`` for all poses.
    funcs : (n, R, 4) float64
        Coefficients of ``R`` functions on ``(1, x, y, x**2 + y**2)`` per pose.
    combine : Combine
        Turns the evaluated functions into the bottom.
    n_work : int
        Scratch arrays ``combine`` needs.
    pose_values : (n, S) float64 or None
        Per-pose scalars handed to ``combine`` (cast to the working dtype).
    float64 : bool
        Evaluate in float64 whatever the grid's dtype (for poses whose
        formulas lose too much in float32); the result is cast back.
    """

    indices: NDArray[np.intp] | None
    funcs: NDArray[np.float64]
    combine: Combine
    n_work: int
    pose_values: NDArray[np.float64] | None = None
    float64: bool = False


class _Buffers:
    """Scratch arrays of one dtype, allocated on first use and reused per block."""

    def __init__(self, dtype: np.dtype[Any], rows: int, work: int, block: int, n_pts: int):
        self.slabs = np.empty((rows * block, n_pts), dtype=dtype)
        self.term = np.empty((rows * block, n_pts), dtype=dtype)
        self.work = np.empty((work + 1, block, n_pts), dtype=dtype)


def evaluate_bottom(grid: LineGrid, groups: Sequence[PoseGroup]) -> NDArray[Any]:
    """Evaluate per-pose functions on the grid and combine them into the bottom.

    Parameters
    ----------
    grid : LineGrid
    groups : sequence of PoseGroup
        Together they must cover every pose exactly once.

    Returns
    -------
    (P, H, W) float, mm
        In the grid's dtype; ``+inf`` where a line misses the body.
    """
    n_poses, rows, cols = grid.n_poses, grid.rows, grid.cols
    out = np.empty((n_poses, rows, cols), dtype=grid.dtype)
    if out.size == 0 or not groups:
        return out
    n_pts = rows * cols
    flat = out.reshape(n_poses, n_pts)
    block = max(1, min(n_poses, BLOCK_ELEMENTS // n_pts))
    max_rows = max(g.funcs.shape[1] for g in groups)
    max_work = max(g.n_work for g in groups)
    buffers: dict[np.dtype[Any], _Buffers] = {}
    bases: dict[np.dtype[Any], NDArray[Any]] = {}
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for group in groups:
            count = group.funcs.shape[0]
            if count == 0:
                continue
            dtype = np.dtype(np.float64) if group.float64 else grid.dtype
            if dtype not in buffers:
                buffers[dtype] = _Buffers(dtype, max_rows, max_work, block, n_pts)
                if grid.basis is not None:
                    bases[dtype] = grid.basis.astype(dtype)
            _evaluate_group(grid, group, dtype, bases.get(dtype), buffers[dtype], block, flat)
    return out


def _evaluate_group(
    grid: LineGrid,
    group: PoseGroup,
    dtype: np.dtype[Any],
    basis: NDArray[Any] | None,
    buf: _Buffers,
    block: int,
    flat: NDArray[Any],
) -> None:
    idx = group.indices
    count, n_rows = group.funcs.shape[:2]
    n_pts = flat.shape[1]
    start = 0 if idx is None else int(idx[0])
    contiguous = idx is None or int(idx[-1]) - start + 1 == count
    coef = _basis_coefficients(grid, group.funcs, idx).astype(dtype, copy=False)
    pvals = (
        np.zeros((count, 0), dtype=dtype)
        if group.pose_values is None
        else group.pose_values.astype(dtype)
    )
    direct = contiguous and dtype == flat.dtype
    scatter = buf.work[-1]
    for a in range(0, count, block):
        m = min(count, a + block) - a
        cb = coef[a : a + m]
        if basis is not None:
            lhs = np.ascontiguousarray(cb.transpose(1, 0, 2)).reshape(n_rows * m, -1)
            slabs = _combine_basis(lhs, basis, buf.slabs[: n_rows * m], buf.term[: n_rows * m])
            slabs = slabs.reshape(n_rows, m, n_pts)
        else:
            assert grid.pose_basis is not None
            sel = slice(a, a + m) if idx is None else idx[a : a + m]
            pose_basis = grid.pose_basis[sel].astype(dtype)
            slabs = fo_matmul(cb, pose_basis).astype(dtype, copy=False).transpose(1, 0, 2)
        work = [buf.work[i, :m] for i in range(group.n_work)]
        rows = slice(start + a, start + a + m) if contiguous else idx[a : a + m]  # type: ignore[index]
        if direct:
            group.combine(slabs, work, flat[rows], pvals[a : a + m])
        else:
            target = scatter[:m]
            group.combine(slabs, work, target, pvals[a : a + m])
            flat[rows] = target


def _combine_basis(
    lhs: NDArray[Any], basis: NDArray[Any], out: NDArray[Any], term: NDArray[Any]
) -> NDArray[Any]:
    """``lhs @ basis`` (``(R, 4) @ (4, N)``) into ``out``, summed in a fixed order.

    Not ``np.matmul``: its BLAS picks a kernel for the CPU (with fused
    multiply-adds or without), and a point exactly on a body's boundary, a
    tie of ``lo <= hi``, then falls on one side on one machine and on the
    other elsewhere. Multiplying and adding column by column gives the same
    bits everywhere.
    """
    out[...] = lhs[:, :1]  # the first basis function is 1
    for k in range(1, basis.shape[0]):
        np.multiply(lhs[:, k : k + 1], basis[k : k + 1], out=term)
        np.add(out, term, out=out)
    return out


def finish_interval(
    lo: NDArray[Any], hi: NDArray[Any], scratch: NDArray[Any], out: NDArray[Any]
) -> None:
    """Write ``lo`` where ``lo <= hi`` and ``+inf`` elsewhere, without a mask.

    ``(lo - hi) * inf`` is ``-inf`` where the interval is non-empty, ``+inf``
    where it is empty and NaN on the boundary (kept as a hit by ``fmax``).
    ``lo`` must not be NaN (turn a NaN into ``+inf`` first). ``scratch`` may
    alias ``hi``.
    """
    np.subtract(lo, hi, out=scratch)
    np.multiply(scratch, np.inf, out=scratch)
    np.fmax(lo, scratch, out=out)
