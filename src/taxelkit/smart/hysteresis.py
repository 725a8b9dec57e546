"""Schmitt triggers and marks held for frames in a row, for the limits of Level 2.

:mod:`~taxelkit.smart.contact_limits` draws the contact classes' limits with
hysteresis: a contact becomes a line or an area at a higher mark and stays
one down to a lower mark (:func:`schmitt`), and the higher mark must be seen
in two frames in a row where the frames are close (:func:`enter_frames`,
:func:`held_high`): a taxel's flicker lasts one frame at any rate.
:func:`held_high_rows` does the same along many streams at once (the bank's
chunks, :mod:`~taxelkit.smart.limits_rows`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

__all__ = ["enter_frames", "held_high", "held_high_rows", "schmitt", "schmitt_masks"]


def schmitt(
    value: NDArray[np.float64], high: float, low: float, *, start: bool = False
) -> NDArray[np.bool_]:
    """A Schmitt trigger over a sequence, vectorised: on at ``>= high``, off below ``low``.

    Parameters
    ----------
    value : (T,) float
    high, low : float
        Thresholds, ``low <= high``.
    start : bool
        State before the first sample.

    Returns
    -------
    (T,) bool
        The state after each sample: that of the last sample outside the
        band ``[low, high)``.
    """
    return schmitt_masks(value >= high, value < low, start=start)


def schmitt_masks(
    on: NDArray[np.bool_], off: NDArray[np.bool_], *, start: bool = False
) -> NDArray[np.bool_]:
    """:func:`schmitt` from its two decisions: each sample's state is that of the last
    sample that switched it on (``on``) or off (``off``), else ``start``."""
    decisive = on | off
    idx = np.maximum.accumulate(np.where(decisive, np.arange(on.size), -1))
    out: NDArray[np.bool_] = np.where(idx >= 0, on[np.maximum(idx, 0)], start)
    return out


def enter_frames(dt_s: NDArray[np.float64], enter_s: float) -> NDArray[np.int64]:
    """Frames in a row a mark must be seen at each frame's interval ``dt_s``: 2, or 1 if the
    frames are more than ``enter_s`` apart (or the interval is unknown, or ``enter_s`` is 0)."""
    two = np.isfinite(dt_s) & (dt_s > 0.0) & (dt_s <= enter_s)
    out: NDArray[np.int64] = np.where(two, 2, 1).astype(np.int64)
    return out


def held_high(
    value: NDArray[np.float64],
    high: float,
    t_s: NDArray[np.float64],
    enter_s: float,
    run: int = 0,
    t_prev: float = math.nan,
    at_once: float = math.inf,
) -> tuple[NDArray[np.bool_], int, float]:
    """Samples at or above ``high`` for :func:`enter_frames` frames in a row (this one included).

    A sample at or above ``at_once`` is held in its first frame.

    Parameters
    ----------
    value, t_s : (T,) float
        The samples and their times, s.
    high : float
    enter_s : float
        How long the mark must be held, s.
    run : int
        Samples at or above ``high`` in a row just before the first.
    t_prev : float
        Time of the sample before the first, s (NaN: none).
    at_once : float
        Samples at or above this are held at once (default: none).

    Returns
    -------
    held : (T,) bool
    run, t_last : int, float
        The run and the last time, to carry to the next call.
    """
    if value.size == 0:
        return value >= high, run, t_prev
    held, runs, last = held_high_rows(
        value[None], high, np.asarray(t_s, dtype=np.float64)[None], enter_s,
        np.array([run]), np.array([t_prev]), at_once,
    )  # fmt: skip
    return held[0], int(runs[0]), float(last[0])


def held_high_rows(
    value: NDArray[np.float64],
    high: float,
    t_s: NDArray[np.float64],
    enter_s: float,
    run: NDArray[np.int64],
    t_prev: NDArray[np.float64],
    at_once: float = math.inf,
) -> tuple[NDArray[np.bool_], NDArray[np.int64], NDArray[np.float64]]:
    """:func:`held_high` along each row of ``value`` and ``t_s`` ``(m, T)``, ``T >= 1``.

    ``run`` and ``t_prev`` ``(m,)`` are each row's carried run and last
    time; returns the held samples ``(m, T)`` and the new run and last time.
    """
    on = value >= high
    t = on.shape[1]
    # a mark needs 2 frames in a row where the frames are close (enter_frames), else 1:
    # held where on, and on the frame before too (or in the run carried) if it needs 2
    before = np.empty_like(on)
    before[:, 0] = run > 0
    before[:, 1:] = on[:, :-1]
    dt = np.diff(t_s, axis=1, prepend=t_prev[:, None])
    held: NDArray[np.bool_] = on & (before | (enter_frames(dt, enter_s) < 2) | (value >= at_once))
    # the run at the end: frames since the last off one (or all, plus the run carried)
    off_back = np.argmax(~on[:, ::-1], axis=1)  # frames on at the end
    any_off = np.any(~on, axis=1)
    run_end: NDArray[np.int64] = np.where(any_off, off_back, t + run).astype(np.int64)
    return held, run_end, t_s[:, -1].copy()
