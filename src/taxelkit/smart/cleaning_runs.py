"""Rules 3-4 of the image cleaning computed once per run of equal frames.

A contact held still repeats its image frame after frame (two thirds of the
frames of the benchmark's recordings). Rule 3 (persistence) of a frame equal
to the one before it keeps it whole: its one-frame test passes every taxel
(each is its own neighbour in the previous frame), and so does the two-frame
test (each taxel was on itself in the previous frame). Rule 4 (strays)
depends on the frame alone. So along a run of equal bridged frames only the
first differs from the rest, and :func:`clean_runs` computes rules 3-4 on
the first frame of each run and on its repeat, then lays them out frame by
frame: the same images as :func:`~taxelkit.smart.cleaning._clean` (tested).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.cleaning import CleaningConfig, _crowded, _dilate3, _stray
from taxelkit.smart.gather import take_rows

__all__ = ["RUNS_WORTH", "clean_runs", "clean_runs_if_worth", "run_starts"]

#: Rules 3-4 go by runs when at most this share of the frames starts a run
#: (beyond, gathering the runs costs more than it saves).
RUNS_WORTH = 0.6


def run_starts(a: NDArray[Any], t: int) -> NDArray[np.bool_] | None:
    """``(n,)``: frames of ``a`` ``(n, ...)`` unlike the one before, or first of their array.

    The frames are those of ``n // t`` arrays of ``t`` frames each, laid end to
    end. Compared 64 bits at a time; None when a frame does not fill whole
    64-bit words (or the frames are not contiguous).
    """
    n = a.shape[0]
    per = a.reshape(n, -1)
    if n == 0 or t <= 0 or (per.shape[1] * per.itemsize) % 8 or not per.flags.c_contiguous:
        return None
    w = per.view(np.uint64)
    new = np.empty(n, bool)
    diff = new[1:]
    np.not_equal(w[1:, 0], w[:-1, 0], out=diff)
    for j in range(1, w.shape[1]):
        diff |= w[1:, j] != w[:-1, j]
    new[::t] = True  # each array's first frame starts a run
    return new


def clean_runs(
    ops: Any,
    frames: NDArray[Any],
    first: NDArray[np.intp],
    run: NDArray[np.intp],
    t: int,
    prev: NDArray[Any],
    prev_passed: NDArray[Any],
    config: CleaningConfig,
) -> tuple[NDArray[Any], NDArray[Any]]:
    """Rules 3-4 on bridged packed frames, once per run of equal frames.

    Parameters
    ----------
    ops : PackedRows
        The packed rows of ``frames``.
    frames : (u, ...) unsigned int
        The bridged frame of each run: ``m`` arrays of ``t`` frames each, laid
        end to end, are ``u`` runs of equal frames (none across two arrays).
    first : (u,) int
        Each run's first frame (``flatnonzero`` of :func:`run_starts`).
    run : (m * t,) int
        Each frame's run (``cumsum`` of :func:`run_starts`, less 1).
    t : int
        Frames per array.
    prev, prev_passed : (m, ...) unsigned int
        Each array's bridged frame before its first and that frame's one-frame
        test (rule 3).
    config : CleaningConfig
        With ``persistence`` on.

    Returns
    -------
    out : (m * t, ...) unsigned int
        The cleaned frames: those of :func:`~taxelkit.smart.cleaning._clean`.
    last_passed : (m, ...) unsigned int
        The one-frame test of each array's last frame (the next ``prev_passed``).
    """
    n, u = run.size, first.size
    length = np.diff(first, append=n)
    arr = first // t  # each run's array
    lead = (first % t) == 0  # runs that begin an array
    shape = (-1,) + (1,) * (frames.ndim - 1)  # a per-run flag against the runs' frames
    # the frame before each run's first, and its one-frame test
    before = np.empty_like(frames)
    before[1:] = frames[:-1]
    before[lead] = prev[arr[lead]]
    crowded = _crowded(ops, frames)
    passed = frames & (_dilate3(ops, before) | crowded)
    # a run's later frames pass whole: the test of its last frame
    last_passed = np.where((length >= 2).reshape(shape), frames, passed)
    if config.persistence_depth > 1:
        passed_before = np.empty_like(frames)
        passed_before[1:] = last_passed[:-1]
        passed_before[lead] = prev_passed[arr[lead]]
        head = frames & (before | crowded | _dilate3(ops, passed_before))
    else:
        head = passed
    # rule 4 on each run's first frame and on its repeat (the frame itself)
    table = np.concatenate([head, frames])
    if config.strays:
        stray = _stray(ops, table)
        big = ops.any_per_frame(table & ~stray)
        table = table & ~(stray & ops.per_frame(big, table))
    pick = run + u
    pick[first] -= u
    out = take_rows(table, pick)
    ends = run[t - 1 :: t]  # each array's last run
    return out, last_passed[ends]


def clean_runs_if_worth(
    ops: Any,
    a: NDArray[Any],
    t: int,
    prev: NDArray[Any],
    prev_passed: NDArray[Any],
    config: CleaningConfig,
) -> NDArray[Any] | None:
    """:func:`clean_runs` of bridged frames ``a`` ``(m * t, ...)``, or None if not worth it.

    None when persistence is off, when the frames do not fill whole 64-bit
    words, or when more than :data:`RUNS_WORTH` of them start a run: the
    frame-by-frame rules then serve.
    """
    new = run_starts(a, t) if config.persistence else None
    if new is None or np.count_nonzero(new) > RUNS_WORTH * new.size:
        return None
    first, run = np.flatnonzero(new), np.cumsum(new) - 1
    out, _ = clean_runs(ops, take_rows(a, first), first, run, t, prev, prev_passed, config)
    return out
