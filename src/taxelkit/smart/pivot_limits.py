"""The limits Level 3's pivot verdicts read a turning line's pivot ratio against.

"About one end" keeps the ratio plus an allowance for its uncertainty below a
limit (:func:`pivot_upper`); "in an arc" needs a ratio above a limit that
widens as the turn shrinks (:func:`arc_ratio_limit`), read at the turn of
:func:`arc_limit_turn_deg`; both know how far the grid alone tilts a line
(:func:`grid_tilt_deg`). The ratios themselves come from
:mod:`taxelkit.smart.pivots`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["arc_limit_turn_deg", "arc_ratio_limit", "grid_tilt_deg", "pivot_lower", "pivot_upper"]


def pivot_upper(
    ratio: NDArray[np.float64], error: NDArray[np.float64], sigmas: float
) -> NDArray[np.float64]:
    """The ratio that "about one end" must keep below: ``ratio + sigmas x error``.

    ``sigmas`` 0: the ratio itself (no allowance for the estimate's uncertainty).
    """
    if sigmas == 0.0:
        return ratio
    out: NDArray[np.float64] = ratio + sigmas * error
    return out


def pivot_lower(
    ratio: NDArray[np.float64], error: NDArray[np.float64], sigmas: float
) -> NDArray[np.float64]:
    """The ratio that "in an arc" must keep above its limit: ``ratio - sigmas x error``.

    ``sigmas`` 0: the ratio itself (no allowance for the estimate's uncertainty).
    """
    return pivot_upper(ratio, error, -sigmas)


def arc_ratio_limit(
    turn_deg: NDArray[np.float64],
    end_ratio: float,
    band: float,
    full_turn_deg: float,
    arc_turn_deg: float,
    line_mm: NDArray[np.float64] | None = None,
    pitch_mm: float = 0.0,
) -> NDArray[np.float64]:
    """Least pivot ratio that reads "in an arc" at each frame's turn, in half-lengths.

    From ``full_turn_deg`` on it is ``end_ratio x band``; below, the pivot is
    located from a shorter turn and its error grows as one over the turn, so
    the band widens in log: ``end_ratio x band ** (full_turn_deg / turn)``.
    Below ``arc_turn_deg``, and (up to ``full_turn_deg``) below twice the
    angle one taxel subtends over the line's drawn length (``2 atan(pitch /
    length)``: a straight roll seen on a coarse array turns by about that much
    from the grid alone): infinite (no verdict).

    Parameters
    ----------
    turn_deg : (n,) float
        Each frame's turn from the reference, deg.
    end_ratio, band : float
        ``pivot_end_ratio`` and ``pivot_band`` of
        :class:`~taxelkit.smart.tacteme_config.TactemeConfig`.
    full_turn_deg, arc_turn_deg : float
        ``pivot_turn_deg`` and ``pivot_arc_turn_deg``, deg.
    line_mm : (n,) float, optional
        Each frame's drawn line length, mm (with ``pitch_mm``).
    pitch_mm : float
        Taxel pitch, mm; 0: the grid is not taken into account.

    Returns
    -------
    (n,) float
    """
    counted = turn_deg > arc_turn_deg
    if line_mm is not None and pitch_mm > 0:
        grid = grid_tilt_deg(line_mm, pitch_mm)
        counted &= (turn_deg > grid) | (turn_deg > full_turn_deg)  # never stricter than that
    scale = np.maximum(1.0, full_turn_deg / np.where(counted, turn_deg, full_turn_deg))
    with np.errstate(over="ignore"):  # a tiny arc_turn_deg: an infinite limit, no arc
        out: NDArray[np.float64] = np.where(counted, end_ratio * band**scale, np.inf)
    return out


def arc_limit_turn_deg(
    turn_deg: NDArray[np.float64],
    largest_deg: NDArray[np.float64],
    line_mm: NDArray[np.float64],
    pitch_mm: float,
    full_turn_deg: float,
) -> NDArray[np.float64]:
    """The turn "in an arc" reads its limit at: the largest so far, where the grid allows.

    The pivot is fitted to every line so far, so its error is set by how far
    the lines have spread (``largest_deg``), not by the turn now. Where the
    grid alone can tilt the line by ``full_turn_deg`` (twice the angle one
    taxel subtends over its drawn length, as in :func:`arc_ratio_limit`), a
    line's largest turn may be the grid's and the turn now stands.

    Parameters
    ----------
    turn_deg, largest_deg : (n,) float
        Each frame's turn from the reference and the largest up to it, deg.
    line_mm : (n,) float
        Each frame's drawn line length, mm.
    pitch_mm : float
        Taxel pitch, mm; 0: unknown (the largest turn everywhere).
    full_turn_deg : float
        ``pivot_turn_deg``, deg.

    Returns
    -------
    (n,) float
    """
    if pitch_mm <= 0:
        return largest_deg
    out: NDArray[np.float64] = np.where(
        grid_tilt_deg(line_mm, pitch_mm) < full_turn_deg, largest_deg, turn_deg
    )
    return out


def grid_tilt_deg(line_mm: NDArray[np.float64], pitch_mm: float) -> NDArray[np.float64]:
    """How far the grid alone can tilt a drawn line: twice the angle one taxel subtends, deg.

    ``2 atan(pitch / length)`` for each line length ``(n,)`` in mm (90 deg for
    a line of no length).
    """
    out: NDArray[np.float64] = 2.0 * np.rad2deg(
        np.arctan2(pitch_mm, np.where(line_mm > 0, line_mm, 0.0))
    )
    return out
