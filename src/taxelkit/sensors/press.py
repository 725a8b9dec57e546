"""Pressing the simulated sensor onto the world: penetration -> skin -> frames.

The pipeline for a batch of ``P`` poses is

1. sample the world on the taxel grid plus the skin's margin, with
   ``oversample x oversample`` points spread over each element's area;
2. geometric penetration ``p = max(0, depth of the body below the skin)``;
3. mean over each element's area;
4. lateral coupling of the skin (:func:`~taxelkit.sensors.skin.displacement_from_penetration`);
5. seeded noise and quantisation (:func:`~taxelkit.sensors.noise.apply_noise`).

Poses are processed in chunks so that memory stays bounded for any batch.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, DTypeLike, NDArray

from taxelkit.errors import InputError, check_finite_array
from taxelkit.sensors.array_geometry import TaxelArray
from taxelkit.sensors.noise import RngLike, apply_noise
from taxelkit.sensors.presets import Sensor
from taxelkit.sensors.skin import (
    coupling_margin_taxels,
    dimple_mm,
    displacement_from_penetration,
)
from taxelkit.world.base import Relief, Solid
from taxelkit.world.pose import check_rotations

__all__ = [
    "DEFAULT_CHUNK_POSES",
    "displacement_from_relief",
    "displacement_from_solid",
    "sample_offsets_mm",
]

#: Poses processed together: bounds the temporaries to about 1 MB each so they
#: stay in cache (1024 measured fastest of 128..2048 on the solids benchmark).
DEFAULT_CHUNK_POSES = 1024


def sample_offsets_mm(
    array: TaxelArray, *, margin: int, oversample: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Sample coordinates covering every element (and the margin) on a regular sub-grid.

    Parameters
    ----------
    array : TaxelArray
    margin : int
        Virtual taxel rings around the array.
    oversample : int
        Samples per element along each axis (>= 1); 1 samples the centres.

    Returns
    -------
    x_mm : ((cols + 2 margin) * oversample,) float, mm
    y_mm : ((rows + 2 margin) * oversample,) float, mm
        Relative to the array centre, grouped element by element.
    """
    if int(oversample) < 1:
        raise InputError(f"oversample must be an integer >= 1, got {oversample!r}")
    n = int(oversample)
    xc, yc = array.centre_offsets_mm(margin=margin)
    sub = ((np.arange(n) + 0.5) / n - 0.5) * array.element_size_mm if n > 1 else np.zeros(1)
    return (xc[:, None] + sub).ravel(), (yc[:, None] + sub).ravel()


def _grid_for(
    sensor: Sensor, oversample: int, active_only: bool
) -> tuple[NDArray[np.float64], NDArray[np.float64], tuple[int, int]]:
    """Sample coordinates for the whole array or its active block, and the output shape."""
    margin = coupling_margin_taxels(sensor.skin, sensor.array.pitch_mm)
    xs, ys = sample_offsets_mm(sensor.array, margin=margin, oversample=oversample)
    if not active_only:
        return xs, ys, sensor.array.shape
    block = sensor.array.active_region
    n = int(oversample)
    xs = xs[block.col0 * n : (block.col0 + block.cols + 2 * margin) * n]
    ys = ys[block.row0 * n : (block.row0 + block.rows + 2 * margin) * n]
    return xs, ys, (block.rows, block.cols)


