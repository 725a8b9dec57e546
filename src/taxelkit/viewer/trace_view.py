"""Log an edge trace of paper 000 to rerun: the probe path, the edges it saw, the recall curve.

Every entry is on the ``section`` timeline (the tracer's section index, 0 at
the start point), so scrubbing it replays the trace as it happened:

=============================== ========================================================
``trace/path``                  the array centres visited so far, one line strip (mm)
``trace/probe``                 the array centre at this section, a point (mm)
``trace/edges``                 every edge estimated so far: per section, the segment
                                from the point corrected by ``de`` along ``dv`` (Eq. 7)
``recall/correlation/<name>``   ``c`` (Eq. 14) of each stored contour at the arc length
                                reached by this section (a scalar)
``recall/recognised``           the top-ranked contour whenever it changes (text)
``trace/verdict``               a last line: how the trace ended and what was recognised
=============================== ========================================================

Plane coordinates are the plate's, mm (x right, y up). The recall curve's
``s`` (normalised arc length) is placed at the section whose arc length first
reaches it.
"""

from __future__ import annotations

import os
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.memory.contour_recall import RecallCurve
from taxelkit.tracing.tracer import Trace
from taxelkit.viewer.rerun_view import close_stream, open_stream

__all__ = ["TRACE_ENTITY_PATHS", "edge_segments_mm", "view_trace"]

#: Entity path of each kind of entry (``recall/correlation`` is a prefix: one child per contour).
TRACE_ENTITY_PATHS = {
    "path": "trace/path",
    "probe": "trace/probe",
    "edges": "trace/edges",
    "correlation": "recall/correlation",
    "recognised": "recall/recognised",
    "verdict": "trace/verdict",
}


def edge_segments_mm(trace: Trace) -> NDArray[np.float64]:
    """The edge estimated at each section, as a segment on the plate.

    Parameters
    ----------
    trace : Trace
        A trace from :func:`~taxelkit.tracing.tracer.trace_edge`.

    Returns
    -------
    (K, 2, 2) float, mm
        Section ``k``'s segment from ``p_k + de_k`` to ``p_k + de_k + dv_k``
        (Eq. 7: the point brought onto the edge, then one section along it);
        NaN at a section where no edge was seen.
    """
    start = trace.points_mm[:-1] + trace.de_mm
    segments = np.stack([start, start + trace.dv_mm], axis=1)
    missed = ~np.isfinite(trace.normals).all(axis=1)
    segments[missed] = np.nan
    return segments


def _section_of_s(trace: Trace, s: NDArray[np.float64]) -> NDArray[np.int64]:
    """The first section whose arc length reaches each normalised arc length ``s``."""
    arc = trace.arc_length_mm
    total = float(arc[-1]) if arc[-1] > 0 else 1.0
    index = np.searchsorted(arc / total, np.asarray(s, dtype=np.float64) - 1e-12)
    return np.clip(index, 0, trace.n_sections).astype(np.int64)


def view_trace(
    trace: Trace,
    curve: RecallCurve,
    *,
    save_path: str | os.PathLike[str] | None = None,
    spawn: bool = False,
    connect_url: str | None = None,
) -> int:
    """Log a trace and its recall curve to an ``.rrd`` file and/or a rerun viewer.

    Parameters
    ----------
    trace : Trace
        The traced contour.
    curve : RecallCurve
        :func:`~taxelkit.memory.contour_recall.recall_curve` of ``trace.moves_mm``.
    save_path : str or os.PathLike, optional
        The ``.rrd`` file to write.
    spawn : bool, optional
        Show it in a rerun viewer on this machine.
    connect_url : str, optional
        Stream it to the viewer at this address.

    Returns
    -------
    int
        Number of sections logged (``K + 1`` points of the path).

    Raises
    ------
    ViewerDependencyError
        If rerun-sdk is not installed.
    ViewerConnectionError
        If a viewer was asked for and could not be reached.
    """
    rr, stream = open_stream(save_path=save_path, spawn=spawn, connect_url=connect_url)
    points = trace.points_mm
    segments = edge_segments_mm(trace)
    seen = np.asarray(np.isfinite(segments).all(axis=(1, 2)), dtype=bool)
    for k in range(points.shape[0]):
        stream.set_time("section", sequence=k)
        stream.log(TRACE_ENTITY_PATHS["path"], rr.LineStrips2D([points[: k + 1]]))
        stream.log(TRACE_ENTITY_PATHS["probe"], rr.Points2D([points[k]]))
        if k > 0 and seen[:k].any():
            stream.log(TRACE_ENTITY_PATHS["edges"], rr.LineStrips2D(segments[:k][seen[:k]]))
    _log_curve(rr, stream, trace, curve)
    stream.set_time("section", sequence=trace.n_sections)
    ending = "closed" if trace.closed else trace.stop_reason
    verdict = curve.verdicts[-1] if curve.verdicts else "-"
    stream.log(
        TRACE_ENTITY_PATHS["verdict"],
        rr.TextLog(f"{trace.n_sections} sections ({ending}); recognised: {verdict}"),
    )
    close_stream(stream)
    return int(points.shape[0])


def _log_curve(rr: Any, stream: Any, trace: Trace, curve: RecallCurve) -> None:
    """Log the correlations and the top-ranked contour at each ``s`` of the curve."""
    sections = _section_of_s(trace, curve.s)
    last = None
    for j, k in enumerate(sections):
        stream.set_time("section", sequence=int(k))
        for name, c in zip(curve.names, curve.correlations[j], strict=True):
            stream.log(f"{TRACE_ENTITY_PATHS['correlation']}/{name}", rr.Scalars(float(c)))
        if curve.verdicts[j] != last:
            last = curve.verdicts[j]
            text = f"s = {float(curve.s[j]):.2f}: {last}"
            stream.log(TRACE_ENTITY_PATHS["recognised"], rr.TextLog(text))
