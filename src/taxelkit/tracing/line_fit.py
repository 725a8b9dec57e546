"""Up to two edge lines through crossing points (corners), by exhaustive RANSAC.

Near a corner the array (18 x 18 mm for the central 6 x 6 of paper 000) sees
two edges at once; one straight line through all crossing points would blend
them. :func:`fit_edge_lines` finds the line with the most inliers among the
lines through every pair of points (a few thousand candidates, all scored in
one array operation), refits it by total least squares, removes its inliers
and repeats once. Each line's normal is oriented towards the raised side by
the votes of its inliers: an element that climbed while scanning along +x
says the raised side lies towards +x.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError

__all__ = ["EdgeLine", "fit_edge_lines", "line_intersection", "vote_agreement"]


@dataclass(frozen=True, eq=False)
class EdgeLine:
    """A straight edge seen by the array.

    Attributes
    ----------
    point_mm : (2,) float, mm
        A point on the line (centroid of its inliers).
    normal : (2,) float
        Unit normal towards the raised side.
    tangent : (2,) float
        Unit direction with the raised side on the left.
    inliers : (K,) bool
        Which crossing points support it.
    """

    point_mm: NDArray[np.float64]
    normal: NDArray[np.float64]
    tangent: NDArray[np.float64]
    inliers: NDArray[np.bool_]

    def signed_distance_mm(self, p: NDArray[np.float64]) -> NDArray[np.float64]:
        """Signed distance of points ``(..., 2)`` from the line, positive on the raised side."""
        out: NDArray[np.float64] = (np.asarray(p) - self.point_mm) @ self.normal
        return out


def _tls(points: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Centroid and unit normal of the total-least-squares line."""
    mean = points.mean(axis=0)
    d = points - mean
    _, vecs = np.linalg.eigh(d.T @ d)
    along = vecs[:, 1]
    return mean, np.array([-along[1], along[0]])


def fit_edge_lines(
    points_mm: NDArray[np.float64],
    rising: NDArray[np.bool_],
    scan_axis: NDArray[np.int_],
    *,
    tolerance_mm: float = 0.6,
    min_inliers: int = 4,
    max_lines: int = 2,
) -> tuple[EdgeLine, ...]:
    """Fit up to ``max_lines`` edge lines to crossing points.

    Parameters
    ----------
    points_mm : (K, 2) float, mm
        Crossing points.
    rising : (K,) bool
        True where the element climbed onto the step.
    scan_axis : (K,) int
        Axis (0 = x, 1 = y) of the scan that found each point.
    tolerance_mm : float
        Inlier distance, mm (about the crossing-location scatter of a 1 mm feeler).
    min_inliers : int
        A line needs at least this many points.
    max_lines : int
        1 or 2.

    Returns
    -------
    tuple of EdgeLine
        Strongest first; empty when no line has enough support.
    """
    p = np.asarray(points_mm, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 2:
        raise InputError(f"points_mm must have shape (K, 2), got {p.shape}")
    if max_lines not in (1, 2):
        raise InputError(f"max_lines must be 1 or 2, got {max_lines!r}")
    remaining = np.ones(p.shape[0], bool)
    lines: list[EdgeLine] = []
    for _ in range(max_lines):
        idx = np.flatnonzero(remaining)
        if idx.size < max(2, min_inliers):
            break
        q = p[idx]
        i, j = np.triu_indices(idx.size, k=1)
        d = q[j] - q[i]
        length = np.hypot(d[:, 0], d[:, 1])
        keep = length > 1e-6
        i, j, d, length = i[keep], j[keep], d[keep], length[keep]
        if i.size == 0:
            break
        n = np.stack([-d[:, 1], d[:, 0]], axis=1) / length[:, None]
        dist = np.abs((q[None, :, :] - q[i][:, None, :]) @ n[:, :, None])[..., 0]
        inl = dist <= tolerance_mm
        score = inl.sum(axis=1) - 1e-3 * np.where(inl, dist, 0.0).sum(axis=1)
        best = int(np.argmax(score))
        members = inl[best]
        if members.sum() < min_inliers:
            break
        mean, normal = _tls(q[members])
        # refine the inlier set once with the refitted line
        members = np.abs((q - mean) @ normal) <= tolerance_mm
        if members.sum() < min_inliers:
            break
        mean, normal = _tls(q[members])
        ax = scan_axis[idx][members]
        votes = np.where(rising[idx][members], 1.0, -1.0) * np.sign(normal[ax])
        if votes.sum() < 0:
            normal = -normal
        full = np.zeros(p.shape[0], bool)
        full[idx[members]] = True
        lines.append(EdgeLine(mean, normal, np.array([normal[1], -normal[0]]), full))
        remaining &= ~full
    return tuple(lines)


def line_intersection(a: EdgeLine, b: EdgeLine) -> NDArray[np.float64] | None:
    """Intersection point of two lines, ``None`` if they are nearly parallel (< 10 deg)."""
    cross = a.tangent[0] * b.tangent[1] - a.tangent[1] * b.tangent[0]
    if abs(cross) < np.sin(np.deg2rad(10.0)):
        return None
    # a.point + s * a.tangent lies on b: (a.point + s t_a - b.point) . n_b = 0
    s = float((b.point_mm - a.point_mm) @ b.normal) / float(a.tangent @ b.normal)
    out: NDArray[np.float64] = a.point_mm + s * a.tangent
    return out


def vote_agreement(
    line: EdgeLine,
    points_mm: NDArray[np.float64],
    rising: NDArray[np.bool_],
    scan_axis: NDArray[np.int_],
) -> float:
    """Fraction of a line's crossings that agree with its raised side.

    Parameters
    ----------
    line : EdgeLine
        A line fitted to ``points_mm`` (its ``inliers`` index them).
    points_mm : (K, 2) float, mm
    rising : (K,) bool
        True where the element climbed onto the step.
    scan_axis : (K,) int
        Axis (0 = x, 1 = y) of the scan that found each point.

    Returns
    -------
    float in [0, 1]
        1 for a step climbed only from its low side; about 1/2 for a bump that
        is climbed and left at the same place; 0 for a line without inliers.
    """
    members = np.asarray(line.inliers, dtype=bool)
    if members.shape != (np.asarray(points_mm).shape[0],):
        raise InputError(
            f"line.inliers must index the {np.asarray(points_mm).shape[0]} points, "
            f"got shape {members.shape}"
        )
    if not np.any(members):
        return 0.0
    ax = np.asarray(scan_axis)[members]
    votes = np.where(np.asarray(rising)[members], 1.0, -1.0) * np.sign(line.normal[ax])
    return float(np.mean(votes > 0))
