"""The pivot of a turning line for Level 3: where the lines of a roll meet, and how surely.

A rolling cone's contact line turns about its apex, a truncated cone's about a
virtual apex beyond the line's end, and a line spun in place about its
middle. The least-squares common point of the lines seen so far (the pivot),
its distance from the current line's centre in half-lengths (the ratio), and
the uncertainty of that ratio, from running sums shared by the batch rules
(:mod:`taxelkit.smart.tactemes`) and their streaming twin
(:class:`~taxelkit.smart.pivot_stream.PivotRun`). The limits the verdicts
read them against are in :mod:`taxelkit.smart.pivot_limits`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.segment_runs import Runs
from taxelkit.smart.track_geometry import drawn_half_mm

__all__ = [
    "MIN_PRESSED_SHARE",
    "drawn_lines",
    "drawn_pivot_fit",
    "pivot_fit",
    "pivot_from_sums",
    "pivot_ratios",
    "pivot_sums",
    "pivot_terms",
    "pressed_half_mm",
    "trailing_mean",
]

#: The least share of a line's drawn half-length that :func:`pressed_half_mm` keeps.
MIN_PRESSED_SHARE = 0.25


def pressed_half_mm(
    drawn_half_mm: NDArray[np.float64], area_mm2: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Half the length of the pressed line under a drawn one: the drawn half less its half-width.

    The skin spreads a line contact's footprint by about as much along the
    line, beyond each pressed end, as across it, and the drawn ends are
    widened by half a pitch (:func:`~taxelkit.smart.line_extents.line_extents`)
    as its sides are by the taxel cells; a pressed line is thin, so the
    footprint's half-width, ``area / (2 x drawn length)``, is mostly that
    spread. Taking it off each end leaves the pressed line, whose half-length
    a pivot's distance is compared with: a cone's apex then lies about 1
    half-length from the middle at any size (the drawn yardstick put a short
    truncated cone's virtual apex, 2.08 pressed half-lengths out, at 1.4 drawn
    ones). At least :data:`MIN_PRESSED_SHARE` of the drawn half-length.

    Parameters
    ----------
    drawn_half_mm : (n,) float
        Half of each line's drawn length, mm.
    area_mm2 : (n,) float
        Each line's contact area, mm^2.

    Returns
    -------
    (n,) float
    """
    safe = np.where(drawn_half_mm > 0, drawn_half_mm, 1.0)
    half_width = area_mm2 / (4.0 * safe)
    out: NDArray[np.float64] = np.maximum(
        drawn_half_mm - half_width, MIN_PRESSED_SHARE * drawn_half_mm
    )
    return out


def pivot_ratios(
    orientation_deg: NDArray[np.float64],
    centre_mm: NDArray[np.float64],
    half_length_mm: NDArray[np.float64],
) -> NDArray[np.float64]:
    """Distance from each line's centre to the common point of the lines so far, in half-lengths.

    For each ``j``: the least-squares common point of the lines ``0..j``
    (running sums of ``n n^T`` and ``n (n . c)``, ``n`` the lines' normals),
    its distance from the centre of line ``j``, divided by the mean
    half-length of lines ``0..j``. NaN while the lines are too
    close to parallel for a common point (condition number above 1e6).
    The first of :func:`pivot_fit`'s two results.
    """
    return pivot_fit(orientation_deg, centre_mm, half_length_mm)[0]


