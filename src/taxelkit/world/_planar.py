"""Private helpers of the relief specimens: boundary checks and planar geometry.

Shared by :mod:`taxelkit.world.contour_relief`, :mod:`taxelkit.world.edge`
and :mod:`taxelkit.world.relief`; not part of the public API.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive

__all__ = [
    "DISTANCE_BLOCK_PAIRS",
    "UM_PER_MM",
    "as_points",
    "broadcast_xy",
    "check_finite",
    "check_transform",
    "check_vertices",
    "check_xy",
    "cos_sin_deg",
    "distance_to_closed_polyline_mm",
    "rotation_2d",
    "signed_area_mm2",
    "transform_points",
]

#: Micrometres per millimetre.
UM_PER_MM = 1000.0

#: Point-segment pairs processed together by the polygon distance query;
#: bounds its temporary arrays to a few tens of MB.
DISTANCE_BLOCK_PAIRS = 1 << 20

#: ``(cos, sin)`` of 0, 90, 180 and 270 deg, exactly.
_QUARTER_TURNS: tuple[tuple[float, float], ...] = ((1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0))


def check_finite(name: str, value: float) -> float:
    """Return ``value`` as a float if it is a finite number, else raise :class:`InputError`."""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"{name} must be finite, got {value!r}")
    return v


def check_xy(name: str, value: ArrayLike) -> tuple[float, float]:
    """Return ``value`` as an ``(x, y)`` tuple of finite floats, mm."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be an (x, y) pair of numbers in mm, got {value!r}") from None
    if arr.shape != (2,):
        raise InputError(f"{name} must be an (x, y) pair in mm, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{name} must be finite, got {value!r}")
    return float(arr[0]), float(arr[1])


