"""Experiment ``fig9-readings``: which reading of paper 000's Associatron gives Fig. 9?

Paper 000 leaves open several choices that decide whether the Hebbian
Associatron (Eq. 11-13) works on the five shapes. Each combination below is
run on the same traces as ``fig9`` (the five specimens stored from their
reference traces, then traced again and recalled from the growing trace),
always with the paper's one-step recall ``Z = Phi(Phi(M) y)`` (Eq. 12) and
``c`` of Eq. 14 computed on the recalled ``Z`` against each stored ``x``:

``frequency``
    ``"relative"``: ``f(i)`` is the fraction of the moves so far (taxelkit's
    default); ``"count"``: the raw number of moves in sector ``i`` against
    absolute thresholds (then a partial trace's code fills in as the trace
    proceeds, without any 0 = unknown element).
``thresholds``
    ``"rounding"``: ``d_j = (j - 1/2) / m`` (for counts: times the mean number
    of moves of the stored traces); ``"orthogonal"``: the ``l`` thresholds from
    a grid that make the five stored codes as orthogonal as possible (least
    sum of squared off-diagonal overlaps, the paper's "stored vectors should
    perpendicularly intersect each other").
``phases``
    1 (the paper's binning) or 2 (two-phase sector binning, as the improved rule).
``diagonal``
    The diagonal of ``M`` kept (Eq. 11 as printed) or zeroed.
``phi_m_threshold``
    ``epsilon`` of the Phi applied to ``M`` in Eq. 12 (the paper leaves it open).

Fig. 9's shape is scored by four criteria, each measured on the curves:
``rising`` (mean correlation between ``s`` and the true shape's ``c`` >=
:data:`RISING_MIN`), ``triangle`` (the triangle alone top-ranked from an ``s``
in :data:`TRIANGLE_FROM_S`, paper 0.61), ``star`` (the star alone top-ranked
from an ``s`` in :data:`STAR_FROM_S`, paper 0.66, and close to the circle
before: mean ``|c_star - c_circle|`` below :data:`STAR_CIRCLE_GAP` for
``s < 0.66``) and ``full`` (all five recognised from the full trace). The
readings are ranked by criteria met, then by ``|s_triangle - 0.61| +
|s_star - 0.66|``.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.experiments.fig9 import PAPER_RECOGNISED_FROM_S
from taxelkit.experiments.paper000_common import reference_traces, trace_shape
from taxelkit.memory.chain_code import DEFAULT_CHAIN_CODE, rounding_thresholds
from taxelkit.memory.contour_recall import DEFAULT_S_GRID, moves_turned
from taxelkit.memory.direction_histogram import histogram_from_moves
from taxelkit.memory.recall import RecallResult, recall_with_operator
from taxelkit.memory.recall_rules import LinearRecall, hebbian_matrix
from taxelkit.neuron.quantisers import ternary
from taxelkit.world.relief import SHAPE_NAMES

__all__ = ["Fig9Reading", "Fig9ReadingsResult", "run_fig9_readings"]

#: Least mean correlation between s and the true shape's c for "c rises with s".
RISING_MIN = 0.5
#: Window of s from which the triangle must be top-ranked (paper: 0.61).
TRIANGLE_FROM_S = (0.5, 0.75)
#: Window of s from which the star must be top-ranked (paper: 0.66).
STAR_FROM_S = (0.55, 0.8)
#: Largest mean |c_star - c_circle| before s = 0.66 for "star and circle close".
STAR_CIRCLE_GAP = 0.1
#: Candidate thresholds of the "orthogonal" search: fractions, and move counts.
ORTHOGONAL_GRID_RELATIVE = tuple(round(0.01 * k, 2) for k in range(1, 50))
ORTHOGONAL_GRID_COUNT = tuple(float(k) for k in range(1, 41))
#: Thresholds of Phi(M) tried (M's entries are odd integers for K = 5 patterns).
PHI_M_EPSILONS = (0.0, 1.0, 3.0)


@dataclass(frozen=True)
class Fig9Reading:
    """One reading of the paper's code and rule (see the module docs)."""

    frequency: str
    thresholds: str
    phases: int
    diagonal: bool
    phi_m_threshold: float

    @property
    def label(self) -> str:
        """Short name."""
        diag = "diag kept" if self.diagonal else "diag zeroed"
        return (
            f"{self.frequency}, {self.thresholds} d_j, {self.phases} phase(s), {diag}, "
            f"Phi(M) eps {self.phi_m_threshold:g}"
        )