def _element_mean(p: NDArray[Any], n: int) -> NDArray[Any]:
    if n == 1:
        return p
    k, h, w = p.shape
    mean: NDArray[Any] = p.reshape(k, h // n, n, w // n, n).mean(axis=(2, 4))
    return mean


def _as_per_pose(name: str, value: ArrayLike, n_poses: int) -> NDArray[np.float64]:
    v = np.asarray(value, dtype=np.float64)
    if v.ndim == 0:
        v = np.full(n_poses, float(v))
    if v.shape != (n_poses,):
        raise InputError(f"{name} must be a scalar or have shape ({n_poses},), got {v.shape}")
    check_finite_array(name, v)
    return v


def _check_positions(positions_mm: ArrayLike) -> NDArray[np.float64]:
    pos = np.asarray(positions_mm, dtype=np.float64)
    if pos.shape == (2,):
        pos = pos[None]
    if pos.ndim != 2 or pos.shape[1] != 2:
        raise InputError(f"positions_mm must have shape (P, 2), got {pos.shape}")
    check_finite_array("positions_mm", pos)
    return pos


def _check_dtype(dtype: DTypeLike) -> type[np.floating[Any]]:
    dt = np.dtype(dtype)
    if dt not in (np.dtype(np.float32), np.dtype(np.float64)):
        raise InputError(f"dtype must be float32 or float64, got {dt}")
    return dt.type  # type: ignore[return-value]


def _finish(
    sensor: Sensor,
    penetration: NDArray[Any],
    n: int,
    add_noise: bool,
    rng: RngLike,
    floor: NDArray[Any] | None = None,
) -> NDArray[Any]:
    p = _element_mean(penetration, n)
    u = displacement_from_penetration(p, pitch_mm=sensor.array.pitch_mm, skin=sensor.skin)
    if floor is not None:
        np.maximum(u, floor, out=u)
    if add_noise and not sensor.noise.is_identity:
        u = apply_noise(u, sensor.noise, rng)
    return u


def displacement_from_relief(
    sensor: Sensor,
    relief: Relief,
    positions_mm: ArrayLike,
    *,
    indent_mm: ArrayLike,
    yaw_deg: ArrayLike = 0.0,
    oversample: int = 3,
    add_noise: bool = True,
    rng: RngLike = None,
    chunk_poses: int = DEFAULT_CHUNK_POSES,
    dtype: DTypeLike = np.float32,
    active_only: bool = False,
) -> NDArray[np.floating[Any]]:
    """Displacement frames of the sensor pressed flat onto a relief specimen.

    Parameters
    ----------
    sensor : Sensor
    relief : Relief
        Specimen; its base plane is ``z = 0``.
    positions_mm : (P, 2) or (2,) float, mm
        Position of the array centre over the specimen for each frame.
    indent_mm : float or (P,) float, mm
        How far the skin is pressed below the specimen's base plane (a raised
        relief of height ``h`` penetrates ``indent_mm + h``). Negative values
        lift the sensor off.
    yaw_deg : float or (P,) float, deg
        Rotation of the array about the vertical axis (columns along x at 0).
    oversample : int
        Samples per element along each axis for the area average.
    add_noise : bool
        Apply the sensor's noise model.
    rng : int, Generator or None
        Seed for the noise.
    chunk_poses : int
        Poses per internal chunk.
    dtype : float32 or float64
        Working and output precision. float32 (default) resolves 1e-7 of the
        largest height involved, far below the 1 um read-out resolution.
    active_only : bool
        Simulate only the array's active block (for example the central 6 x 6
        used by paper 000); the output then has the block's shape.

    Returns
    -------
    (P, rows, cols) float, mm
        Taxel displacement, positive into the sensor.
    """
    pos = _check_positions(positions_mm)
    n_poses = pos.shape[0]
    indent = _as_per_pose("indent_mm", indent_mm, n_poses)
    yaw = np.deg2rad(_as_per_pose("yaw_deg", yaw_deg, n_poses))
    xs, ys, shape = _grid_for(sensor, oversample, active_only)
    gen = np.random.default_rng(rng)
    ftype = _check_dtype(dtype)
    out = np.empty((n_poses, *shape), dtype=ftype)
    for a in range(0, n_poses, max(1, int(chunk_poses))):
        b = min(n_poses, a + max(1, int(chunk_poses)))
        c, s = np.cos(yaw[a:b])[:, None, None], np.sin(yaw[a:b])[:, None, None]
        gx, gy = xs[None, None, :], ys[None, :, None]
        wx = pos[a:b, 0, None, None] + c * gx - s * gy
        wy = pos[a:b, 1, None, None] + s * gx + c * gy
        h = np.asarray(relief.height_mm(wx, wy), dtype=np.float64)
        pen = np.maximum(h + indent[a:b, None, None], 0.0).astype(ftype)
        out[a:b] = _finish(sensor, pen, int(oversample), add_noise, gen)
    return out


def displacement_from_solid(
    sensor: Sensor,
    solid: Solid,
    rotations: ArrayLike,
    positions_mm: ArrayLike,
    *,
    indent_mm: ArrayLike,
    oversample: int = 1,
    add_noise: bool = True,
    rng: RngLike = None,
    chunk_poses: int = DEFAULT_CHUNK_POSES,
    dtype: DTypeLike = np.float32,
    active_only: bool = False,
) -> NDArray[np.floating[Any]]:
    """Displacement frames of a solid pressed onto the sensor in given poses.

    Parameters
    ----------
    sensor : Sensor
    solid : Solid
    rotations : (P, 3, 3) or (3, 3) float
        Body orientation for each frame.
    positions_mm : (P, 2) or (2,) float, mm
        Where the body's reference point sits over the array (array centre = 0).
    indent_mm : float or (P,) float, mm
        Depth of the body's lowest point below the skin surface; <= 0 means
        no contact.
    oversample : int
        Samples per element along each axis for the area average.
    add_noise : bool
        Apply the sensor's noise model.
    rng : int, Generator or None
        Seed for the noise.
    chunk_poses : int
        Poses per internal chunk.
    dtype : float32 or float64
        Working and output precision (see :func:`displacement_from_relief`).
    active_only : bool
        Simulate only the array's active block.

    Returns
    -------
    (P, rows, cols) float, mm
    """
    rot, pos = _check_poses(rotations, positions_mm)
    n_poses = pos.shape[0]
    indent = _as_per_pose("indent_mm", indent_mm, n_poses)
    xs64, ys64, shape = _grid_for(sensor, oversample, active_only)
    ftype = _check_dtype(dtype)
    xs, ys = xs64.astype(ftype), ys64.astype(ftype)
    posf = pos.astype(ftype)
    xc, yc = _output_centres_mm(sensor, active_only)  # for the point-contact dimple
    use_dimple = sensor.skin.point_dimple and sensor.skin.spread_mm > 0
    gen = np.random.default_rng(rng)
    out = np.empty((n_poses, *shape), dtype=ftype)
    step = max(1, int(chunk_poses))
    for a in range(0, n_poses, step):
        b = min(n_poses, a + step)
        zb: Any = solid.bottom_mm(
            rot[a:b], xs[None, :] - posf[a:b, 0:1], ys[None, :] - posf[a:b, 1:2]
        )
        floor = None
        if use_dimple:
            ends = solid.lowest_segment_mm(rot[a:b])  # (n, 2, 3), relative to the body
            level64 = indent[a:b] + ends[:, :, 2].min(axis=1)  # the lower end (tied: either)
            ends_xy = ends[:, :, :2] + pos[a:b, None, :]
            floor = dimple_mm(indent[a:b], ends_xy, xc.astype(ftype), yc.astype(ftype), sensor.skin)
        else:
            level64 = indent[a:b] + solid.lowest_z_mm(rot[a:b])
        level = level64.astype(ftype)[:, None, None]
        pen = np.subtract(level, zb, dtype=ftype)
        np.maximum(pen, 0.0, out=pen)
        out[a:b] = _finish(sensor, pen, int(oversample), add_noise, gen, floor)
    return out


def _check_poses(
    rotations: ArrayLike, positions_mm: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Rotations ``(P, 3, 3)`` and positions ``(P, 2)``; a single one is repeated to match."""
    rot = check_rotations(rotations)
    pos = _check_positions(positions_mm)
    if pos.shape[0] == 1 and rot.shape[0] > 1:
        pos = np.repeat(pos, rot.shape[0], axis=0)
    if rot.shape[0] == 1 and pos.shape[0] > 1:
        rot = np.repeat(rot, pos.shape[0], axis=0)
    if rot.shape[0] != pos.shape[0]:
        raise InputError(
            f"rotations ({rot.shape[0]}) and positions_mm ({pos.shape[0]}) "
            "must hold the same number of poses"
        )
    return rot, pos


def _output_centres_mm(
    sensor: Sensor, active_only: bool
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """x ``(W,)`` and y ``(H,)`` of the output taxels' centres, mm (active block only if asked)."""
    xc, yc = sensor.array.centre_offsets_mm()
    block = sensor.array.active_region if active_only else None
    if block is not None:
        xc = xc[block.col0 : block.col0 + block.cols]
        yc = yc[block.row0 : block.row0 + block.rows]
    return xc, yc
