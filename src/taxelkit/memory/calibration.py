"""Temperature-scaled probabilities and their calibration (beyond paper 000).

:mod:`taxelkit.memory.open_set` turns recall scores into probabilities with
:func:`probabilities_from_scores` at a temperature :func:`fit_temperature`
learns from held-out traces; :func:`expected_calibration_error` measures how
well the probabilities match the hit rate (the reliability diagram).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError

__all__ = [
    "TEMPERATURE_GRID",
    "expected_calibration_error",
    "fit_temperature",
    "probabilities_from_scores",
]

#: Temperatures searched by :func:`fit_temperature` (log-spaced, units of ``c``).
TEMPERATURE_GRID = np.geomspace(1e-3, 1.0, 301)


def probabilities_from_scores(scores: ArrayLike, temperature: float) -> NDArray[np.float64]:
    """Softmax ``exp(c_k / T) / sum_j exp(c_j / T)`` along the last axis.

    Parameters
    ----------
    scores : (..., K) float
        Correlations ``c`` (Eq. 14).
    temperature : float
        ``T`` > 0, units of ``c``.

    Returns
    -------
    (..., K) float64
        Rows sum to 1; equal scores get equal probabilities.

    Examples
    --------
    >>> probabilities_from_scores([1.0, 1.0, 0.0], 1e-3).round(3).tolist()
    [0.5, 0.5, 0.0]
    """
    if not (np.isfinite(temperature) and temperature > 0):
        raise InputError(f"temperature must be a finite number > 0, got {temperature!r}")
    z = np.asarray(scores, dtype=np.float64) / temperature
    z = z - z.max(axis=-1, keepdims=True)
    e = np.exp(z)
    out: NDArray[np.float64] = e / e.sum(axis=-1, keepdims=True)
    return out


def fit_temperature(scores: ArrayLike, labels: ArrayLike) -> float:
    """Temperature with the least negative log-likelihood of the true labels.

    Parameters
    ----------
    scores : (Q, K) float
        Held-out scores of traces of stored shapes.
    labels : (Q,) int
        Index of each trace's true shape.

    Returns
    -------
    float
        The best of :data:`TEMPERATURE_GRID`.
    """
    c = np.asarray(scores, dtype=np.float64)
    y = np.asarray(labels, dtype=np.int64)
    if c.ndim != 2 or y.shape != (c.shape[0],) or c.shape[0] == 0:
        raise InputError(f"scores (Q, K) and labels (Q,) must match, got {c.shape}, {y.shape}")
    nll = [
        -float(np.mean(np.log(probabilities_from_scores(c, t)[np.arange(len(y)), y] + 1e-300)))
        for t in TEMPERATURE_GRID
    ]
    return float(TEMPERATURE_GRID[int(np.argmin(nll))])


def expected_calibration_error(
    confidence: ArrayLike, correct: ArrayLike, *, n_bins: int = 10
) -> tuple[float, NDArray[np.float64], NDArray[np.float64], NDArray[np.int64]]:
    """Expected calibration error and the reliability diagram's bins.

    Parameters
    ----------
    confidence : (Q,) float
        Top probability of each prediction.
    correct : (Q,) bool or float
        Whether the top shape was right (a fraction in [0, 1] when the top
        is shared by tied shapes).
    n_bins : int
        Equal-width bins over [0, 1].

    Returns
    -------
    ece : float
        ``sum_b (n_b / Q) |accuracy_b - confidence_b|``.
    accuracy, mean_confidence : (n_bins,) float64
        Per bin (NaN where empty).
    counts : (n_bins,) int64
    """
    p = np.asarray(confidence, dtype=np.float64)
    ok = np.asarray(correct, dtype=np.float64)
    if p.shape != ok.shape or p.ndim != 1 or p.size == 0:
        raise InputError(f"confidence and correct must be matching (Q,), got {p.shape}, {ok.shape}")
    b = np.minimum((p * n_bins).astype(np.int64), n_bins - 1)
    counts = np.bincount(b, minlength=n_bins)
    with np.errstate(invalid="ignore"):
        acc = np.bincount(b, weights=ok, minlength=n_bins) / counts
        conf = np.bincount(b, weights=p, minlength=n_bins) / counts
    gaps = np.where(counts > 0, np.abs(acc - conf), 0.0)
    ece = float(np.sum(counts * gaps) / p.size)
    return ece, acc, conf, counts.astype(np.int64)