@dataclass(frozen=True, eq=False)
class Fig9ReadingsResult:
    """Scores and curves of every reading.

    Attributes
    ----------
    readings : tuple of Fig9Reading
    thresholds : tuple of tuple of float
        The ``d_j`` used by each reading (fractions or move counts).
    s : (S,) float
    results : tuple of tuple of RecallResult
        Per reading, per traced shape, the recall at every ``s``.
    """

    readings: tuple[Fig9Reading, ...]
    thresholds: tuple[tuple[float, ...], ...]
    s: NDArray[np.float64]
    results: tuple[tuple[RecallResult, ...], ...]

    def score(self, index: int) -> dict[str, Any]:
        """Criteria of Fig. 9's shape for reading ``index``."""
        res = self.results[index]
        s = self.s
        from_s = {n: _from_s(res[k], k, s) for k, n in enumerate(SHAPE_NAMES)}
        rising = float(np.mean([_rise(s, r.correlations[:, k]) for k, r in enumerate(res)]))
        star = res[SHAPE_NAMES.index("star")]
        early = s < PAPER_RECOGNISED_FROM_S["star"]
        ks, kc = SHAPE_NAMES.index("star"), SHAPE_NAMES.index("circle")
        gap = float(np.mean(np.abs(star.correlations[early, ks] - star.correlations[early, kc])))
        full = int(sum(r.recognised_index[-1] == k for k, r in enumerate(res)))
        tri, st = from_s["triangle"], from_s["star"]
        criteria = {
            "rising": rising >= RISING_MIN,
            "triangle": tri is not None and TRIANGLE_FROM_S[0] <= tri <= TRIANGLE_FROM_S[1],
            "star": st is not None and STAR_FROM_S[0] <= st <= STAR_FROM_S[1]
            and gap < STAR_CIRCLE_GAP,
            "full": full == len(SHAPE_NAMES),
        }  # fmt: skip
        distance = sum(
            1.0 if v is None else abs(v - PAPER_RECOGNISED_FROM_S[n])
            for n, v in (("triangle", tri), ("star", st))
        )
        return {
            "criteria_met": int(sum(criteria.values())),
            "criteria": criteria,
            "recognised_from_s": from_s,
            "rising": round(rising, 4),
            "star_circle_gap_before_0.66": round(gap, 4),
            "recognised_at_full_contour": full,
            "distance_to_paper": round(distance, 4),
        }

    def ranking(self) -> list[int]:
        """Reading indices, best first (criteria met, then distance to the paper's s)."""
        scores = [self.score(i) for i in range(len(self.readings))]
        return sorted(
            range(len(scores)),
            key=lambda i: (-scores[i]["criteria_met"], scores[i]["distance_to_paper"], i),
        )

    def to_json(self) -> dict[str, Any]:
        """Every reading's parameters, scores and curves; the best one named."""
        order = self.ranking()
        rows = []
        for i in order:
            reading = self.readings[i]
            rows.append(
                {
                    "label": reading.label,
                    "frequency": reading.frequency,
                    "thresholds": reading.thresholds,
                    "d_j": [round(v, 4) for v in self.thresholds[i]],
                    "phases": reading.phases,
                    "diagonal_kept": reading.diagonal,
                    "phi_m_threshold": reading.phi_m_threshold,
                    **self.score(i),
                    "curves": {
                        n: {
                            stored: [round(float(v), 4) for v in r.correlations[:, k]]
                            for k, stored in enumerate(SHAPE_NAMES)
                        }
                        for n, r in zip(SHAPE_NAMES, self.results[i], strict=True)
                    },
                }
            )
        best = rows[0]
        return {
            "experiment": "fig9-readings",
            "s": [float(v) for v in self.s],
            "paper_recognised_from_s": PAPER_RECOGNISED_FROM_S,
            "criteria": {
                "rising_min": RISING_MIN,
                "triangle_from_s": list(TRIANGLE_FROM_S),
                "star_from_s": list(STAR_FROM_S),
                "star_circle_gap": STAR_CIRCLE_GAP,
            },
            "best": best["label"],
            "reproduced": best["criteria_met"] == 4,
            "readings": rows,
        }


def _rise(s: NDArray[np.float64], c: NDArray[np.float64]) -> float:
    return 0.0 if np.std(c) == 0 else float(np.corrcoef(s, c)[0, 1])


def _from_s(result: RecallResult, k: int, s: NDArray[np.float64]) -> float | None:
    ok = result.recognised_index == k
    if not ok[-1]:
        return None
    bad = np.flatnonzero(~ok)
    return float(s[0 if bad.size == 0 else bad[-1] + 1])


