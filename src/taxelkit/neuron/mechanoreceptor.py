"""Mechanoreceptive unit of paper 000 (Section III, Eq. 1-6 and the signed form of Eq. 9).

The model turns the displacement history of tactile elements into the pulse
density of a neuron:

* receptor output (Eq. 2): ``s_i = a |dU_i/dt|``; the signed form drops the
  absolute value so that rising and falling steps differ (Section IV);
* temporal summation (Eq. 3-4): convolution with the square synaptic weight
  ``w(t) = 1`` for ``0 <= t < tau``, i.e. ``u_i(t) = integral of s_i over the
  last tau seconds``;
* spatial summation (Eq. 1): ``u = sum_i w_i u_i`` over a square receptive
  field of ``k x k`` elements (``k = 1`` by default: one neuron per element);
* threshold (Eq. 5-6): ``z = phi(u - h)`` with the ramp ``phi``; for direction
  finding ``h = 0`` and the ternary ``Phi`` of Eq. 9 replaces ``phi``.

Discretisation: frames are sampled every ``dt_s``; ``dU/dt`` is the backward
difference (0 for the first frame); the integral over ``tau`` is the sum of the
last ``n = max(1, round(tau / dt))`` samples times ``dt``. For the signed
receptor this gives exactly ``u(t) = a (U(t) - U(t - n dt))``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import ndimage

from taxelkit.errors import InputError, check_positive
from taxelkit.neuron.quantisers import ramp, ternary

__all__ = [
    "DEFAULT_GAIN_A",
    "DEFAULT_TAU_S",
    "NeuronParams",
    "direction_output",
    "membrane_potential",
    "pulse_density",
    "receptor_output",
    "spatial_summation",
    "temporal_summation",
    "window_samples",
]

#: Coefficient ``a`` of Eq. 2, 1/mm: scales the displacement rate (mm/s) so
#: that ``u`` is dimensionless; 1/mm keeps ``u`` numerically equal to the
#: displacement change in mm over the window, which makes thresholds readable.
DEFAULT_GAIN_A = 1.0
#: Width ``tau`` of the square synaptic weight (Eq. 4), s. The paper gives no
#: value; 0.1 s spans the whole passage of a 1 mm feeler over a step at the
#: default scan speed of 10 mm/s, so each crossing yields one summed pulse.
DEFAULT_TAU_S = 0.1


@dataclass(frozen=True)
class NeuronParams:
    """Parameters of the mechanoreceptive unit.

    Parameters
    ----------
    gain_a : float
        Coefficient ``a`` of Eq. 2, 1/mm.
    tau_s : float
        Width of the square synaptic weight, Eq. 4, s.
    threshold_h : float
        Threshold ``h`` of Eq. 5 (dimensionless, same scale as ``u``).
    receptive_field : int
        Side ``k`` of the square group of elements summed by one neuron (Eq. 1),
        with unit weights; odd, >= 1.
    """

    gain_a: float = DEFAULT_GAIN_A
    tau_s: float = DEFAULT_TAU_S
    threshold_h: float = 0.0
    receptive_field: int = 1

    def __post_init__(self) -> None:
        check_positive("gain_a", self.gain_a)
        check_positive("tau_s", self.tau_s)
        check_positive("threshold_h", self.threshold_h, allow_zero=True)
        k = self.receptive_field
        if not isinstance(k, int | np.integer) or k < 1 or k % 2 == 0:
            raise InputError(f"receptive_field must be an odd integer >= 1, got {k!r}")


def _series(name: str, displacement_mm: ArrayLike) -> NDArray[np.float64]:
    u = np.asarray(displacement_mm, dtype=np.float64)
    if u.ndim < 1 or u.shape[0] < 1:
        raise InputError(f"{name} must have shape (T, ...) with T >= 1, got {u.shape}")
    if not np.all(np.isfinite(u)):
        raise InputError(f"{name} must be finite")
    return u


def window_samples(tau_s: float, dt_s: float) -> int:
    """Samples in the synaptic window: ``max(1, round(tau_s / dt_s))``."""
    return max(1, round(check_positive("tau_s", tau_s) / check_positive("dt_s", dt_s)))


def receptor_output(
    displacement_mm: ArrayLike, dt_s: float, *, gain_a: float = DEFAULT_GAIN_A, signed: bool = False
) -> NDArray[np.float64]:
    """Receptor output from the displacement rate, Eq. 2.

    Parameters
    ----------
    displacement_mm : (T, ...) float, mm
        Displacement ``U_i`` of every element, sampled every ``dt_s``.
    dt_s : float
        Sample interval, s.
    gain_a : float
        Coefficient ``a``, 1/mm.
    signed : bool
        Keep the sign of ``dU/dt`` (Section IV, for direction); default is the
        absolute value of Eq. 2.

    Returns
    -------
    (T, ...) float, 1/s
        ``a |dU/dt|`` (or ``a dU/dt``), backward difference, 0 at ``t = 0``.

    References
    ----------
    Paper 000, Eq. 2.
    """
    u = _series("displacement_mm", displacement_mm)
    dt = check_positive("dt_s", dt_s)
    rate = np.zeros_like(u)
    rate[1:] = np.diff(u, axis=0) / dt
    rate *= check_positive("gain_a", gain_a)
    return rate if signed else np.abs(rate)


def temporal_summation(receptor: ArrayLike, dt_s: float, tau_s: float) -> NDArray[np.float64]:
    """Convolution with the square synaptic weight of width ``tau_s``, Eq. 3-4.

    Parameters
    ----------
    receptor : (T, ...) float
        Receptor outputs ``s_i(t)``.
    dt_s, tau_s : float
        Sample interval and window width, s.

    Returns
    -------
    (T, ...) float
        ``dt * sum of the last n samples`` (fewer at the start), ``n =
        window_samples(tau_s, dt_s)``; one cumulative sum, no loop over time.

    Notes
    -----
    ``scipy.ndimage.correlate1d(s, np.ones(n), axis=0, mode="constant",
    origin=(n - 1) // 2)`` computes the same window sums (within 1e-16 on random
    inputs of unit scale) and more accurately (a difference of cumulative sums carries
    their rounding), but not bit for bit: with it, ``reproduce fig7`` reports
    other correlations in the fifth decimal (0.99998808 becomes 0.99998792)
    and other direction errors, so the published results would change.
    """
    s = _series("receptor", receptor)
    n = window_samples(tau_s, dt_s)
    c = np.cumsum(s, axis=0)
    out = c.copy()
    out[n:] -= c[:-n]
    out *= dt_s
    return out


def spatial_summation(potential: ArrayLike, receptive_field: int = 1) -> NDArray[np.float64]:
    """Sum over a ``k x k`` receptive field with unit weights, Eq. 1.

    Parameters
    ----------
    potential : (T, rows, cols) float
        Per-element potentials.
    receptive_field : int
        Odd side ``k``; ``1`` returns the input unchanged.

    Returns
    -------
    (T, rows, cols) float
        Neuron ``(i, j)`` sums the elements within ``k // 2`` of ``(i, j)``
        (elements outside the array contribute nothing):
        :func:`scipy.ndimage.correlate` with a ``k x k`` kernel of ones.
    """
    p = _series("potential", potential)
    k = int(receptive_field)
    if k < 1 or k % 2 == 0:
        raise InputError(f"receptive_field must be an odd integer >= 1, got {receptive_field!r}")
    if k == 1:
        return p
    if p.ndim != 3:
        raise InputError(f"potential must have shape (T, rows, cols), got {p.shape}")
    out: NDArray[np.float64] = ndimage.correlate(p, np.ones((1, k, k)), mode="constant")
    return out


def membrane_potential(
    displacement_mm: ArrayLike, dt_s: float, params: NeuronParams, *, signed: bool = False
) -> NDArray[np.float64]:
    """Membrane potential ``u`` of Eq. 3 for every neuron and sample.

    Parameters
    ----------
    displacement_mm : (T, rows, cols) float, mm
        Element displacements sampled every ``dt_s``.
    dt_s : float
        Sample interval, s.
    params : NeuronParams
    signed : bool
        Use the signed receptor (Section IV).

    Returns
    -------
    (T, rows, cols) float
    """
    s = receptor_output(displacement_mm, dt_s, gain_a=params.gain_a, signed=signed)
    return spatial_summation(temporal_summation(s, dt_s, params.tau_s), params.receptive_field)


def pulse_density(
    displacement_mm: ArrayLike, dt_s: float, params: NeuronParams | None = None
) -> NDArray[np.float64]:
    """Pulse density ``z = phi(u - h)`` of Eq. 5 (the faithful neuron, Eq. 1-6).

    Parameters
    ----------
    displacement_mm : (T, rows, cols) float, mm
    dt_s : float
        Sample interval, s.
    params : NeuronParams, optional

    Returns
    -------
    (T, rows, cols) float, >= 0
    """
    p = NeuronParams() if params is None else params
    return ramp(membrane_potential(displacement_mm, dt_s, p) - p.threshold_h)


def direction_output(
    displacement_mm: ArrayLike,
    dt_s: float,
    *,
    epsilon: float,
    params: NeuronParams | None = None,
) -> NDArray[np.int8]:
    """Signed neuron output for edge direction: ``Phi(u)`` with ``h = 0`` (Section IV).

    Parameters
    ----------
    displacement_mm : (T, rows, cols) float, mm
    dt_s : float
        Sample interval, s.
    epsilon : float
        Dead zone of the ternary Phi (Eq. 9), same scale as ``u``.
    params : NeuronParams, optional
        ``threshold_h`` is ignored (``h = 0``).

    Returns
    -------
    (T, rows, cols) int8 in {-1, 0, +1}
        +1 while an element is rising onto a step, -1 while falling off one.
    """
    p = NeuronParams() if params is None else params
    u: Any = membrane_potential(displacement_mm, dt_s, p, signed=True)
    return ternary(u, epsilon)
