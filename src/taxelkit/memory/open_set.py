"""Open-set recognition with calibrated probabilities (beyond paper 000).

The recall of :mod:`taxelkit.memory.recall` always names a stored shape. This
module turns its scores into an answer a user can act on:

scores
    ``c_k`` of Eq. 14 against every stored shape ``k`` (best over rotations).
probabilities
    ``p_k = softmax(c_k / T)`` over the stored shapes (temperature scaling,
    Guo et al., ICML 2017). ``T`` (dimensionless, in units of ``c``) is
    fitted by :func:`~taxelkit.memory.calibration.fit_temperature` to the
    negative log-likelihood of held-out traces of the stored shapes (other
    seeds, poses and sizes than any evaluation), at several traced
    fractions, so that a shape given 0.9 is right about 90 % of the time.
unknown
    A completed (closed) trace is "unknown" when its best score is below
    ``min_top_score``, or - when a reference is known - when its compactness
    ``Q = 4 pi A / P^2`` (:func:`compactness_from_points`, from the traced
    points only) differs from the best shape's by more than
    ``compactness_tolerance`` in ``|log(Q / Q_ref)|``. Both limits are learnt
    from held-out in-set traces by :func:`fit_open_set`: the lowest held-out
    best score minus :data:`REJECTION_SLACK`, and the largest held-out
    compactness deviation times :data:`COMPACTNESS_TOLERANCE_FACTOR`. The
    compactness test is what separates the histogram twins of a stored shape
    (a pentagon and the star, an L-shape or a cross and the square), which the
    direction code alone cannot.
decided
    A known trace is decided when its top probability reaches
    ``decide_probability`` (:data:`DECIDE_PROBABILITY`) and no other shape
    ties it; until then it is "undecided". :func:`decided_at_s` reports, after
    the fact, from which traced fraction ``s`` the verdict stayed decided on
    one shape; the codes it sees are those of the part traced so far, never
    the contour's total length.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError
from taxelkit.memory.calibration import fit_temperature, probabilities_from_scores
from taxelkit.memory.recall import RecallResult

__all__ = [
    "COMPACTNESS_TOLERANCE_FACTOR",
    "DECIDE_PROBABILITY",
    "REJECTION_SLACK",
    "OpenSetCalibration",
    "OpenSetResult",
    "compactness_from_points",
    "decided_at_s",
    "fit_open_set",
    "open_set_from_recall",
]

#: Top probability from which a known trace is decided (dimensionless).
DECIDE_PROBABILITY = 0.9
#: Subtracted from the lowest held-out in-set best score to give
#: ``min_top_score`` (units of ``c``; 0.02 is about 4 of the 192 elements of
#: the 24 x 8 code).
REJECTION_SLACK = 0.02
#: The largest held-out compactness deviation ``|log(Q / Q_ref)|`` is widened
#: by this factor to give ``compactness_tolerance`` (dimensionless).
COMPACTNESS_TOLERANCE_FACTOR = 1.5


@dataclass(frozen=True)
class OpenSetCalibration:
    """What :func:`fit_open_set` learns from held-out in-set traces.

    Parameters
    ----------
    temperature : float
        ``T`` of ``softmax(c / T)`` (> 0, units of ``c``).
    min_top_score : float
        Best scores below this are "unknown" (units of ``c``).
    reference_compactness : tuple of (str, float)
        ``(name, Q)`` of each stored shape, ``Q = 4 pi A / P^2``; empty to skip
        the compactness test.
    compactness_tolerance : float
        Largest accepted ``|log(Q / Q_ref)|`` (>= 0).
    decide_probability : float
        Top probability from which a trace is decided, in (0, 1].
    """

    temperature: float
    min_top_score: float
    reference_compactness: tuple[tuple[str, float], ...] = ()
    compactness_tolerance: float = np.inf
    decide_probability: float = DECIDE_PROBABILITY

    def __post_init__(self) -> None:
        if not (np.isfinite(self.temperature) and self.temperature > 0):
            raise InputError(f"temperature must be a finite number > 0, got {self.temperature!r}")
        if not (0 < self.decide_probability <= 1):
            raise InputError(
                f"decide_probability must be in (0, 1], got {self.decide_probability!r}"
            )
        if not self.compactness_tolerance >= 0:
            raise InputError(
                f"compactness_tolerance must be >= 0, got {self.compactness_tolerance!r}"
            )


@dataclass(frozen=True, eq=False)
class OpenSetResult:
    """Open-set verdicts of ``Q`` queries against ``K`` stored shapes.

    Attributes
    ----------
    names : tuple of str
        The ``K`` stored names.
    scores : (Q, K) float64
        ``c_k`` of Eq. 14.
    probabilities : (Q, K) float64
        Calibrated ``p_k`` (rows sum to 1).
    unknown : (Q,) bool
        The trace matches no stored shape.
    decided : (Q,) bool
        Known, not tied and top probability >= ``decide_probability``.
    margin : (Q,) float64
        Best score minus the second best.
    recognised : tuple of (str or None)
        The decided name, else None.
    verdicts : tuple of str
        ``name``, ``"unknown"`` or ``"undecided"``.
    unknown_reasons : tuple of str
        Why each unknown query was rejected: ``"score"`` (best score below
        ``min_top_score``) or ``"compactness"``; ``""`` if not unknown.
    """

    names: tuple[str, ...]
    scores: NDArray[np.float64]
    probabilities: NDArray[np.float64]
    unknown: NDArray[np.bool_]
    decided: NDArray[np.bool_]
    margin: NDArray[np.float64]
    recognised: tuple[str | None, ...]
    verdicts: tuple[str, ...]
    unknown_reasons: tuple[str, ...]


def compactness_from_points(points_mm: ArrayLike) -> float:
    """Isoperimetric quotient ``Q = 4 pi A / P^2`` of a closed traced path.

    Parameters
    ----------
    points_mm : (n, 2) float, mm
        Traced points; the path is closed from the last point to the first.

    Returns
    -------
    float
        In (0, 1]: 1 for a circle, pi/4 for a square; scale and rotation
        invariant. 0 for fewer than 3 points.

    Examples
    --------
    >>> round(compactness_from_points([(0, 0), (1, 0), (1, 1), (0, 1)]), 4)
    0.7854
    """
    p = np.asarray(points_mm, dtype=np.float64)
    if p.ndim != 2 or p.shape[1] != 2:
        raise InputError(f"points_mm must have shape (n, 2), got {p.shape}")
    if p.shape[0] < 3:
        return 0.0
    x, y = p[:, 0], p[:, 1]
    area = 0.5 * abs(float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)))
    d = np.diff(np.vstack([p, p[:1]]), axis=0)
    perimeter = float(np.sum(np.hypot(d[:, 0], d[:, 1])))
    return 0.0 if perimeter == 0 else 4 * np.pi * area / perimeter**2


def open_set_from_recall(
    recall: RecallResult,
    calibration: OpenSetCalibration,
    *,
    compactness: ArrayLike | None = None,
    closed: ArrayLike | None = None,
) -> OpenSetResult:
    """Calibrated probabilities, "unknown" and "undecided" from a recall.

    Parameters
    ----------
    recall : RecallResult
        ``Q`` queries against ``K`` stored shapes.
    calibration : OpenSetCalibration
    compactness : (Q,) float, optional
        ``Q = 4 pi A / P^2`` of each query's closed trace; NaN (or None for
        all) where the trace is partial or open: then only the score test
        applies.
    closed : (Q,) bool, optional
        Whether each query is a completed (closed) trace; the rejection
        tests apply only to those - a trace still running with little
        evidence is "undecided", not "unknown". Default: all closed.

    Returns
    -------
    OpenSetResult
    """
    scores = recall.correlations
    q = scores.shape[0]
    probs = probabilities_from_scores(scores, calibration.temperature)
    top = scores.max(axis=1, initial=-np.inf)
    done = np.ones(q, bool) if closed is None else np.asarray(closed, dtype=bool).reshape(q)
    unknown = done & (top < calibration.min_top_score)
    reasons = ["score" if u else "" for u in unknown]
    ref = dict(calibration.reference_compactness)
    if compactness is not None and ref:
        qc = np.asarray(compactness, dtype=np.float64).reshape(q)
        for i in range(q):  # one look-up per query; Q is small (a trace's s grid)
            best = recall.names[int(np.argmax(scores[i]))]
            known_q = done[i] and np.isfinite(qc[i]) and best in ref and qc[i] > 0
            off = known_q and abs(np.log(qc[i] / ref[best])) > calibration.compactness_tolerance
            if off and not unknown[i]:
                unknown[i] = True
                reasons[i] = "compactness"
    top_p = probs.max(axis=1, initial=0.0)
    decided = ~unknown & recall.decided & (top_p >= calibration.decide_probability)
    recognised = tuple(recall.recognised[i] if decided[i] else None for i in range(q))
    verdicts = tuple(
        "unknown" if unknown[i] else (r if r is not None else "undecided")
        for i, r in enumerate(recognised)
    )
    return OpenSetResult(
        names=recall.names,
        scores=scores,
        probabilities=probs,
        unknown=unknown,
        decided=decided,
        margin=recall.margin,
        recognised=recognised,
        verdicts=verdicts,
        unknown_reasons=tuple(reasons),
    )


def decided_at_s(s: ArrayLike, verdicts: Sequence[str]) -> float | None:
    """The smallest ``s`` from which the verdict stays one named shape to the end.

    Parameters
    ----------
    s : (S,) float
        Traced fractions, increasing (known only after the fact).
    verdicts : sequence of S str
        Verdicts at each ``s`` (``"unknown"`` and ``"undecided"`` are not names).

    Returns
    -------
    float or None
        None if the last verdict is not a name.

    Examples
    --------
    >>> decided_at_s([0.2, 0.4, 0.6, 0.8], ["undecided", "star", "undecided", "star"])
    0.8
    """
    grid = np.asarray(s, dtype=np.float64)
    v = list(verdicts)
    if len(v) != grid.size or not v or v[-1] in ("unknown", "undecided"):
        return None
    k = len(v) - 1
    while k > 0 and v[k - 1] == v[-1]:
        k -= 1
    return float(grid[k])


def fit_open_set(
    names: Sequence[str],
    scores: ArrayLike,
    labels: ArrayLike,
    *,
    full_top_scores: ArrayLike,
    reference_compactness: Mapping[str, float] | None = None,
    held_out_compactness: ArrayLike | None = None,
    held_out_labels: ArrayLike | None = None,
) -> OpenSetCalibration:
    """Learn the temperature and the rejection limits from held-out in-set traces.

    Parameters
    ----------
    names : sequence of K str
        Stored names (memory order of ``scores``' columns).
    scores : (Q, K) float
        Held-out scores at several traced fractions.
    labels : (Q,) int
        True shape index of each row.
    full_top_scores : (F,) float
        Best score of each held-out *full* trace (the rejection threshold).
    reference_compactness : mapping name -> float, optional
        ``Q`` of each stored shape's stored trace.
    held_out_compactness, held_out_labels : (F,) float and (F,) int, optional
        ``Q`` and true shape index of each held-out closed trace.

    Returns
    -------
    OpenSetCalibration
    """
    temperature = fit_temperature(scores, labels)
    top = np.asarray(full_top_scores, dtype=np.float64)
    if top.ndim != 1 or top.size == 0:
        raise InputError(f"full_top_scores must be a non-empty (F,) array, got {top.shape}")
    ref: tuple[tuple[str, float], ...] = ()
    tolerance = np.inf
    if reference_compactness is not None and held_out_compactness is not None:
        ref = tuple((n, float(reference_compactness[n])) for n in names)
        qc = np.asarray(held_out_compactness, dtype=np.float64)
        lab = np.asarray(held_out_labels, dtype=np.int64)
        refs = np.array([reference_compactness[names[k]] for k in lab])
        tolerance = COMPACTNESS_TOLERANCE_FACTOR * float(np.max(np.abs(np.log(qc / refs))))
    return OpenSetCalibration(
        temperature=temperature,
        min_top_score=float(top.min()) - REJECTION_SLACK,
        reference_compactness=ref,
        compactness_tolerance=tolerance,
    )