def pivot_fit(
    orientation_deg: NDArray[np.float64],
    centre_mm: NDArray[np.float64],
    half_length_mm: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """:func:`pivot_ratios` and the uncertainty of each, both in half-lengths.

    Parameters
    ----------
    orientation_deg : (n,) float
        The lines' axes, deg.
    centre_mm : (n, 2) float
        Their centres, mm.
    half_length_mm : (n,) float
        Their half-lengths, mm.

    Returns
    -------
    ratio, error : (n,) float
        The ratio of :func:`pivot_ratios`, and its uncertainty (see
        :func:`pivot_from_sums`); NaN where the ratio is.
    """
    sums = pivot_sums(orientation_deg, centre_mm, half_length_mm)
    return pivot_from_sums(sums, 0, centre_mm[:, 0], centre_mm[:, 1])


def drawn_pivot_fit(
    orientation_deg: NDArray[np.float64],
    centre_mm: NDArray[np.float64],
    half_length_mm: NDArray[np.float64],
    extent_mm: NDArray[np.float64] | None = None,
    arc_w: int = 1,
    *,
    runs: Runs | None = None,
    area_mm2: NDArray[np.float64] | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """:func:`pivot_fit` of drawn lines, and the ratio that "in an arc" reads.

    With the lines' extents, each line is its drawn segment (its middle and
    half its length); without, its moment centre and half-length. With their
    areas, the ratios are in half-lengths of the pressed lines
    (:func:`pressed_half_mm`), else of the drawn ones.

    Parameters
    ----------
    orientation_deg : (n,) float
        The lines' axes, deg.
    centre_mm : (n, 2) float
        Their moment centres, mm.
    half_length_mm : (n,) float
        Their moment half-lengths, mm.
    extent_mm : (n, 2) float, optional
        Each line's drawn ends along its axis from its centre, mm (NaN where
        not measured; :func:`~taxelkit.smart.line_extents.line_extents`).
    arc_w : int
        Lines whose mean middle (:func:`trailing_mean`) the third ratio is
        measured from; 1: the current line's, the first ratio itself.
    runs : Runs, optional
        The lines are several runs laid end to end (each its own fit, as if
        alone); None: one run.
    area_mm2 : (n,) float, optional
        The lines' contact areas, mm^2.

    Returns
    -------
    ratio, error, arc_ratio : (n,) float
    """
    centre, half = drawn_lines(orientation_deg, centre_mm, half_length_mm, extent_mm)
    if area_mm2 is not None:
        half = pressed_half_mm(half, area_mm2)
    terms = pivot_terms(orientation_deg, centre, half)
    count: int | NDArray[np.intp] = 0
    if runs is None:
        sums = np.cumsum(terms, axis=0)
    else:
        sums, count = runs.cumsum(terms), runs.local + 1
    ratio, error = pivot_from_sums(sums, count, centre[:, 0], centre[:, 1])
    if arc_w <= 1:
        return ratio, error, ratio
    local = None if runs is None else runs.local
    mean = trailing_mean(centre, arc_w, local=local)  # each run's own window
    return ratio, error, pivot_from_sums(sums, count, mean[:, 0], mean[:, 1])[0]


def drawn_lines(
    orientation_deg: NDArray[np.float64],
    centre_mm: NDArray[np.float64],
    half_length_mm: NDArray[np.float64],
    extent_mm: NDArray[np.float64] | None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Each line as its drawn segment: its middle (n, 2) and half its length (n,), mm.

    Where the extent is not measured (NaN), or without extents, the moment
    centre and half-length stand.
    """
    if extent_mm is None:
        return centre_mm, half_length_mm
    ext = extent_mm
    measured: NDArray[np.bool_] = np.isfinite(ext[:, 0]) & np.isfinite(ext[:, 1])
    t = np.deg2rad(orientation_deg)
    offset = 0.5 * (ext[:, 0] + ext[:, 1])
    middle = centre_mm + offset[:, None] * np.stack([np.cos(t), np.sin(t)], axis=-1)
    return np.where(measured[:, None], middle, centre_mm), drawn_half_mm(half_length_mm, ext)


def pivot_terms(
    orientation_deg: NDArray[np.float64],
    centre_mm: NDArray[np.float64],
    half_length_mm: NDArray[np.float64],
) -> NDArray[np.float64]:
    """Each line's terms of :func:`pivot_sums` (before summing), (n, 7)."""
    t = np.deg2rad(orientation_deg)
    nx, ny = -np.sin(t), np.cos(t)  # line normals
    d = nx * centre_mm[:, 0] + ny * centre_mm[:, 1]
    return np.stack([nx * nx, nx * ny, ny * ny, nx * d, ny * d, half_length_mm, d * d], axis=-1)


def pivot_sums(
    orientation_deg: NDArray[np.float64],
    centre_mm: NDArray[np.float64],
    half_length_mm: NDArray[np.float64],
) -> NDArray[np.float64]:
    """The running sums of :func:`pivot_from_sums` over the lines ``0..j``, for each ``j``.

    Parameters
    ----------
    orientation_deg : (n,) float
        The lines' axes, deg.
    centre_mm : (n, 2) float
        Their centres, mm.
    half_length_mm : (n,) float
        Their half-lengths, mm.

    Returns
    -------
    (n, 7) float
    """
    out: NDArray[np.float64] = np.cumsum(
        pivot_terms(orientation_deg, centre_mm, half_length_mm), axis=0
    )
    return out


def trailing_mean(
    values: NDArray[np.float64],
    w: int,
    before: NDArray[np.float64] | None = None,
    *,
    local: NDArray[np.intp] | None = None,
) -> NDArray[np.float64]:
    """Mean of each row and the ``w - 1`` rows before it (fewer at the start), along axis 0.

    The sum is taken row by row, newest first (a row outside the window adds
    an exact zero), so that the same window gives the same floats whether the
    rows arrive at once (batch), in chunks (streaming, with the rows before
    the chunk in ``before``) or as several runs laid end to end (``local``).

    Parameters
    ----------
    values : (n, d) float
        The rows.
    w : int
        Window, rows (>= 1).
    before : (b, d) float, optional
        The rows just before ``values``, oldest first: at least ``w - 1`` of
        them, or all there were. None: none.
    local : (n,) int, optional
        Each row's index within its run, for runs laid end to end (windows
        stop at a run's first row); not with ``before``.

    Returns
    -------
    (n, d) float
    """
    head = values[:0] if before is None else before[max(0, before.shape[0] - (w - 1)) :]
    b, n = head.shape[0], values.shape[0]
    pos = np.arange(b, b + n) if local is None else np.asarray(local)
    # the rows, led by w - 1 zero rows so that every lag is a plain slice
    rows = np.concatenate([np.zeros((w - 1, *values.shape[1:])), head, values])
    acc = np.zeros_like(values)
    top = int(pos.max()) if n else -1
    low = int(pos.min()) if n else 0
    lags = min(w, top + 1)
    # A sum begun at +0 is never -0, so adding a finite row's exact zero (x * 0)
    # leaves it as it is: with every row finite, a row a lag does not reach keeps
    # its sum (the same floats; those rows, sorted by position, are a prefix);
    # else it adds x * 0 (NaN stays NaN).
    finite = low < lags - 1 and bool(np.all(np.isfinite(rows)))
    if finite:
        early = np.flatnonzero(pos < lags - 1)
        order = early[np.argsort(pos[early], kind="stable")]
        cuts = np.searchsorted(pos[order], np.arange(lags)).tolist()
    for lag in range(lags):
        start = w - 1 + b - lag
        if lag <= low:  # every row reaches back this far: the plain rows (x * 1 is x)
            acc += rows[start : start + n]
        elif finite:
            short = order[: cuts[lag]]  # the rows this lag does not reach
            kept = acc[short]
            acc += rows[start : start + n]
            acc[short] = kept
        else:
            acc += rows[start : start + n] * (pos >= lag)[:, None]
    count = np.minimum(pos + 1, w).astype(np.float64)  # the lags each row had (exact)
    out: NDArray[np.float64] = acc / count[:, None]
    return out


def pivot_from_sums(
    sums: NDArray[np.float64],
    count: int | NDArray[np.intp],
    cx: NDArray[np.float64],
    cy: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Pivot ratio and its uncertainty from the running sums of the lines (batch and streaming).

    Parameters
    ----------
    sums : (m, 7) float
        Running sums over the lines so far of ``nx nx``, ``nx ny``, ``ny ny``,
        ``nx d``, ``ny d``, the half-length (mm) and ``d d``, where ``(nx, ny)``
        is a line's normal and ``d`` its distance from the origin along it (mm).
    count : int or (m,) int
        Lines summed before the first row; or, per row, the lines summed in it.
    cx, cy : (m,) float
        Each row's line centre, mm.

    Returns
    -------
    ratio : (m,) float
        Distance from the line's centre to the least-squares common point,
        over the mean half-length; NaN while the lines are too close to
        parallel (condition number above 1e6).
    error : (m,) float
        The common point's uncertainty along the lines, in the same
        half-lengths: the lines' rms distance from it over the rms sine of
        their spread about their mean direction (the error of one line's
        noise seen across the turn; it does not shrink with the number of
        frames, so it reads the same at any frame rate). Zero for lines
        through one point.
    """
    sxx, sxy, syy, bx, by, sh, dd = (sums[:, k] for k in range(7))
    det = sxx * syy - sxy * sxy
    trace = sxx + syy
    well = det > 1e-6 * trace * trace  # eigenvalue ratio above ~1e-6
    safe = np.where(well, det, 1.0)
    px = (syy * bx - sxy * by) / safe
    py = (sxx * by - sxy * bx) / safe
    if np.ndim(count) == 0:
        before = int(count)
        lines = np.arange(before + 1, before + sums.shape[0] + 1)
    else:
        lines = np.asarray(count)
    half = sh / lines
    dist = np.hypot(px - cx, py - cy)
    ok = well & (half > 0)
    scale = np.where(half > 0, half, 1.0)
    ratio: NDArray[np.float64] = np.where(ok, dist / scale, np.nan)
    # residual sum of squares of the lines about (px, py), and the smaller eigenvalue
    # of the normals' scatter (det / larger one: no cancellation)
    rss = px * (px * sxx + 2.0 * py * sxy) + py * py * syy - 2.0 * (px * bx + py * by) + dd
    rss = np.maximum(rss, 0.0)
    big = 0.5 * (trace + np.sqrt(np.maximum(trace * trace - 4.0 * det, 0.0)))
    small = np.where(ok, det / np.where(big > 0, big, 1.0), 1.0)
    error: NDArray[np.float64] = np.where(ok, np.sqrt(rss / small) / scale, np.nan)
    return ratio, error
