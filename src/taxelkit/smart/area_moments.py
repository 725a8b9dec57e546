"""Moments of area ``m_pq`` and central moments ``mu_pq`` of binary contact images, any order.

Paper 001, Section 3, Level 1, Eq. 1-3, with the conventions of
:mod:`taxelkit.smart.moments` (taxels are ``pitch x pitch`` cells, coordinates
in mm from the array centre). Level 1 itself needs only orders up to 2, which
:func:`~taxelkit.smart.moments.image_stats` computes faster; these general
forms serve checks and users who want higher moments.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.smart.index_sums import CHUNK_FRAMES, centred_index, index_sums
from taxelkit.smart.moments import check_images

__all__ = ["moments_central", "moments_of_area"]


def _cell_power_means(
    n: int, order: int, origin: NDArray[np.float64] | None = None
) -> NDArray[np.float64]:
    """Mean of ``(u - origin)^p`` over each unit cell ``[c - 1/2, c + 1/2]``, pitch units.

    Returns ``(order + 1, n)`` without ``origin``, else ``(T, order + 1, n)``
    for the ``(T,)`` origins.
    """
    c = centred_index(n)
    if origin is not None:
        c = c[None, None, :] - origin[:, None, None]
    p = np.arange(order + 1, dtype=np.float64)[:, None]
    hi, lo = c + 0.5, c - 0.5
    return np.asarray((hi ** (p + 1) - lo ** (p + 1)) / (p + 1))


def moments_of_area(
    frames: ArrayLike,
    *,
    pitch_mm: float,
    order: int = 2,
    threshold: float | None = None,
) -> NDArray[np.float64]:
    """Moments of area ``m_pq`` of binary contact images, in physical units.

    ``m[t, p, q] = integral of x^p y^q dx dy`` over the union of the
    ``pitch x pitch`` cells of the taxels in contact in frame ``t``, with
    ``x, y`` relative to the array centre (see the module notes).

    Parameters
    ----------
    frames : (T, rows, cols) bool or float
        Contact images, or displacements to be thresholded.
    pitch_mm : float
        Taxel pitch, mm.
    order : int, optional
        Highest power of each coordinate (>= 0).
    threshold : float, optional
        Contact threshold for numeric frames (see :func:`binary_images`).

    Returns
    -------
    (T, order + 1, order + 1) float, mm^(2 + p + q)
        ``m[t, p, q]``; ``m[:, 0, 0]`` is the area in mm^2.

    Raises
    ------
    InputError
        On a bad shape, dtype, pitch, order or threshold.

    References
    ----------
    Paper 001, Section 3, Level 1 (general moment of area ``m_pq``).

    Examples
    --------
    >>> img = np.zeros((1, 4, 4), bool)
    >>> img[0, 1, 1:4] = True
    >>> m = moments_of_area(img, pitch_mm=2.0, order=1)[0].tolist()
    >>> m[0][0], m[1][0] / m[0][0], m[0][1] / m[0][0]  # area, centre x, centre y
    (12.0, 1.0, -1.0)
    """
    pitch = check_positive("pitch_mm", pitch_mm)
    if not isinstance(order, int | np.integer) or order < 0:
        raise InputError(f"order must be an integer >= 0, got {order!r}")
    images = check_images(frames, threshold)
    n_t, rows, cols = images.shape
    xp = _cell_power_means(cols, int(order))  # (P, cols), pitch units
    yq = _cell_power_means(rows, int(order))  # (Q, rows)
    out = np.empty((n_t, order + 1, order + 1), dtype=np.float64)
    for a in range(0, n_t, CHUNK_FRAMES):
        f = images[a : a + CHUNK_FRAMES].astype(np.float64)
        # sum over columns first: (T, rows, P), then over rows: (T, P, Q)
        out[a : a + CHUNK_FRAMES] = np.einsum("trp,qr->tpq", f @ xp.T, yq, optimize=True)
    powers = np.arange(order + 1, dtype=np.float64)
    scale = pitch ** (2.0 + powers[:, None] + powers[None, :])
    result: NDArray[np.float64] = out * scale
    return result


def moments_central(
    frames: ArrayLike,
    *,
    pitch_mm: float,
    order: int = 2,
    threshold: float | None = None,
) -> NDArray[np.float64]:
    """Central moments of area ``mu_pq`` about each frame's centre of area.

    ``mu[t, p, q] = integral of (x - x_c)^p (y - y_c)^q dx dy`` over the
    contact region of frame ``t`` (cells of ``pitch x pitch``, see the module
    notes). Empty frames give 0 for every moment (their centre is undefined
    but the region is empty).

    Parameters
    ----------
    frames : (T, rows, cols) bool or float
    pitch_mm : float
        Taxel pitch, mm.
    order : int, optional
        Highest power of each coordinate (>= 0).
    threshold : float, optional
        Contact threshold for numeric frames.

    Returns
    -------
    (T, order + 1, order + 1) float, mm^(2 + p + q)
        ``mu[:, 0, 0]`` is the area, ``mu[:, 1, 0] = mu[:, 0, 1] = 0``.

    Raises
    ------
    InputError
        On a bad shape, dtype, pitch, order or threshold.

    Notes
    -----
    Computed directly about the centre (not from the raw moments through the
    binomial expansion, which cancels badly far from the array centre): one
    contraction of the images with the per-frame cell means of
    ``(x - x_c)^p`` and ``(y - y_c)^q``.
    """
    pitch = check_positive("pitch_mm", pitch_mm)
    if not isinstance(order, int | np.integer) or order < 0:
        raise InputError(f"order must be an integer >= 0, got {order!r}")
    images = check_images(frames, threshold)
    n_t, rows, cols = images.shape
    sums = index_sums(images)
    n = sums[0]
    nn = np.where(n > 0, n, 1.0)
    uc, vc = sums[1] / nn, sums[2] / nn  # centre, pitch units (0 when empty)
    out = np.empty((n_t, order + 1, order + 1), dtype=np.float64)
    for a in range(0, n_t, CHUNK_FRAMES):
        b = min(n_t, a + CHUNK_FRAMES)
        xp = _cell_power_means(cols, int(order), uc[a:b])  # (T, P, cols)
        yq = _cell_power_means(rows, int(order), vc[a:b])  # (T, Q, rows)
        f = images[a:b].astype(np.float64)
        out[a:b] = np.einsum("trc,tpc,tqr->tpq", f, xp, yq, optimize=True)
    powers = np.arange(order + 1, dtype=np.float64)
    scale = pitch ** (2.0 + powers[:, None] + powers[None, :])
    mu: NDArray[np.float64] = out * scale
    return mu
