"""Level 2's limits (:mod:`~taxelkit.smart.contact_limits`) along rows of frames, vectorised.

:func:`~taxelkit.smart.contact_limits.apply_limits` limits one stream's
classes; :func:`limits_rows` limits ``m`` streams' chunks of ``T`` frames at
once (the rows of ``(m, T)`` arrays), each row from its own carried state:
whether its contact was long enough for a line and big enough for an area,
its run of frames over the area's higher mark and its last frame's time.
The classes are those of ``apply_limits`` on each whole stream
(:class:`~taxelkit.smart.levels12.ChunkLevels12`'s tests).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.contact_classes import AREA_MIN_AREA_MM2, ContactClass
from taxelkit.smart.contact_limits import (
    ContactLimits,
    _length_thresholds,
    line_dropped,
    line_lengths,
)
from taxelkit.smart.hysteresis import held_high_rows

__all__ = ["limits_rows", "schmitt_rows"]

_LINE, _AREA = int(ContactClass.LINE), int(ContactClass.AREA)
#: Each row's limit state: long, big, area run, last time (s), line run, last length (mm).
_State = tuple[
    NDArray[np.bool_],
    NDArray[np.bool_],
    NDArray[np.int64],
    NDArray[np.float64],
    NDArray[np.int64],
    NDArray[np.float64],
]
_POINT, _INDET = int(ContactClass.POINT), int(ContactClass.INDETERMINATE)


def schmitt_rows(
    on: NDArray[np.bool_], off: NDArray[np.bool_], start: NDArray[np.bool_]
) -> NDArray[np.bool_]:
    """:func:`~taxelkit.smart.hysteresis.schmitt_masks` along each row, from its own state.

    ``on``, ``off`` ``(m, T)``: where the trigger is set and reset; ``start``
    ``(m,)``: each row's state before its first frame.
    """
    decisive = on | off
    idx = np.maximum.accumulate(np.where(decisive, np.arange(on.shape[1]), -1), axis=1)
    last = np.take_along_axis(on, np.maximum(idx, 0), axis=1)
    out: NDArray[np.bool_] = np.where(idx >= 0, last, start[:, None])
    return out


def limits_rows(
    classes: NDArray[np.int8],
    taxels: NDArray[np.int64],
    area: NDArray[np.float64],
    elong: NDArray[np.float64],
    half: NDArray[np.float64],
    t_s: NDArray[np.float64],
    limits: ContactLimits,
    state: _State,
) -> tuple[NDArray[np.int8], _State]:
    """Limited classes of ``m`` rows of frames ``(m, T)``, and each row's state after them.

    Parameters
    ----------
    classes : (m, T) int8
        :class:`~taxelkit.smart.contact_classes.ContactClass` codes before the limits.
    taxels, area, elong, half : (m, T)
        Taxels in contact, area (mm^2), elongation and half-length (mm) of each frame.
    t_s : (m, T) float, s
        The frames' times.
    limits : ContactLimits
    state : ((m,) bool, (m,) bool, (m,) int, (m,) float, (m,) int, (m,) float)
        Each row's state before its first frame: long enough for a line, big
        enough for an area, frames in a row over the area's higher mark, the
        last frame's time (s; NaN: none), frames in a row over the line's
        length and the last frame's length (mm; 0: no contact).

    Returns
    -------
    classes : (m, T) int8
    state : as the parameter, after the last frame
    """
    long0, big0, run0, t_prev0, line_run0, length0 = state
    length = np.where(taxels > 0, 2.0 * half, 0.0)
    high, low = _length_thresholds(limits)
    as_line = line_lengths(classes, length, limits)  # only a line's length makes a line
    held_l, line_run, _ = held_high_rows(
        as_line, high, t_s, limits.line_enter_s, line_run0, t_prev0, limits.line_confirm_mm
    )
    before = np.concatenate([length0[:, None], length[:, :-1]], axis=1)
    long = schmitt_rows(held_l, (length < low) | line_dropped(length, before, limits), long0)
    enter = AREA_MIN_AREA_MM2 * (1.0 + limits.area_hysteresis)
    held, run, t_last = held_high_rows(area, enter, t_s, limits.area_enter_s, run0, t_prev0)
    big = schmitt_rows(held, area < AREA_MIN_AREA_MM2, big0)
    out = classes.copy()
    out[(out == _LINE) & ~long] = _INDET
    out[(out == _AREA) & ~big] = _INDET
    cap = limits.point_max_area_mm2
    if cap is not None:
        compact = (taxels > 0) & (elong <= 2.0) & (area <= cap)
        out[compact & (out == _INDET)] = _POINT
    few = (taxels > 0) & (taxels <= limits.point_max_taxels) & (elong <= 2.0)
    out[few & (out != _LINE)] = _POINT
    return out, (long[:, -1], big[:, -1], run, t_last, line_run, length[:, -1].copy())