def _histogram(moves: NDArray[np.float64], phases: int) -> NDArray[np.float64]:
    """Sector counts ``(m,)`` at the phase that concentrates them most."""
    m = DEFAULT_CHAIN_CODE.m
    best, best_score = np.zeros(m), -1.0
    for k in range(phases):
        h = histogram_from_moves(moves_turned(moves, k * 2 * np.pi / m / phases), m=m)
        score = float(np.sum((h / h.sum()) ** 2))
        if score > best_score + 1e-12:
            best, best_score = h.astype(np.float64), score
    return best


def _code(h: NDArray[np.float64], d: tuple[float, ...], frequency: str) -> NDArray[np.int8]:
    f = h if frequency == "count" else h / h.sum()
    above = f[np.newaxis, :] >= np.asarray(d)[:, np.newaxis]
    out: NDArray[np.int8] = np.where(above, 1, -1).astype(np.int8).reshape(-1)
    return out


def _orthogonal(hists: list[NDArray[np.float64]], frequency: str) -> tuple[float, ...]:
    """The ``l`` grid thresholds with the least squared overlap of the stored codes."""
    grid = ORTHOGONAL_GRID_COUNT if frequency == "count" else ORTHOGONAL_GRID_RELATIVE
    f = np.stack([h if frequency == "count" else h / h.sum() for h in hists])  # (K, m)
    signs = np.where(f[np.newaxis] >= np.asarray(grid)[:, None, None], 1.0, -1.0)  # (G, K, m)
    gram = np.einsum("gkm,gjm->gkj", signs, signs)  # (G, K, K) per level
    combos = np.array(list(itertools.combinations(range(len(grid)), DEFAULT_CHAIN_CODE.l)))
    total = gram[combos].sum(axis=1)  # (C, K, K)
    off = np.triu(np.ones(total.shape[1:], bool), 1)
    cost = (total[:, off] ** 2).sum(axis=1)
    best = combos[int(np.argmin(cost))]
    return tuple(float(grid[i]) for i in best)


def _partial_hists(moves: NDArray[np.float64], phases: int, s: NDArray[np.float64]) -> list[Any]:
    length = np.concatenate([[0.0], np.cumsum(np.hypot(moves[:, 0], moves[:, 1]))])
    out = []
    for frac in s:
        k = max(1, int(np.searchsorted(length, frac * length[-1] - 1e-9, side="left")))
        out.append(_histogram(moves[:k], phases))
    return out


def run_fig9_readings(
    *, seed: int = 0, progress: Callable[[int, int], None] | None = None
) -> Fig9ReadingsResult:
    """Recall the ``fig9`` traces under every reading.

    Parameters
    ----------
    seed : int
        Seed of the query traces (as ``fig9``).
    progress : callable, optional
        ``progress(done, total)`` over readings.
    """
    stored = [t.moves_mm for t in reference_traces()]
    queries = [trace_shape(n, seed=seed * 100 + 50 + k).moves_mm for k, n in enumerate(SHAPE_NAMES)]
    s = np.asarray(DEFAULT_S_GRID, dtype=np.float64)
    mean_moves = float(np.mean([len(m) for m in stored]))
    readings = [
        Fig9Reading(freq, thr, ph, diag, eps)
        for freq, thr, ph, diag, eps in itertools.product(
            ("relative", "count"), ("rounding", "orthogonal"), (1, 2), (True, False), PHI_M_EPSILONS
        )
    ]
    thresholds, results = [], []
    for i, r in enumerate(readings):
        hists = [_histogram(m, r.phases) for m in stored]
        if r.thresholds == "orthogonal":
            d = _orthogonal(hists, r.frequency)
        else:
            scale = mean_moves if r.frequency == "count" else 1.0
            d = tuple(v * scale for v in rounding_thresholds(12, 4))
        x = np.stack([_code(h, d, r.frequency) for h in hists])
        matrix = hebbian_matrix(x).astype(np.float64)
        if not r.diagonal:
            np.fill_diagonal(matrix, 0.0)
        zero = np.zeros(x.shape[1])
        op = LinearRecall(ternary(matrix, r.phi_m_threshold).astype(np.float64), zero, zero, 0.0)
        per_shape = []
        for mv in queries:
            codes = np.stack([_code(h, d, r.frequency) for h in _partial_hists(mv, r.phases, s)])
            per_shape.append(recall_with_operator(op, x, codes, names=SHAPE_NAMES))
        thresholds.append(d)
        results.append(tuple(per_shape))
        if progress is not None:
            progress(i + 1, len(readings))
    return Fig9ReadingsResult(tuple(readings), tuple(thresholds), s, tuple(results))
