"""Elastic skin: from geometric penetration to taxel displacement.

Model (documented choice, not taken from either paper)
------------------------------------------------------
A rigid body pressed into the sensor's skin pushes each point of the skin
surface down by the geometric penetration ``p(x, y) >= 0`` (the depth of the
body below the undeformed skin surface), as in a Winkler foundation. A real
elastic layer also drags its neighbourhood down: the surface sags around a
contact and a sharp step is rounded. We model that lateral coupling with a
normalised Gaussian kernel ``g`` of standard deviation ``spread_mm`` and take
the envelope

    u = max(p, coupling * (g * p))

where ``*`` is a 2-D convolution over taxels. The envelope keeps three
properties a rigid contact demands: where the body touches, the skin cannot
sit above it (``u >= p``); a uniform press stays uniform (``sum g = 1``, so
``g * p = p``); and far from any feature the response equals the penetration
(a step of height ``h`` still separates the two sides by ``h``). Near edges
the skin sags beyond the contact, with a length scale ``spread_mm`` of the
order of the skin thickness.

This is a phenomenological kernel, cheaper than a Boussinesq half-space
solution (which would need an iterative contact solver per frame) and
sufficient for contact images and for the fine steps of paper 000.

Point-contact dimple
--------------------
A vertex, an apex, a tilted rim or a knife edge touches the skin over an area
far thinner than a taxel, so sampled penetration alone would miss it, while a
real elastic layer pressed by a point or an edge forms a dimple or a groove
about as wide as the layer is thick (paper 001 sees them as "point" and "line"
images). When the body's deepest part is known (a point, or a segment: an edge
or a generator lying flat), the skin is pulled down at least to the Gaussian
profile ``d exp(-r^2 / (2 spread_mm^2))`` around it (``d`` its depth, ``r``
the distance from the point or segment), see :func:`dimple_mm`. Inside a flat
or gently curved contact this stays below the penetration and changes nothing.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import ndimage

from taxelkit.errors import InputError, check_in_range, check_positive

__all__ = [
    "KERNEL_TRUNCATION_SIGMAS",
    "SkinModel",
    "coupling_kernel_1d",
    "coupling_margin_taxels",
    "dimple_mm",
    "displacement_from_penetration",
]

#: Smallest exponent of the dimple's Gaussian: exp(-40) = 4e-18 of the depth is
#: nothing measurable, and stopping there keeps float32 out of denormal numbers.
DIMPLE_MIN_EXPONENT = -40.0
_EXP_FLOOR = DIMPLE_MIN_EXPONENT

#: The Gaussian coupling kernel is truncated at this many standard deviations
#: (weights beyond 3 sigma are below 1.2 % of the peak).
KERNEL_TRUNCATION_SIGMAS = 3.0


@dataclass(frozen=True)
class SkinModel:
    """Lateral coupling of the elastic skin.

    Parameters
    ----------
    spread_mm : float
        Standard deviation of the Gaussian coupling kernel, mm (about the
        skin thickness). 0 disables coupling: each taxel reports its own
        penetration.
    coupling : float
        Weight of the spread field in the envelope, in [0, 1]. 1 lets a
        uniform press stay uniform; smaller values weaken the sag.
    point_dimple : bool
        Add the dimple around a body's deepest point (see module docs).
    """

    spread_mm: float = 0.0
    coupling: float = 1.0
    point_dimple: bool = True

    def __post_init__(self) -> None:
        check_positive("spread_mm", self.spread_mm, allow_zero=True)
        check_in_range("coupling", self.coupling, 0.0, 1.0)


def coupling_margin_taxels(skin: SkinModel, pitch_mm: float) -> int:
    """Number of virtual taxel rings the coupling kernel reaches beyond the array.

    Parameters
    ----------
    skin : SkinModel
    pitch_mm : float
        Taxel pitch, mm.

    Returns
    -------
    int
        ``ceil(KERNEL_TRUNCATION_SIGMAS * spread_mm / pitch_mm)``; 0 without coupling.
    """
    pitch = check_positive("pitch_mm", pitch_mm)
    if skin.spread_mm == 0.0 or skin.coupling == 0.0:
        return 0
    return math.ceil(KERNEL_TRUNCATION_SIGMAS * skin.spread_mm / pitch - 1e-12)


def coupling_kernel_1d(skin: SkinModel, pitch_mm: float) -> NDArray[np.float64]:
    """Normalised 1-D Gaussian weights at taxel offsets ``-m .. m``.

    Returns
    -------
    (2 m + 1,) float
        Weights summing to 1, ``m = coupling_margin_taxels(skin, pitch_mm)``.
    """
    m = coupling_margin_taxels(skin, pitch_mm)
    if m == 0:
        return np.ones(1)
    k = np.arange(-m, m + 1, dtype=np.float64) * pitch_mm
    w: NDArray[np.float64] = np.exp(-0.5 * (k / skin.spread_mm) ** 2)
    w /= w.sum()
    return w


def displacement_from_penetration(
    penetration_mm: NDArray[Any], *, pitch_mm: float, skin: SkinModel
) -> NDArray[np.floating[Any]]:
    """Taxel displacement from the penetration sampled on the array plus a margin.

    Parameters
    ----------
    penetration_mm : (..., rows + 2 m, cols + 2 m) float, mm
        Geometric penetration (>= 0) at every taxel centre and at ``m =
        coupling_margin_taxels(skin, pitch_mm)`` rings of virtual taxels
        around the array. Leading dimensions (poses, time) are batched.
    pitch_mm : float
        Taxel pitch, mm.
    skin : SkinModel
        Coupling parameters.

    Returns
    -------
    (..., rows, cols) float, mm
        ``max(p, coupling * (g * p))`` on the real taxels (see module docs);
        float32 input stays float32, anything else is computed in float64.

    Raises
    ------
    InputError
        If the array is smaller than the margin requires.

    Examples
    --------
    >>> import numpy as np
    >>> skin = SkinModel(spread_mm=1.0)
    >>> m = coupling_margin_taxels(skin, 1.0)
    >>> u = displacement_from_penetration(np.full((4 + 2 * m, 4 + 2 * m), 0.2),
    ...                                   pitch_mm=1.0, skin=skin)
    >>> bool(np.allclose(u, 0.2))
    True
    """
    p = np.asarray(penetration_mm)
    if p.dtype != np.float32:
        p = p.astype(np.float64)
    m = coupling_margin_taxels(skin, pitch_mm)
    if p.ndim < 2 or p.shape[-1] <= 2 * m or p.shape[-2] <= 2 * m:
        raise InputError(
            f"penetration_mm must have shape (..., rows + {2 * m}, cols + {2 * m}) "
            f"with rows, cols >= 1, got {p.shape}"
        )
    if m == 0:
        return p.copy()
    w = coupling_kernel_1d(skin, pitch_mm)
    rows, cols = p.shape[-2] - 2 * m, p.shape[-1] - 2 * m
    # Separable Gaussian, one pass per axis; the margin holds every tap that a
    # real taxel needs, so the padding mode never reaches the kept values.
    along_x = ndimage.correlate1d(p, w, axis=-1, mode="constant")[..., m : m + cols]
    spread = ndimage.correlate1d(along_x, w, axis=-2, mode="constant")[..., m : m + rows, :]
    centre = p[..., m : m + rows, m : m + cols]
    if skin.coupling != 1.0:  # the default 1 needs no multiplication
        spread = spread * p.dtype.type(skin.coupling)
    out: NDArray[np.floating[Any]] = np.maximum(centre, spread)
    return out


def dimple_mm(
    depth_mm: NDArray[Any],
    ends_mm: NDArray[Any],
    x_mm: NDArray[Any],
    y_mm: NDArray[Any],
    skin: SkinModel,
) -> NDArray[np.floating[Any]]:
    """Dimple (or groove) of the skin around a body's deepest point or edge.

    Parameters
    ----------
    depth_mm : (P,) float, mm
        Depth of the deepest part below the skin surface (<= 0: none).
    ends_mm : (P, 2, 2) float, mm
        ``(x, y)`` of the two ends of the deepest segment (equal for a point),
        in the sensor frame.
    x_mm : (W,) float, mm
        x of the taxel columns.
    y_mm : (H,) float, mm
        y of the taxel rows.
    skin : SkinModel

    Returns
    -------
    (P, H, W) float, mm, in the dtype of ``x_mm``
        ``max(d, 0) exp(-r^2 / (2 spread_mm^2))``, ``r`` the distance to the
        segment; zeros when the skin has no spread or the dimple is off.
        Point-like segments use a separable form (two small exponentials per
        pose); only true segments pay for the full distance computation.
    """
    x = np.asarray(x_mm)
    y = np.asarray(y_mm)
    ftype = x.dtype.type
    ends = np.asarray(ends_mm, dtype=np.float64)
    depth = np.maximum(np.asarray(depth_mm, dtype=np.float64), 0.0)
    n = ends.shape[0]
    if skin.spread_mm == 0.0 or not skin.point_dimple:
        return np.zeros((n, y.size, x.size), dtype=x.dtype)
    scale = -0.5 / skin.spread_mm**2
    a, d = ends[:, 0], ends[:, 1] - ends[:, 0]
    # every pose first as a point at its first end (separable, cheap) ...
    # exponents clamped at DIMPLE_MIN_EXPONENT: far taxels would otherwise underflow
    # through denormal numbers, which are some hundred times slower to compute
    gx = np.exp(
        np.maximum(ftype(scale) * (x[None, :] - a[:, 0:1].astype(x.dtype)) ** 2, _EXP_FLOOR)
    )
    gy = np.exp(
        np.maximum(ftype(scale) * (y[None, :] - a[:, 1:2].astype(x.dtype)) ** 2, _EXP_FLOOR)
    )
    gy *= depth[:, None].astype(x.dtype)
    out: NDArray[np.floating[Any]] = gy[:, :, None] * gx[:, None, :]
    # ... then the true segments (edges, generators) by their distance field
    length2 = np.sum(d * d, axis=1)
    ln = np.flatnonzero(length2 > 1e-12)
    if ln.size:
        rx = x[None, None, :] - a[ln, 0, None, None]  # (L, 1, W)
        ry = y[None, :, None] - a[ln, 1, None, None]  # (L, H, 1)
        dx, dy = d[ln, 0, None, None], d[ln, 1, None, None]
        t = np.clip((rx * dx + ry * dy) / length2[ln, None, None], 0.0, 1.0)
        r2 = (rx - t * dx) ** 2 + (ry - t * dy) ** 2
        out[ln] = (depth[ln, None, None] * np.exp(np.maximum(scale * r2, _EXP_FLOOR))).astype(
            x.dtype
        )
    return out
