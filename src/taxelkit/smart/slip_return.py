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

__all__ = ["ReturnTest", "drop_returns", "first_hold_hit", "reseat_steps"]


def reseat_steps(x: NDArray[np.float64], limit_mm: float) -> NDArray[np.bool_]:
    """Whether both drawn ends of a line stepped along it together, beyond ``limit_mm``.

    For each row of ``x`` ``(n, 15)`` but the first (``(n - 1,)``): the
    ends' moves from the row before, along that row's line (from its first
    end to its second), both of one sign and both longer than ``limit_mm``.
    Only IEEE-exact operations (products, sums and one square root, no
    division or trigonometry): the same decisions on every CPU and in every
    path. Rows whose ends were not measured (NaN) never step.
    """
    a, b = x[:-1], x[1:]
    lx, ly = a[:, 9] - a[:, 7], a[:, 10] - a[:, 8]  # the line, first end to second
    d1 = (b[:, 7] - a[:, 7]) * lx + (b[:, 8] - a[:, 8]) * ly  # moves along it, times its length
    d2 = (b[:, 9] - a[:, 9]) * lx + (b[:, 10] - a[:, 10]) * ly
    far = limit_mm * np.sqrt(lx * lx + ly * ly)
    out: NDArray[np.bool_] = (d1 * d2 > 0.0) & (np.abs(d1) > far) & (np.abs(d2) > far)
    return out


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
    reseat_mm : float
        Also a pair of windows across which the line reseated: both ends
        stepped along it, the same way, by more than this in one frame
        (:func:`reseat_steps`), with no such step in the :attr:`rest`
        frames before (``line_reseat_s``; 0: not tested).
    rest : int
        Frames without a step of both ends before a reseat.
    """

    cur: int
    ref: int
    back: int
    jump: bool
    tol_mm: float
    area_step: float
    reseat_mm: float = 0.0
    rest: int = 0

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
        which others are tested with it. With :attr:`reseat_mm`, also the
        windows across which the line's ends stepped together (:func:`reseat_steps`).
        """
        c, r = self.cur, self.ref
        ps = np.asarray(ps, np.intp)
        lo = ps - c - r + 1  # each reference's first row
        out = np.zeros(ps.size, bool)
        seated = np.zeros(ps.size, bool)
        if self.reseat_mm > 0.0 and ps.size:
            g = max(0, int(lo.min()) - self.rest, first_allowed)
            both = reseat_steps(x[g : int(ps.max()) + 1], self.reseat_mm)
            # both[j - 1]: the ends stepped together into row g + j; a reseat: none in the rest
            # before (a slide whose two ends keep stepping together is judged at its next step)
            moved = np.concatenate([[0], np.cumsum(both)])  # moved[j]: into rows g + 1 .. g + j
            j = np.arange(1, both.size + 1)
            calm = moved[j - 1] - moved[np.maximum(j - 1 - self.rest, 0)] == 0
            upto = np.concatenate([[0], np.cumsum(both & calm)])
            seated = upto[ps - g] - upto[np.clip(lo - g, 0, None)] > 0  # into rows lo + 1 .. ps
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
        return out | seated


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
