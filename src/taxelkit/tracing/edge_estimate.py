"""Edge direction (Eq. 8) and error vector (Eq. 7) from the two scans at a point.

At each point the robot scans along x and along y (paper 000, Fig. 4). The
signed neuron output of every element (Eq. 9 with ``h = 0``) is +1 while the
element climbs onto the step and -1 while it comes down.

Edge direction, faithful (``estimator="eq8"``)
    Eq. 8 sums the outputs of the X scan and of the Y scan over time and
    cells: ``S_x = sum z_x V dt``, ``S_y = sum z_y V dt`` (mm). Read literally
    (see SEED-NOTES) ``(S_x, S_y)`` points across the step, towards the raised
    side: it is the edge *normal*. The printed denominator
    ``sqrt(sum (Z_x^2 + Z_y^2))`` (with ``Z`` the per-cell time sums) is not
    the norm of ``(S_x, S_y)``; we keep it for :attr:`EdgeEstimate.dv_eq8`
    and use the unit vector ``(S_x, S_y) / |(S_x, S_y)|`` as the normal. The
    edge direction is the normal turned by -90 deg, so that the raised side is
    on the left: a raised figure is traced counter-clockwise.

Edge direction, improved (``estimator="crossings"``)
    Each element that fires during a scan crossed the edge; the centroid of its
    firing samples, corrected for the lag of the square synaptic window
    (``(n - 1) / 2`` samples), locates the crossing point along the stroke.
    Up to two straight lines are fitted through the crossing points of both
    scans (:func:`~taxelkit.tracing.line_fit.fit_edge_lines`: two lines near a
    corner), each oriented towards the raised side by the signs of its
    crossings. The line nearest the array centre is the primary edge; the
    tracer uses both to turn corners.

Dead zone (Eq. 9)
    ``dead_zone="fixed"`` (the paper's reading) uses ``epsilon`` as given.
    ``dead_zone="adaptive"`` sets it at each point from the noise of that
    point's two scans (:mod:`taxelkit.neuron.dead_zone`): never below
    ``epsilon``, ``noise_factor`` robust noise levels above each scan's
    baseline otherwise. On a clean plate both give the same outputs.

Edge test
    A point has an edge when at least ``min_crossings`` crossings were
    located and, for the ``crossings`` estimator, a line fits at least that
    many of them and the best-supported line at least ``min_edge_crossings``
    (a straight edge across the 6 x 6 block is crossed by at least a row or
    a column of elements; a few isolated pulses are not an edge). With
    ``min_vote_agreement > 0`` a line is kept only when that fraction of its
    crossings agree on which side is raised: a real step is climbed on one
    side only, a bump of a rough plate is climbed and left at the same place.
    These two tests apply only where the measured noise raised the adaptive
    dead zone above ``epsilon`` (:attr:`EdgeEstimate.noisy`): on a clean plate
    the adaptive detector gives the fixed one's estimates, sharp corners
    (seen by few elements) included.

Error vector ``de`` (Section IV, Ishikawa's active sensing)
    The perpendicular from the commanded array centre to the primary line (for
    ``eq8``: to the line with the Eq. 8 direction through the centroid of the
    crossings, weighted by a Gaussian of width ``fit_radius_mm`` around the
    centre). Both are measured from the sensor's own outputs.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.motion.probe import Scan
from taxelkit.neuron.dead_zone import DEFAULT_NOISE_FACTOR, DeadZone, adaptive_direction_outputs
from taxelkit.neuron.mechanoreceptor import NeuronParams, direction_output, window_samples
from taxelkit.tracing.line_fit import EdgeLine, fit_edge_lines, vote_agreement

__all__ = [
    "DEAD_ZONES",
    "DEFAULT_EPSILON",
    "ESTIMATORS",
    "ROBUST_MIN_EDGE_CROSSINGS",
    "ROBUST_MIN_VOTE_AGREEMENT",
    "EdgeDetectorConfig",
    "EdgeEstimate",
    "crossing_points",
    "estimate_edge",
]

#: Dead zone of the ternary output, same scale as ``u`` (with ``a = 1/mm``, a
#: displacement change in mm within ``tau``): 10 um, about 7 times the noise
#: of a difference of two 1 um-rms readings and a fifth of the smallest 50 um
#: step of the paper.
DEFAULT_EPSILON = 0.01
#: Names of the edge-direction estimators.
ESTIMATORS = ("eq8", "crossings")
#: Crossings the best line needs where the plate is noisy: one row or column
#: of the 6 x 6 active block of paper 000 (isolated pulses that survive the
#: dead zone come in ones and twos; along traces of the five specimens, clean
#: or rough, the best line had 6 or more).
ROBUST_MIN_EDGE_CROSSINGS = 6
#: Fraction of a line's crossings that must agree on the raised side where the
#: plate is noisy (a bump is climbed and left at the same place: about half
#: agree; along rough traces of the five specimens at least 0.7 did on all but
#: a few second lines at star corners).
ROBUST_MIN_VOTE_AGREEMENT = 0.7
#: Names of the dead-zone modes: the paper's fixed ``epsilon`` and taxelkit's
#: noise-adaptive one.
DEAD_ZONES = ("fixed", "adaptive")


def _default_neuron() -> NeuronParams:
    # tau = 0.1 s at 10 mm/s spans 1 mm: a feeler's whole passage over a step.
    return NeuronParams(tau_s=0.1)


@dataclass(frozen=True)
class EdgeDetectorConfig:
    """How edges are read from the scans.

    Parameters
    ----------
    estimator : {"eq8", "crossings"}
        Edge-direction estimator (see module docs). ``"eq8"`` is the paper's.
    epsilon : float
        Dead zone of the ternary neuron output (Eq. 9).
    neuron : NeuronParams
        Mechanoreceptive unit (``threshold_h`` is ignored: ``h = 0``).
    fit_radius_mm : float
        Width of the Gaussian weight of crossing points around the array
        centre, mm.
    min_crossings : int
        Fewer crossing points than this means "no edge here".
    dead_zone : {"fixed", "adaptive"}
        ``"fixed"`` is the paper's Eq. 9 with ``epsilon``; ``"adaptive"``
        raises the dead zone above ``epsilon`` to ``noise_factor`` measured
        noise levels and removes a tilt's baseline (module docs).
    noise_factor : float
        Adaptive dead zone in robust noise levels of ``u``.
    min_vote_agreement : float
        Fraction in ``[0, 1]`` of a fitted line's crossings that must agree on
        the raised side where the plate is noisy (``crossings`` estimator); 0
        accepts every line.
    min_edge_crossings : int
        Crossings the best-supported line needs where the plate is noisy
        (``crossings`` estimator); at most ``min_crossings`` (the default 3)
        adds no test.
    """

    estimator: Literal["eq8", "crossings"] = "crossings"
    epsilon: float = DEFAULT_EPSILON
    neuron: NeuronParams = field(default_factory=_default_neuron)
    fit_radius_mm: float = 4.5
    min_crossings: int = 3
    dead_zone: Literal["fixed", "adaptive"] = "adaptive"
    noise_factor: float = DEFAULT_NOISE_FACTOR
    min_vote_agreement: float = ROBUST_MIN_VOTE_AGREEMENT
    min_edge_crossings: int = ROBUST_MIN_EDGE_CROSSINGS

    def __post_init__(self) -> None:
        if self.estimator not in ESTIMATORS:
            raise InputError(f"estimator must be one of {ESTIMATORS}, got {self.estimator!r}")
        if self.dead_zone not in DEAD_ZONES:
            raise InputError(f"dead_zone must be one of {DEAD_ZONES}, got {self.dead_zone!r}")
        check_positive("epsilon", self.epsilon, allow_zero=True)
        check_positive("noise_factor", self.noise_factor, allow_zero=True)
        if not 0.0 <= float(self.min_vote_agreement) <= 1.0:
            raise InputError(
                f"min_vote_agreement must be in [0, 1], got {self.min_vote_agreement!r}"
            )
        check_positive("fit_radius_mm", self.fit_radius_mm)
        if int(self.min_crossings) < 2:
            raise InputError(f"min_crossings must be >= 2, got {self.min_crossings!r}")


@dataclass(frozen=True, eq=False)
class EdgeEstimate:
    """The edge as seen from one point.

    Attributes
    ----------
    found : bool
        False when too few elements fired (no edge under the array).
    normal : (2,) float
        Unit normal towards the raised side (NaN when not found).
    tangent : (2,) float
        Unit edge direction with the raised side on the left.
    error_mm : (2,) float, mm
        Vector from the commanded centre to the nearest point of the edge.
    dv_eq8 : (2,) float
        Eq. 8 as printed (its normalisation, not a unit vector).
    crossings_mm : (K, 2) float, mm
        Located crossing points.
    rising : (K,) bool
        True where the element climbed onto the step.
    lines : tuple of EdgeLine
        The fitted lines (``crossings`` estimator), primary first.
    dead_zone : DeadZone or None
        What the adaptive dead zone measured (None with ``dead_zone="fixed"``).
    noisy : bool
        True where the measured noise raised the dead zone above ``epsilon``.
    """

    found: bool
    normal: NDArray[np.float64]
    tangent: NDArray[np.float64]
    error_mm: NDArray[np.float64]
    dv_eq8: NDArray[np.float64]
    crossings_mm: NDArray[np.float64]
    rising: NDArray[np.bool_]
    lines: tuple[EdgeLine, ...] = ()
    dead_zone: DeadZone | None = None
    noisy: bool = False


def crossing_points(
    scan: Scan, z: NDArray[Any], element_offsets_mm: NDArray[np.float64], lag_samples: float
) -> tuple[NDArray[np.float64], NDArray[np.bool_]]:
    """Where each firing element crossed the edge during one scan.

    Parameters
    ----------
    scan : Scan
    z : (T, rows, cols) int8
        Signed neuron output of the scan.
    element_offsets_mm : (rows, cols, 2) float, mm
        Element centres relative to the array centre.
    lag_samples : float
        Delay of the synaptic window's centroid, samples.

    Returns
    -------
    points_mm : (K, 2) float, mm
        One point per (element, sign) that fired.
    rising : (K,) bool
    """
    lag_mm = lag_samples * scan.speed_mm_s * scan.dt_s
    pts, rising = [], []
    for sign in (1, -1):  # two passes: climbing and descending elements
        mask = z == sign
        count = mask.sum(axis=0)
        fired = count > 0
        if not np.any(fired):
            continue
        along = (mask * scan.offsets_mm[:, None, None]).sum(axis=0)[fired] / count[fired]
        p = scan.centre_mm + element_offsets_mm[fired]
        p[:, scan.axis] += along - lag_mm
        pts.append(p)
        rising.append(np.full(p.shape[0], sign > 0))
    if not pts:
        return np.zeros((0, 2)), np.zeros(0, bool)
    return np.concatenate(pts), np.concatenate(rising)


def _unit(v: NDArray[np.float64]) -> NDArray[np.float64]:
    n = float(np.hypot(v[0], v[1]))
    return v / n if n > 0 else np.full(2, np.nan)


def estimate_edge(
    scan_x: Scan,
    scan_y: Scan,
    element_offsets_mm: NDArray[np.float64],
    config: EdgeDetectorConfig | None = None,
) -> EdgeEstimate:
    """Edge normal, direction and error vector from an X scan and a Y scan.

    Parameters
    ----------
    scan_x, scan_y : Scan
        Strokes along x and y centred on the same commanded point.
    element_offsets_mm : (rows, cols, 2) float, mm
        Element centres relative to the array centre.
    config : EdgeDetectorConfig, optional

    Returns
    -------
    EdgeEstimate

    References
    ----------
    Paper 000, Eq. 7-9 and Fig. 3-4; SEED-NOTES on reading Eq. 8.
    """
    cfg = EdgeDetectorConfig() if config is None else config
    if scan_x.axis != 0 or scan_y.axis != 1:
        raise InputError("scan_x must be along x (axis 0) and scan_y along y (axis 1)")
    if not np.allclose(scan_x.centre_mm, scan_y.centre_mm):
        raise InputError("scan_x and scan_y must share their centre")
    zone: DeadZone | None = None
    if cfg.dead_zone == "adaptive":
        if scan_x.dt_s != scan_y.dt_s:
            raise InputError("an adaptive dead zone needs both scans at the same dt_s")
        (zx, zy), zone = adaptive_direction_outputs(
            (scan_x.frames_mm, scan_y.frames_mm),
            scan_x.dt_s,
            epsilon_floor=cfg.epsilon,
            noise_factor=cfg.noise_factor,
            params=cfg.neuron,
        )
    else:
        zx = direction_output(scan_x.frames_mm, scan_x.dt_s, epsilon=cfg.epsilon, params=cfg.neuron)
        zy = direction_output(scan_y.frames_mm, scan_y.dt_s, epsilon=cfg.epsilon, params=cfg.neuron)
    # Eq. 8: per-cell time sums Z (mm), then sums over cells.
    cell_x = zx.sum(axis=0) * scan_x.speed_mm_s * scan_x.dt_s
    cell_y = zy.sum(axis=0) * scan_y.speed_mm_s * scan_y.dt_s
    s = np.array([cell_x.sum(), cell_y.sum()], dtype=np.float64)
    denominator = float(np.sqrt(np.sum(cell_x**2 + cell_y**2)))
    dv_eq8 = s / denominator if denominator > 0 else np.zeros(2)

    lag = (window_samples(cfg.neuron.tau_s, scan_x.dt_s) - 1) / 2.0
    px, rx = crossing_points(scan_x, zx, element_offsets_mm, lag)
    py, ry = crossing_points(scan_y, zy, element_offsets_mm, lag)
    pts, rising = np.concatenate([px, py]), np.concatenate([rx, ry])
    axis = np.concatenate([np.zeros(px.shape[0], int), np.ones(py.shape[0], int)])
    nan2 = np.full(2, np.nan)
    noisy = zone is not None and zone.epsilon > cfg.epsilon
    missing = EdgeEstimate(False, nan2, nan2, np.zeros(2), dv_eq8, pts, rising, (), zone, noisy)
    if pts.shape[0] < cfg.min_crossings or not np.any(s):
        return missing

    centre = scan_x.centre_mm
    if cfg.estimator == "eq8":
        w = np.exp(-0.5 * np.sum((pts - centre) ** 2, axis=1) / cfg.fit_radius_mm**2)
        mean = (w / w.sum()) @ pts
        normal = _unit(s)
        error = float((mean - centre) @ normal) * normal
        tangent = np.array([normal[1], -normal[0]])
        return EdgeEstimate(True, normal, tangent, error, dv_eq8, pts, rising, (), zone, noisy)
    lines = fit_edge_lines(pts, rising, axis, min_inliers=cfg.min_crossings)
    if noisy and cfg.min_vote_agreement > 0.0:
        lines = tuple(
            ln for ln in lines if vote_agreement(ln, pts, rising, axis) >= cfg.min_vote_agreement
        )
    least = cfg.min_edge_crossings if noisy else cfg.min_crossings
    if not lines or max(int(ln.inliers.sum()) for ln in lines) < least:
        return missing
    lines = tuple(sorted(lines, key=lambda ln: abs(float(ln.signed_distance_mm(centre)))))
    primary = lines[0]
    error = -float(primary.signed_distance_mm(centre)) * primary.normal
    return EdgeEstimate(
        True, primary.normal, primary.tangent, error, dv_eq8, pts, rising, lines, zone, noisy
    )
