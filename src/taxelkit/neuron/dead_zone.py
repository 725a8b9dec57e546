"""A dead zone for Eq. 9 set from the noise the sensor measured (taxelkit's extension).

Paper 000 leaves the dead zone ``epsilon`` of the ternary ``Phi`` (Eq. 9) as
"an appropriate threshold"; :data:`~taxelkit.tracing.edge_estimate.DEFAULT_EPSILON`
fixes it at 10 um, about 7 times the read-out noise of a clean plate. On a
rough plate the membrane potential ``u`` of a neuron that crosses no edge
wanders by the roughness itself and a fixed 10 um fires on every bump; on a
tilted plate every neuron sees a constant ``u`` (the slope times the distance
one window spans) and fires everywhere.

The adaptive dead zone reads both from the potentials of the scans at one
point, which contain mostly plate and only a few samples of edge:

* **baseline** ``b`` per scan: the median of ``u`` over every neuron and
  every sample with a full synaptic window (a tilt's constant offset; the
  first ``n`` samples sum fewer differences, so a slope gives them
  ``b min(t, n) / n``, and that ramp is what is removed). It is removed only when
  ``|b|`` exceeds both :data:`BASELINE_MIN_SIGMAS` noise levels and
  :data:`BASELINE_MIN_FLOOR_FRACTION` of the floor, so that a clean scan keeps
  its potentials bit for bit (its median is a rounding error);
* **noise level** ``sigma``: the median absolute deviation from the baseline,
  pooled over the scans, times :data:`MAD_TO_SIGMA` (the standard deviation
  of a Gaussian). The edge samples move the median only a little: when
  every element of a stroke crosses a step (16 % of the samples) the
  estimate is 1.24 times the noise, erring towards fewer spurious pulses;
* **dead zone** ``epsilon = max(epsilon_floor, noise_factor * sigma)``: never
  below the faithful 10 um (so clean specimens give the faithful outputs) and
  :data:`DEFAULT_NOISE_FACTOR` noise levels above the baseline otherwise.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.neuron.mechanoreceptor import NeuronParams, membrane_potential, window_samples
from taxelkit.neuron.quantisers import ternary

__all__ = [
    "BASELINE_MIN_FLOOR_FRACTION",
    "BASELINE_MIN_SIGMAS",
    "DEFAULT_NOISE_FACTOR",
    "MAD_TO_SIGMA",
    "DeadZone",
    "adaptive_direction_outputs",
    "robust_noise_level",
]

#: Ratio of the standard deviation to the median absolute deviation of a
#: Gaussian, ``1 / Phi^-1(3/4)``.
MAD_TO_SIGMA = 1.482602218505602
#: Dead zone in noise levels. A neuron's potential is a window sum and is
#: correlated over about one window (5 samples at the defaults), so a 6 mm
#: stroke of 36 neurons holds about 220 independent draws per scan; at 4
#: sigma a Gaussian exceeds the dead zone with probability 6.3e-5 each, about
#: one spurious pulse per 70 points traced.
DEFAULT_NOISE_FACTOR = 4.0
#: A scan's median potential is removed as its baseline only beyond this many
#: noise levels (a smaller offset is within the spread of the noise).
BASELINE_MIN_SIGMAS = 0.5
#: ... and beyond this fraction of the dead zone's floor (1 um of the faithful
#: 10 um: the read-out resolution of the optical sensor, below which a
#: median is not a measured offset).
BASELINE_MIN_FLOOR_FRACTION = 0.1


@dataclass(frozen=True)
class DeadZone:
    """What the adaptive dead zone measured at one point.

    Attributes
    ----------
    epsilon : float
        Dead zone applied, same scale as ``u`` (mm with ``a = 1/mm``).
    noise_level : float
        Robust standard deviation of ``u`` about the baselines, ``sigma``.
    baselines : tuple of float
        Offset removed from each scan's potentials (0 where not removed).
    """

    epsilon: float
    noise_level: float
    baselines: tuple[float, ...]


def robust_noise_level(deviations: ArrayLike) -> float:
    """``MAD_TO_SIGMA * median(|d|)``: the noise level of deviations from a baseline.

    Parameters
    ----------
    deviations : (...) float
        Potentials minus their baseline.

    Returns
    -------
    float
        0 for an empty input.

    Examples
    --------
    >>> d = np.random.default_rng(0).normal(0.0, 2.0, 100_000)
    >>> round(robust_noise_level(d), 1)
    2.0
    """
    d = np.abs(np.asarray(deviations, dtype=np.float64)).ravel()
    if d.size == 0:
        return 0.0
    return MAD_TO_SIGMA * float(np.median(d))


def adaptive_direction_outputs(
    scans_mm: Sequence[ArrayLike],
    dt_s: float,
    *,
    epsilon_floor: float,
    noise_factor: float = DEFAULT_NOISE_FACTOR,
    params: NeuronParams | None = None,
) -> tuple[list[NDArray[np.int8]], DeadZone]:
    """Signed neuron outputs of several scans with one dead zone set from their noise.

    Parameters
    ----------
    scans_mm : sequence of (T, rows, cols) float, mm
        Displacement frames of the scans at one point (the X and Y strokes).
    dt_s : float
        Sample interval, s.
    epsilon_floor : float
        Smallest dead zone, same scale as ``u`` (the faithful fixed value).
    noise_factor : float
        Dead zone in robust noise levels.
    params : NeuronParams, optional
        ``threshold_h`` is ignored (``h = 0``).

    Returns
    -------
    outputs : list of (T, rows, cols) int8 in {-1, 0, +1}
        ``Phi(u - b)`` of each scan, Eq. 9 with the measured dead zone.
    dead_zone : DeadZone

    Raises
    ------
    InputError
        If no scan is given or a parameter is negative.

    References
    ----------
    Paper 000, Eq. 9 (``epsilon`` "an appropriate threshold").
    """
    if len(scans_mm) == 0:
        raise InputError("scans_mm must hold at least one scan, got none")
    floor = check_positive("epsilon_floor", epsilon_floor, allow_zero=True)
    factor = check_positive("noise_factor", noise_factor, allow_zero=True)
    p = NeuronParams() if params is None else params
    us: list[Any] = [membrane_potential(s, dt_s, p, signed=True) for s in scans_mm]
    n = window_samples(p.tau_s, dt_s)
    # share of a constant slope in each sample's (partial) window: min(t, n) / n
    ramps = [np.minimum(np.arange(u.shape[0]), n)[:, None, None] / n for u in us]
    medians = [float(np.median(u[n:] if u.shape[0] > n else u)) for u in us]
    centred = [(u - m * r).ravel() for u, m, r in zip(us, medians, ramps, strict=True)]
    sigma = robust_noise_level(np.concatenate(centred))
    least = max(BASELINE_MIN_SIGMAS * sigma, BASELINE_MIN_FLOOR_FRACTION * floor)
    baselines = tuple(m if abs(m) > least else 0.0 for m in medians)
    eps = max(floor, factor * sigma)
    outputs = [
        ternary(u - b * r if b else u, eps) for u, b, r in zip(us, baselines, ramps, strict=True)
    ]
    return outputs, DeadZone(eps, sigma, baselines)
