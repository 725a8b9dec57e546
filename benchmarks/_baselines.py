"""Baselines the benchmarks share: what a user would write with NumPy or scikit-image.

Both compute Level 1 of paper 001 (area, centroid, orientation, inertia
eigenvalues of all taxels in contact) for a batch of contact images:

* :func:`numpy_moments`: raw moments of every frame at once with ``einsum``
  against coordinate vectors, then the same closed-form finish: the best a
  NumPy user would write;
* :func:`skimage_moments`: scikit-image's ``regionprops_table`` called once
  for the whole batch (frames stacked into one tall image, each frame's
  taxels one label), so that scikit-image does the batch in one call where
  its API allows it.
"""

from __future__ import annotations

from typing import Any

import numpy as np


def numpy_moments(images: np.ndarray) -> dict[str, np.ndarray]:
    """Area (taxels), centroid (row, col), orientation (rad) and inertia eigenvalues per frame."""
    _, rows, cols = images.shape
    f = images.astype(np.float64)
    r = np.arange(rows, dtype=np.float64)
    c = np.arange(cols, dtype=np.float64)
    m00 = f.sum(axis=(1, 2))
    row_sums = f.sum(axis=2)  # (t, rows)
    col_sums = f.sum(axis=1)  # (t, cols)
    n = np.where(m00 > 0, m00, 1.0)
    cr = row_sums @ r / n
    cc = col_sums @ c / n
    mrr = row_sums @ (r * r) / n - cr * cr
    mcc = col_sums @ (c * c) / n - cc * cc
    mrc = np.einsum("tij,i,j->t", f, r, c) / n - cr * cc
    half = np.hypot(0.5 * (mrr - mcc), mrc)
    return {
        "area": m00,
        "centroid": np.stack([cr, cc], axis=1),
        "orientation": 0.5 * np.arctan2(-2.0 * mrc, mcc - mrr),
        "eigvals": np.stack([0.5 * (mrr + mcc) + half, 0.5 * (mrr + mcc) - half], axis=1),
    }


def skimage_moments(images: np.ndarray) -> dict[str, Any]:
    """The same from one ``regionprops_table`` call over the stacked batch."""
    from skimage.measure import regionprops_table

    t, rows, cols = images.shape
    labels = np.where(images, np.arange(1, t + 1)[:, None, None], 0).reshape(t * rows, cols)
    return regionprops_table(
        labels, properties=("label", "area", "centroid", "orientation", "inertia_tensor_eigvals")
    )
