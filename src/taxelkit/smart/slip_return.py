"""A line back where it was is not sliding: the slip detector's return tests, and its hold.

:class:`~taxelkit.smart.slip_scan.SlipScanner` opens a slip where the motion
stays above its limit over the hold (:func:`first_hold_hit`). For a line it
first drops the frames whose window is back where the line was
(:class:`ReturnTest`: ``line_return_s`` and ``line_jump_back`` of
:class:`~taxelkit.smart.slip.SlipConfig`): the per-frame rule tests each
frame above the limit, the vectorised scan only the frames that can decide
(:func:`drop_returns`), with the same decisions.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.slip_features import line_returned
from taxelkit.smart.slip_motion import exact_means

__all__ = ["ReturnTest", "drop_returns", "first_hold_hit"]


def first_hold_hit(
    before: Sequence[bool], flags: NDArray[np.bool_], hold: int, needed: int
) -> int | None:
    """The first frame of ``flags`` at which ``needed`` of the last ``hold`` frames are above.

    ``before``: the decided frames just before ``flags`` (the hold carried
    over); the frame itself must be above.
    """
    if not flags.any():
        return None
    h = len(before)
    seq = np.concatenate([np.asarray(before, dtype=bool), flags])
    total = np.concatenate([[0], np.cumsum(seq)])
    j = np.arange(h, seq.size)
    count = total[j + 1] - total[np.maximum(0, j + 1 - hold)]
    hit = np.flatnonzero(seq[h:] & (count >= needed))
    return int(hit[0]) if hit.size else None


@dataclass(frozen=True)
class ReturnTest:
    """Whether a line's windows are back where the line was (its motion then is no slip).

    Attributes
    ----------
    cur, ref : int
        Current and reference windows, frames.
    back : int
        Frames before the reference a window may be back at
        (``line_return_s``; 0: not tested).
    jump : bool
        Also a frame back where a frame of its reference was
        (``line_jump_back``, where one frame lies in every window of the hold).
    tol_mm, area_step : float
        ``line_return_mm`` and ``area_step`` of the config.
    """

    cur: int
    ref: int
    back: int
    jump: bool
    tol_mm: float
    area_step: float

    def returned(
        self, x: NDArray[np.float64], ps: NDArray[np.intp], first_allowed: int
    ) -> NDArray[np.bool_]:
        """Whether the windows ending at frames ``ps`` of ``x`` ``(n, 15)`` are back.

        Back (:func:`~taxelkit.smart.slip_features.line_returned`): a
        window's mean where a single frame of the last :attr:`back` before
        its reference, from row ``first_allowed`` on (the anchor), had the
        line; or, with :attr:`jump`, the frame itself where a frame of its
        reference had it. Each mean is summed row by row (the floats of the
        per-frame rule's means), so a window's verdict does not depend on
        which others are tested with it.
        """
        c, r = self.cur, self.ref
        ps = np.asarray(ps, np.intp)
        lo = ps - c - r + 1  # each reference's first row
        out = np.zeros(ps.size, bool)
        if self.jump:
            g = max(0, int(lo.min()))
            out = line_returned(
                x[ps], x[g : int(ps.max())], lo - g, lo + r - g,
                tol_mm=self.tol_mm, area_step=self.area_step,
            )  # fmt: skip
        if self.back:
            first = np.maximum(np.maximum(lo - self.back, first_allowed), 0)
            todo = np.flatnonzero(~out & (first < lo))
            if todo.size:
                g = int(first[todo].min())
                cur = exact_means(x, ps[todo] - c + 1, c)
                out[todo] = line_returned(
                    cur, x[g : int(lo[todo].max())], first[todo] - g, lo[todo] - g,
                    tol_mm=self.tol_mm, area_step=self.area_step,
                )  # fmt: skip
        return out


def drop_returns(
    flags: NDArray[np.bool_],
    hold: int,
    first_hit: Callable[[NDArray[np.bool_]], int | None],
    returned: Callable[[NDArray[np.intp]], NDArray[np.bool_]],
) -> NDArray[np.bool_]:
    """``flags`` less the frames whose windows are back, testing only those that can decide.

    Those are the frames of the hold that meets the limit first
    (``first_hit``), hold after hold, or without an onset the last ``hold``
    (carried to the next frames): clearing a flag never makes an earlier
    frame meet the hold. ``returned(indices)`` tests frames of ``flags``.
    """
    flags = flags.copy()
    checked = np.zeros(flags.size, bool)
    while True:
        q = first_hit(flags)
        if q is None:  # the hold kept for the next frames
            lo, hi = max(0, flags.size - hold), flags.size
        else:
            lo, hi = max(0, q - hold + 1), q + 1
        todo = np.flatnonzero(flags[lo:hi] & ~checked[lo:hi]) + lo
        if todo.size == 0:
            return flags
        checked[todo] = True
        flags[todo] = ~returned(todo)