def broadcast_xy(
    x_mm: ArrayLike, y_mm: ArrayLike
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Coordinates as float64 arrays broadcast to a common shape ``(...)``."""
    x = np.asarray(x_mm, dtype=np.float64)
    y = np.asarray(y_mm, dtype=np.float64)
    try:
        bx, by = np.broadcast_arrays(x, y)
    except ValueError:
        raise InputError(
            f"x_mm and y_mm must broadcast together, got shapes {x.shape} and {y.shape}"
        ) from None
    return bx, by


def as_points(points_mm: ArrayLike) -> NDArray[np.float64]:
    """Query points as a finite float64 array of shape ``(..., 2)``, mm."""
    try:
        pts = np.asarray(points_mm, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError("points_mm must be a numeric array of shape (N, 2)") from None
    if pts.ndim < 1 or pts.shape[-1] != 2:
        raise InputError(f"points_mm must have shape (N, 2) (or (..., 2)), got {pts.shape}")
    if not np.all(np.isfinite(pts)):
        raise InputError("points_mm must be finite")
    return pts


def cos_sin_deg(angle_deg: float) -> tuple[float, float]:
    """``(cos, sin)`` of an angle in degrees, exact at multiples of 90 deg.

    ``math.cos(math.radians(90))`` is 6e-17, not 0; that would tilt an edge
    along y by a rounding error and misclassify points exactly on it.
    """
    quarter, rest = divmod(angle_deg, 90.0)
    if rest == 0.0:
        return _QUARTER_TURNS[int(quarter) % 4]
    t = math.radians(angle_deg)
    return math.cos(t), math.sin(t)


def rotation_2d(rotation_deg: float) -> NDArray[np.float64]:
    """(2, 2) matrix of a counter-clockwise rotation by ``rotation_deg`` degrees."""
    c, s = cos_sin_deg(rotation_deg)
    return np.array([[c, -s], [s, c]])


def transform_points(
    points_mm: NDArray[np.float64],
    *,
    rotation_deg: float,
    offset_mm: tuple[float, float],
    scale: float,
) -> NDArray[np.float64]:
    """``scale * R(rotation) @ p + offset`` for points ``(..., 2)``."""
    moved: NDArray[np.float64] = scale * (points_mm @ rotation_2d(rotation_deg).T) + np.asarray(
        offset_mm
    )
    return moved


def check_transform(
    rotation_deg: float, offset_mm: ArrayLike, scale: float
) -> tuple[float, tuple[float, float], float]:
    """Validated ``(rotation_deg, offset_mm, scale)`` of a similarity transform."""
    return (
        check_finite("rotation_deg", rotation_deg),
        check_xy("offset_mm", offset_mm),
        check_positive("scale", scale),
    )


def check_vertices(vertices_mm: ArrayLike) -> NDArray[np.float64]:
    """Polygon vertices as a fresh ``(V, 2)`` float64 array, closing copy dropped.

    Checks shape, finiteness, ``V >= 3`` and that no vertex repeats its
    predecessor; simplicity is checked by :class:`~taxelkit.world.contour_relief.PolygonRelief`.
    """
    try:
        verts = np.array(vertices_mm, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError("vertices_mm must be a numeric array of shape (V, 2)") from None
    if verts.ndim != 2 or verts.shape[1] != 2:
        raise InputError(f"vertices_mm must have shape (V, 2), got shape {verts.shape}")
    if not np.all(np.isfinite(verts)):
        raise InputError("vertices_mm must be finite, got NaN or Inf coordinates")
    if verts.shape[0] >= 2 and np.array_equal(verts[0], verts[-1]):
        verts = verts[:-1]  # a closed list repeats the first vertex; drop the copy
    if verts.shape[0] < 3:
        raise InputError(
            f"vertices_mm must hold at least 3 distinct vertices, got {verts.shape[0]}"
        )
    repeats = np.flatnonzero(np.all(verts == np.roll(verts, -1, axis=0), axis=1))
    if repeats.size:
        k = int(repeats[0])
        raise InputError(
            f"vertices_mm must not repeat a vertex consecutively, got vertex {k} "
            f"equal to vertex {(k + 1) % verts.shape[0]}"
        )
    return verts


def signed_area_mm2(verts: NDArray[np.float64]) -> float:
    """Shoelace area of the polygon ``(V, 2)``, mm^2; positive when counter-clockwise."""
    x, y = verts[:, 0], verts[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def distance_to_closed_polyline_mm(
    pts: NDArray[np.float64], verts: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Distance from points ``(N, 2)`` to the closed polyline through ``verts`` ``(V, 2)``.

    Notes
    -----
    ``shapely.distance(shapely.LinearRing(verts), shapely.points(pts))`` gives
    the same distances to about 1e-14 mm, but not bit for bit, and fig8's
    published tracing errors (``docs/results/fig8.json``) are means of these
    distances, so they would change in their last digits. The speed is no
    reason to switch for the specimens (3 to 10 vertices): for 10,000 points
    both take 6 to 21 ms (numpy faster on the triangle, shapely on the star);
    shapely wins only on long contours (720 vertices: 0.23 s against 1.3 s),
    which no specimen has. Containment does use shapely
    (:func:`shapely.intersects_xy`, in :mod:`taxelkit.world.contour_relief`).
    """
    start = verts
    seg = np.roll(verts, -1, axis=0) - verts
    seg_len2 = np.sum(seg * seg, axis=1)  # > 0: consecutive vertices differ
    out = np.empty(pts.shape[0])
    block = max(1, DISTANCE_BLOCK_PAIRS // verts.shape[0])
    for a in range(0, pts.shape[0], block):  # blocks of points, not single points
        rel = pts[a : a + block, None, :] - start[None, :, :]  # (n, V, 2)
        t = np.clip(np.sum(rel * seg, axis=2) / seg_len2, 0.0, 1.0)
        d = rel - t[..., None] * seg
        out[a : a + block] = np.min(np.hypot(d[..., 0], d[..., 1]), axis=1)
    return out
