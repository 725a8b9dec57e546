"""Recall from part of a traced contour: correlation ``c`` against arc length ``s`` (Fig. 9).

The tracer's moves ``dr`` up to a normalised arc length ``s = l / L``
(paper 000, Section VII.3) become a chain code and are recalled against the
memory. With the paper's Hebbian rule the code is Eq. 13 exactly (+-1).
The improved path uses :func:`~taxelkit.memory.partial_code.partial_chain_code_from_moves`:
elements that the rest of the contour could still flip are 0 (unknown), so a
partial trace only asserts what it has seen.

Sector phases (an improvement, ``phases > 1``)
    A straight edge whose direction lies on a sector boundary (every edge of
    the canonical square, triangle and hexagon: multiples of 30 deg) splits its
    moves between two sectors at random, which flattens the histogram. With
    ``phases = P`` the moves are also binned after turning them by
    ``k * 360 / (m P)`` deg, ``k = 0 .. P-1``: stored contours keep the phase
    that concentrates their histogram most (largest sum of squared
    frequencies), and so does each query, at each ``s`` from the part traced
    so far. (Taking the best correlation over all phases instead fails: at
    the wrong phase a polygon's histogram is flat and recalls the circle.)
    With ``P = 2`` some phase puts every edge within a quarter sector of a
    sector's middle. ``phases = 1`` is the paper.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError
from taxelkit.memory.associatron import AssociativeMemory, memorise
from taxelkit.memory.chain_code import DEFAULT_CHAIN_CODE, ChainCodeConfig, chain_code_from_moves
from taxelkit.memory.direction_histogram import histogram_from_moves, relative_frequency
from taxelkit.memory.partial_code import partial_chain_code_from_moves
from taxelkit.memory.recall import verdict_text

__all__ = [
    "DEFAULT_S_GRID",
    "RecallCurve",
    "memorise_contours",
    "moves_turned",
    "prefix_codes",
    "recall_curve",
]

#: Normalised arc lengths at which a recall curve is evaluated by default.
DEFAULT_S_GRID: NDArray[np.float64] = np.round(np.arange(0.05, 1.0001, 0.05), 4)


@dataclass(frozen=True, eq=False)
class RecallCurve:
    """Correlation with every stored contour as the trace grows.

    Attributes
    ----------
    s : (S,) float
        Normalised arc lengths.
    names : tuple of str
        Stored contours, memory order.
    correlations : (S, K) float
        ``c`` of Eq. 14, best over the m rotations, for each stored contour.
    recognised : tuple of (str or None)
        The single top-ranked contour at each ``s``; None where two or more
        are tied (:data:`~taxelkit.memory.recall.TIE_TOLERANCE`).
    margin : (S,) float
        Best ``c`` minus the second best at each ``s`` (0 on a tie).
    tied : tuple of tuple of str
        The names tied at the top at each ``s`` (one name when decided).
    """

    s: NDArray[np.float64]
    names: tuple[str, ...]
    correlations: NDArray[np.float64]
    recognised: tuple[str | None, ...]
    margin: NDArray[np.float64]
    tied: tuple[tuple[str, ...], ...]

    @property
    def verdicts(self) -> tuple[str, ...]:
        """The recognised name or ``"undecided between A and B"`` at each ``s``."""
        return tuple(verdict_text(t) for t in self.tied)

    @property
    def n_ties(self) -> int:
        """Number of ``s`` at which the top is a tie."""
        return sum(r is None for r in self.recognised)

    def recognised_from_s(self, name: str) -> float | None:
        """Smallest ``s`` from which ``name`` stays top-ranked to the end; None if never."""
        ok = np.array([r == name for r in self.recognised])
        if not ok[-1]:
            return None
        bad = np.flatnonzero(~ok)
        first = 0 if bad.size == 0 else int(bad[-1]) + 1
        return float(self.s[first])

    def to_json(self) -> list[dict[str, Any]]:
        """``[{"s", "correlations": {name: c}, "margin", "verdict"}, ...]``."""
        return [
            {
                "s": float(s),
                "correlations": {n: float(c) for n, c in zip(self.names, row, strict=True)},
                "margin": _finite_or_none(round(float(margin), 6)),
                "verdict": verdict,
            }
            for s, row, margin, verdict in zip(
                self.s, self.correlations, self.margin, self.verdicts, strict=True
            )
        ]


def _finite_or_none(value: float) -> float | None:
    """JSON has no infinity: the margin with one stored contour becomes None."""
    return value if np.isfinite(value) else None


def moves_turned(moves_mm: NDArray[np.float64], angle_rad: float) -> NDArray[np.float64]:
    """Moves ``(K, 2)`` turned counter-clockwise by ``angle_rad``."""
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    out: NDArray[np.float64] = moves_mm @ np.array([[c, s], [-s, c]])
    return out


def _phase_angles(config: ChainCodeConfig, phases: int) -> NDArray[np.float64]:
    if int(phases) < 1:
        raise InputError(f"phases must be an integer >= 1, got {phases!r}")
    return np.arange(int(phases)) * (2 * np.pi / config.m) / int(phases)


def memorise_contours(
    names: list[str] | tuple[str, ...],
    moves: list[NDArray[np.float64]],
    *,
    rule: str = "hebbian",
    phases: int = 1,
    config: ChainCodeConfig = DEFAULT_CHAIN_CODE,
) -> AssociativeMemory:
    """Store traced contours, each at its most concentrated sector phase.

    Parameters
    ----------
    names : sequence of str
        One name per contour.
    moves : list of (K_i, 2) float, mm
        Each contour's moves ``dr``.
    rule : str
        Recall rule (:data:`~taxelkit.memory.recall_rules.RECALL_RULES`).
    phases : int
        Sector phases tried (1 = the paper's binning).
    config : ChainCodeConfig

    Returns
    -------
    AssociativeMemory
    """
    if len(names) != len(moves):
        raise InputError(f"names ({len(names)}) and moves ({len(moves)}) must match")
    codes = []
    for mv in moves:
        m = np.asarray(mv, dtype=np.float64)
        scores = [
            float(
                np.sum(
                    relative_frequency(histogram_from_moves(moves_turned(m, a), m=config.m)) ** 2
                )
            )
            for a in _phase_angles(config, phases)
        ]
        angle = float(_phase_angles(config, phases)[int(np.argmax(scores))])
        codes.append(chain_code_from_moves(moves_turned(m, angle), config=config))
    return memorise(list(names), np.stack(codes), config=config, rule=rule)


def prefix_codes(
    moves_mm: ArrayLike,
    memory: AssociativeMemory,
    *,
    s: ArrayLike = DEFAULT_S_GRID,
    unknown_for_partial: bool | None = None,
    phases: int = 1,
) -> NDArray[np.int8]:
    """Chain codes of the growing parts of a trace, one per ``s``.

    The part up to ``s`` is chosen after the fact (``s`` is known only once
    the trace has ended); each code is computed from the moves of that part
    alone, except that ``unknown_for_partial`` uses ``s`` as the coverage of
    the partial code (it then assumes the total length known).

    Parameters
    ----------
    moves_mm, memory, s, unknown_for_partial, phases
        As :func:`recall_curve`.

    Returns
    -------
    (S, N) int8
        Values in {-1, 0, +1}.
    """
    moves = np.asarray(moves_mm, dtype=np.float64)
    if moves.ndim != 2 or moves.shape[1] != 2 or moves.shape[0] == 0:
        raise InputError(f"moves_mm must have shape (K, 2) with K >= 1, got {moves.shape}")
    grid = np.asarray(s, dtype=np.float64).ravel()
    if grid.size == 0 or np.any(grid <= 0) or np.any(grid > 1):
        raise InputError("s must hold values in (0, 1]")
    unknown = memory.rule != "hebbian" if unknown_for_partial is None else unknown_for_partial
    length = np.concatenate([[0.0], np.cumsum(np.hypot(moves[:, 0], moves[:, 1]))])
    total = length[-1]
    angles = _phase_angles(memory.config, phases)
    codes = []
    for frac in grid:  # one code per s; recall is batched over all of them
        k = max(1, int(np.searchsorted(length, frac * total - 1e-9, side="left")))
        best, best_score = 0.0, -1.0
        for angle in angles:  # the most concentrated phase of the part traced so far
            f = relative_frequency(
                histogram_from_moves(moves_turned(moves[:k], float(angle)), m=memory.config.m)
            )
            score = float(np.sum(f**2))
            if score > best_score + 1e-12:
                best, best_score = float(angle), score
        part = moves_turned(moves[:k], best)
        if unknown and frac < 1.0:
            codes.append(partial_chain_code_from_moves(part, coverage=frac, config=memory.config))
        else:
            codes.append(chain_code_from_moves(part, config=memory.config))
    return np.stack(codes)


def recall_curve(
    moves_mm: ArrayLike,
    memory: AssociativeMemory,
    *,
    s: ArrayLike = DEFAULT_S_GRID,
    unknown_for_partial: bool | None = None,
    phases: int = 1,
) -> RecallCurve:
    """Recall a contour from growing parts of its trace.

    Parameters
    ----------
    moves_mm : (K, 2) float, mm
        The tracer's moves ``dr`` in order.
    memory : AssociativeMemory
    s : (S,) float in (0, 1]
        Normalised arc lengths to evaluate.
    unknown_for_partial : bool, optional
        Code partial traces with 0 = unknown. Default: False for the paper's
        ``"hebbian"`` rule (Eq. 13 exactly), True for the other rules.
    phases : int
        Sector phases tried for the query (see module docs); 1 = the paper.

    Returns
    -------
    RecallCurve
    """
    grid = np.asarray(s, dtype=np.float64).ravel()
    codes = prefix_codes(
        moves_mm, memory, s=grid, unknown_for_partial=unknown_for_partial, phases=phases
    )
    result = memory.recall(codes)
    return RecallCurve(
        grid, memory.names, result.correlations, result.recognised, result.margin, result.tied
    )
