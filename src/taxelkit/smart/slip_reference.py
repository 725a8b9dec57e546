"""The slip detector's rule as written: each frame decided in turn (the reference scan).

:class:`~taxelkit.smart.slip_scan.SlipScanner` built with ``reference=True``
decides its frames here, one by one in Python, exactly as
:mod:`taxelkit.smart.slip` states the rule: the onset (the motion between
the reference and the current window above the limit over the hold, a
line's returns dropped), the restart of the reference where the area
changed, and the end (the footprint still between two windows of
``end_s``). The default, vectorised scan of
:class:`~taxelkit.smart.slip_scan.SlipScanner` is tested to decide the same
slips for any chunking.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.slip import SLIP_KINDS, Slip
from taxelkit.smart.slip_motion import row_window_means

if TYPE_CHECKING:
    from taxelkit.smart.slip_scan import SlipScanner

__all__ = ["scan_frames"]


def scan_frames(
    scan: SlipScanner, x: NDArray[np.float64], fr: NDArray[np.intp], base: int, first: int
) -> list[Slip]:
    """Decide the frames ``x[first:]`` of ``scan``'s segment one by one.

    Parameters
    ----------
    scan : SlipScanner
        The scanner, started (its windows known); its hold, anchor and open
        slip are updated.
    x : (n, 15) float
        Slip features of the kept frames and the new ones
        (:func:`~taxelkit.smart.slip_features.slip_features`).
    fr : (n,) int
        Their frame numbers.
    base : int
        Segment index of ``x[0]``.
    first : int
        The first row of ``x`` not decided before.

    Returns
    -------
    list of Slip
        Slips opened or closed by these frames, in order (a slip opened and
        closed here is listed once, closed).
    """
    c, r, e = scan.cur, scan.ref, scan.end
    cur_m = row_window_means(x, c)  # cur_m[p - c + 1]: frames p - c + 1 .. p
    ref_m = row_window_means(x, r)  # full reference windows
    end_m = row_window_means(x, e)
    out: list[Slip] = []
    cfg = scan.config
    for p in range(first, x.shape[0]):
        i = base + p  # segment index of this frame
        if scan._open is None:
            lo = i - c - r + 1  # the reference: a full window, all after the anchor
            if lo < scan._anchor:
                continue
            ref = ref_m[lo - base]
            motion = scan.motion_mm(ref, cur_m[p - c + 1])
            if math.isnan(motion):
                scan._anchor, scan._above = i - c + 1, []
                continue
            above = motion > scan._limit_mm
            if above and scan._back is not None:
                above = not scan._back.returned(x, np.array([p]), scan._anchor - base)[0]
            keep = scan._above[max(0, len(scan._above) + 1 - scan.hold) :]
            scan._above = [*keep, above]
            if scan._above[-1] and sum(scan._above) >= scan.hold_needed:
                q = max(0, p - scan.hold - c + 2)
                onset, scan._open_i = int(fr[q]), base + q
                scan._open = Slip(SLIP_KINDS[scan.cls], onset, int(fr[p]))
                scan._above = []
                out.append(scan._open)
        elif p - 2 * e + 1 >= 0 and i - e + 1 >= scan._open_i:  # the last window: all slip
            step = scan.motion_mm(end_m[p - 2 * e + 1], end_m[p - e + 1])
            if not step > cfg.still_mm:  # still (or the contact changed): the slip ended
                scan._end_open(out, fr, p, i - e + 1)
    return out
