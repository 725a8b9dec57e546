"""The edge-tracing controller of paper 000 (Section IV, Eq. 7, Fig. 3).

At each point the probe scans along x and y, :func:`estimate_edge` reads the
edge, and the manipulator moves by ``dr = dv + de`` (Eq. 7): ``dv`` is one
point-to-point section (3 mm, the pitch, Section VI.3) along the edge with the
raised side on the left, and ``de`` the error vector that brings the edge back
under the array centre (Ishikawa's active sensing). The loop stops when it
closes (back within ``close_radius_mm`` of its start after at least
``min_loop_mm`` of travel) or after ``max_sections`` sections.

The tracer sees only what the probe returns (frames and its own commanded
positions), never the specimen.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.motion.probe import TactileProbe
from taxelkit.tracing.edge_estimate import EdgeDetectorConfig, EdgeEstimate, estimate_edge
from taxelkit.tracing.line_fit import line_intersection

__all__ = [
    "PTP_SECTION_MM",
    "Trace",
    "TracerConfig",
    "find_edge",
    "plan_move",
    "trace_edge",
]

logger = logging.getLogger(__name__)

#: Length of one point-to-point section, mm: the sensor pitch (paper 000, Sect. VI.3).
PTP_SECTION_MM = 3.0
#: The loop is closed when the tracer comes back near its start or near one of
#: its first few points (the start may sit off the contour, e.g. next to a
#: concave corner; the next points lie on the edge once ``de`` has acted).
CLOSURE_HEAD_POINTS = 3
#: Re-sensing steps of :func:`find_edge` to centre the array on the edge it found.
FIND_EDGE_REFINEMENTS = 5
#: :func:`find_edge` stops refining when the error vector is shorter than this, mm.
FIND_EDGE_TOLERANCE_MM = 0.3


@dataclass(frozen=True)
class TracerConfig:
    """Parameters of the edge-tracing controller.

    Parameters
    ----------
    section_mm : float
        Length of ``dv``, one point-to-point section, mm.
    error_gain : float
        Weight of ``de`` in ``dr = dv + gain * de`` (1 is Eq. 7).
    max_sections : int
        Hard stop.
    close_radius_mm : float
        The loop is closed when the array centre comes back this close to its
        start or to one of its first :data:`CLOSURE_HEAD_POINTS` points.
    min_loop_mm : float
        Path length travelled before closing is considered, mm.
    max_misses : int
        Consecutive points with no edge before giving up; at a miss the tracer
        coasts one section along its last direction.
    detector : EdgeDetectorConfig
    """

    section_mm: float = PTP_SECTION_MM
    error_gain: float = 1.0
    max_sections: int = 300
    close_radius_mm: float = 3.0
    min_loop_mm: float = 30.0
    max_misses: int = 2
    detector: EdgeDetectorConfig = field(default_factory=EdgeDetectorConfig)

    def __post_init__(self) -> None:
        check_positive("section_mm", self.section_mm)
        check_positive("error_gain", self.error_gain, allow_zero=True)
        check_positive("close_radius_mm", self.close_radius_mm)
        check_positive("min_loop_mm", self.min_loop_mm, allow_zero=True)
        if int(self.max_sections) < 1:
            raise InputError(f"max_sections must be >= 1, got {self.max_sections!r}")
        if int(self.max_misses) < 0:
            raise InputError(f"max_misses must be >= 0, got {self.max_misses!r}")


@dataclass(frozen=True, eq=False)
class Trace:
    """A traced contour with per-section diagnostics.

    Attributes
    ----------
    points_mm : (K + 1, 2) float, mm
        Commanded array centres, from the start to the last point.
    moves_mm : (K, 2) float, mm
        ``dr`` of every section (Eq. 7); the input of chain-symbolizing.
    dv_mm, de_mm : (K, 2) float, mm
        The two terms of Eq. 7 for every section (``dv`` is zero at a miss).
    normals : (K, 2) float
        Edge normal seen at each point (NaN at a miss).
    n_crossings : (K,) int
        Crossing points found at each point.
    closed : bool
        True when the loop closed.
    stop_reason : str
        ``"closed"``, ``"max_sections"`` or ``"lost"``.
    """

    points_mm: NDArray[np.float64]
    moves_mm: NDArray[np.float64]
    dv_mm: NDArray[np.float64]
    de_mm: NDArray[np.float64]
    normals: NDArray[np.float64]
    n_crossings: NDArray[np.int64]
    closed: bool
    stop_reason: str

    @property
    def n_sections(self) -> int:
        """Number of sections ``K``."""
        return int(self.moves_mm.shape[0])

    @property
    def arc_length_mm(self) -> NDArray[np.float64]:
        """Cumulative path length at every point, ``(K + 1,)`` mm."""
        steps = np.hypot(self.moves_mm[:, 0], self.moves_mm[:, 1])
        return np.concatenate([[0.0], np.cumsum(steps)])

    def straightness(self, *, axis_tolerance_deg: float = 3.0) -> float | None:
        """``|r|``, Pearson correlation of the points' x and y (paper 000, Fig. 7).

        Parameters
        ----------
        axis_tolerance_deg : float
            ``r`` measures straightness only for oblique lines: it tends to 0 as
            a perfectly straight line turns parallel to an axis. Within this
            angle of the x or y axis (principal direction of the points) the
            result is ``None``, as the paper leaves 0 and 90 deg unquoted.

        Returns
        -------
        float or None
        """
        p = self.points_mm - self.points_mm.mean(axis=0)
        if p.shape[0] < 3:
            return None
        _, vecs = np.linalg.eigh(p.T @ p)
        angle = float(np.rad2deg(np.arctan2(vecs[1, 1], vecs[0, 1]))) % 90.0
        if min(angle, 90.0 - angle) < axis_tolerance_deg:
            return None
        return float(abs(np.corrcoef(p[:, 0], p[:, 1])[0, 1]))


def _ray_distance(
    p: NDArray[np.float64], origin: NDArray[np.float64], direction: NDArray[np.float64]
) -> float:
    """Distance from ``p`` to the ray ``origin + s * direction``, ``s >= 0``."""
    s = max(0.0, float((p - origin) @ direction))
    return float(np.hypot(*(p - origin - s * direction)))


def plan_move(
    est: EdgeEstimate, centre_mm: NDArray[np.float64], cfg: TracerConfig
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """``(dv, de, heading)`` of Eq. 7 for one section, turning corners when two edges are seen.

    With one edge: ``dv`` is a section along it and ``de`` the error vector.
    With two edges meeting at a corner ``q`` within two sections: travelling
    with the raised side on the left, the incoming edge ends at ``q`` (its
    crossings lie before ``q`` along its direction) and the outgoing edge
    starts there. While the centre is nearer the incoming ray than the outgoing
    one, the tracer keeps to the incoming edge, and when the corner lies within
    this section it goes to ``q`` and on along the outgoing edge; once nearer
    the outgoing ray it follows the outgoing edge. ``heading`` is
    the unit direction of the edge followed at the end of the move.
    """
    step = cfg.section_mm
    if not est.lines:  # Eq. 8 estimator: no fitted lines
        return step * est.tangent, cfg.error_gain * est.error_mm, est.tangent
    line = est.lines[0]
    if len(est.lines) == 2:
        a, b = est.lines
        q = line_intersection(a, b)
        if q is not None and float(np.hypot(*(q - centre_mm))) <= 2.0 * step:
            sa = float((a.point_mm - q) @ a.tangent)
            sb = float((b.point_mm - q) @ b.tangent)
            if sa * sb < 0:  # one edge ends at the corner, the other starts there
                incoming, outgoing = (a, b) if sa < 0 else (b, a)
                ahead = float((q - centre_mm) @ incoming.tangent)
                if _ray_distance(centre_mm, q, outgoing.tangent) < _ray_distance(
                    centre_mm, q, -incoming.tangent
                ):
                    line = outgoing  # already past the corner
                elif ahead < step:
                    dv = ahead * incoming.tangent + (step - ahead) * outgoing.tangent
                    dr = (q - centre_mm) + (step - ahead) * outgoing.tangent
                    return dv, cfg.error_gain * (dr - dv), outgoing.tangent
                else:
                    line = incoming
    de = -float(line.signed_distance_mm(centre_mm)) * line.normal
    return step * line.tangent, cfg.error_gain * de, line.tangent


def _sense(probe: TactileProbe, at: NDArray[np.float64], cfg: TracerConfig) -> EdgeEstimate:
    return estimate_edge(
        probe.scan(at, 0), probe.scan(at, 1), probe.element_offsets_mm, cfg.detector
    )


def find_edge(
    probe: TactileProbe,
    origin_mm: ArrayLike,
    *,
    direction: ArrayLike = (1.0, 0.0),
    max_distance_mm: float = 150.0,
    config: TracerConfig | None = None,
) -> NDArray[np.float64]:
    """Move from ``origin_mm`` along ``direction`` until an edge is under the array.

    Parameters
    ----------
    probe : TactileProbe
    origin_mm : (2,) float, mm
        Where to start (for example the specimen's centre).
    direction : (2,) float
        Search direction (normalised here).
    max_distance_mm : float
        Give up after this distance.
    config : TracerConfig, optional

    Returns
    -------
    (2,) float, mm
        A point on the edge: after the first sighting the array steps onto the
        edge by its error vector and senses again, up to
        :data:`FIND_EDGE_REFINEMENTS` times, until ``|de|`` is below
        :data:`FIND_EDGE_TOLERANCE_MM`.

    Raises
    ------
    InputError
        If no edge is found within ``max_distance_mm``.
    """
    cfg = TracerConfig() if config is None else config
    d = np.asarray(direction, dtype=np.float64)
    if d.shape != (2,) or not np.any(d):
        raise InputError(f"direction must be a non-zero 2-vector, got {direction!r}")
    d = d / np.hypot(*d)
    origin = np.asarray(origin_mm, dtype=np.float64)
    p = origin.copy()
    stride = 2.0 * cfg.section_mm  # the scans reach +-3 mm around each point
    for _ in range(int(np.ceil(max_distance_mm / stride)) + 1):
        est = _sense(probe, p, cfg)
        if est.found:
            # The first sighting may be an edge at the array's rim, fitted from a
            # few crossings: step onto it and look again until it is centred.
            for _ in range(FIND_EDGE_REFINEMENTS):
                if float(np.hypot(*est.error_mm)) < FIND_EDGE_TOLERANCE_MM:
                    break
                p = p + est.error_mm
                nxt = _sense(probe, p, cfg)
                if not nxt.found:
                    break
                est = nxt
            return np.asarray(p + est.error_mm, dtype=np.float64)
        p = p + stride * d
    raise InputError(
        f"no edge found within {max_distance_mm:g} mm of {tuple(np.round(origin, 3).tolist())}"
    )


def trace_edge(
    probe: TactileProbe,
    start_mm: ArrayLike,
    config: TracerConfig | None = None,
    *,
    progress: Callable[[int], None] | None = None,
) -> Trace:
    """Trace an edge from ``start_mm`` until the loop closes.

    Parameters
    ----------
    probe : TactileProbe
    start_mm : (2,) float, mm
        A point with the edge under the array (see :func:`find_edge`).
    config : TracerConfig, optional
    progress : callable, optional
        Called with the section number after each section.

    Returns
    -------
    Trace

    References
    ----------
    Paper 000, Section IV (Eq. 7) and Section VI.3.
    """
    cfg = TracerConfig() if config is None else config
    start = np.asarray(start_mm, dtype=np.float64)
    if start.shape != (2,) or not np.all(np.isfinite(start)):
        raise InputError(f"start_mm must be two finite numbers, got {start_mm!r}")
    log = _TraceLog(points=[start.copy()])
    p = start.copy()
    last_dir: NDArray[np.float64] | None = None
    travelled, misses = 0.0, 0
    stop = "max_sections"
    for k in range(int(cfg.max_sections)):
        est = _sense(probe, p, cfg)
        if est.found:
            misses = 0
            dv, de, last_dir = plan_move(est, p, cfg)
        else:
            misses += 1
            if last_dir is None or misses > cfg.max_misses:
                stop = "lost"
                break
            dv, de = cfg.section_mm * last_dir, np.zeros(2)
        dr = dv + de
        p = p + dr
        travelled += float(np.hypot(*dr))
        log.record(p, dv, de, est)
        if progress is not None:
            progress(k + 1)
        if travelled >= cfg.min_loop_mm and _back_at_start(log.points, p, cfg):
            stop = "closed"
            break
    logger.info("trace stopped (%s) after %d sections", stop, len(log.moves))
    return log.to_trace(stop)


def _back_at_start(
    points: list[NDArray[np.float64]], p: NDArray[np.float64], cfg: TracerConfig
) -> bool:
    """Whether ``p`` is within the closing radius of the trace's first points."""
    head = np.asarray(points[: CLOSURE_HEAD_POINTS + 1])
    return bool(np.min(np.hypot(*(head - p).T)) <= cfg.close_radius_mm)


@dataclass
class _TraceLog:
    """What :func:`trace_edge` records section by section (kept apart from the controller)."""

    points: list[NDArray[np.float64]]
    moves: list[NDArray[np.float64]] = field(default_factory=list)
    dvs: list[NDArray[np.float64]] = field(default_factory=list)
    des: list[NDArray[np.float64]] = field(default_factory=list)
    normals: list[Any] = field(default_factory=list)
    crossings: list[int] = field(default_factory=list)

    def record(
        self,
        p: NDArray[np.float64],
        dv: NDArray[np.float64],
        de: NDArray[np.float64],
        est: EdgeEstimate,
    ) -> None:
        """Append one section: the new position, its two move parts and the estimate."""
        self.points.append(p.copy())
        self.moves.append(dv + de)
        self.dvs.append(dv)
        self.des.append(de)
        self.normals.append(est.normal)
        self.crossings.append(int(est.crossings_mm.shape[0]))

    def to_trace(self, stop: str) -> Trace:
        """The recorded sections as a :class:`Trace` that stopped for ``stop``."""

        def stack(v: list[Any]) -> NDArray[np.float64]:
            return np.asarray(v, dtype=np.float64).reshape(-1, 2)

        return Trace(
            points_mm=stack(self.points),
            moves_mm=stack(self.moves),
            dv_mm=stack(self.dvs),
            de_mm=stack(self.des),
            normals=stack(self.normals),
            n_crossings=np.asarray(self.crossings, dtype=np.int64),
            closed=stop == "closed",
            stop_reason=stop,
        )
