"""Threshold functions of the neuron model: the ramp (Eq. 6) and the ternary Phi (Eq. 9)."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import check_positive

__all__ = ["ramp", "ternary"]


def ramp(q: ArrayLike) -> NDArray[np.float64]:
    """Threshold function phi of paper 000, Eq. 6: ``q`` where ``q >= 0``, else 0.

    Parameters
    ----------
    q : (...) float
        Membrane potential minus threshold, ``u - h``.

    Returns
    -------
    (...) float
        Pulse density (Eq. 5).

    References
    ----------
    Paper 000, Section III, Eq. 5-6.
    """
    out: NDArray[np.float64] = np.maximum(np.asarray(q, dtype=np.float64), 0.0)
    return out


def ternary(q: ArrayLike, epsilon: float = 0.0) -> NDArray[np.int8]:
    """Three-valued quantiser Phi of paper 000, Eq. 9.

    Parameters
    ----------
    q : (...) float
        Values to quantise.
    epsilon : float
        Dead-zone half-width (>= 0): ``|q| <= epsilon`` maps to 0.

    Returns
    -------
    (...) int8
        +1 where ``q > epsilon``, -1 where ``q < -epsilon``, 0 elsewhere.

    References
    ----------
    Paper 000, Section IV, Eq. 9; also used by the Associatron (Eq. 12).

    Examples
    --------
    >>> ternary([-2.0, -0.5, 0.0, 0.5, 2.0], epsilon=1.0).tolist()
    [-1, 0, 0, 0, 1]
    """
    eps = check_positive("epsilon", epsilon, allow_zero=True)
    a: Any = np.asarray(q)
    out = np.zeros(a.shape, dtype=np.int8)
    out[a > eps] = 1
    out[a < -eps] = -1
    return out
