"""The lateral quadric's roots along vertical lines: the per-case kernels of a body of revolution.

:func:`~taxelkit.world.solids_revolution.revolution_bottom_mm` groups poses by
case (:data:`BOUNDED`, :data:`OPENS_UP`, :data:`OPENS_DOWN`) and form (simple
``(-B +- sqrt(disc)) / A`` or stable ``m / A, C / m``; see that module's
notes) and evaluates each group with one function of :data:`SIMPLE_COMBINE`,
:data:`STABLE_COMBINE` or :func:`upright_cylinder`. Each function reads the
group's function table evaluated on the grid (``slabs``, one row per
coefficient set, in the order below), writes into ``work`` and finishes the
bottom height in ``out`` (mm) with
:func:`~taxelkit.world.solids_grid.finish_interval`.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.world.solids_grid import finish_interval

__all__ = [
    "BOUNDED",
    "OPENS_DOWN",
    "OPENS_UP",
    "SIMPLE_COMBINE",
    "STABLE_COMBINE",
    "upright_cylinder",
]

#: Pose cases of a lateral quadric: the line meets it in an interval, in the
#: ray above the larger root (opening upwards), below the smaller (downwards).
BOUNDED, OPENS_UP, OPENS_DOWN = 0, 1, 2

# Rows of the stable function table: B, disc, c, g = d . w at t = 0, g**2 - C, caps.
_BN, _DISC, _CS, _G, _CROW, _CAP_LO, _CAP_HI = range(7)
# Rows of the simple table: B/A, disc/A**2, c/|A|, caps.
_S_BNA, _S_DISC, _S_CS, _S_CAP_LO, _S_CAP_HI = range(5)


def _stable_roots(slabs: NDArray[Any], work: Any, inv_a: NDArray[Any], clamp: bool) -> None:
    """Stable roots of the lateral quadric: work[1] = m / A, work[2] = C / m.

    A line that misses (negative discriminant) gives NaN unless ``clamp``.
    """
    w0, w1, w2 = work[0], work[1], work[2]
    np.multiply(slabs[_CS], slabs[_CS], out=w0)
    np.subtract(slabs[_DISC], w0, out=w0)
    if clamp:
        np.maximum(w0, 0.0, out=w0)
    np.sqrt(w0, out=w0)
    np.copysign(w0, slabs[_BN], out=w0)
    np.add(slabs[_BN], w0, out=w0)  # m
    np.multiply(w0, inv_a, out=w1)
    np.multiply(slabs[_G], slabs[_G], out=w2)
    np.subtract(w2, slabs[_CROW], out=w2)  # C
    np.divide(w2, w0, out=w2)


def _stable_bounded(slabs: NDArray[Any], work: Any, out: NDArray[Any], pv: NDArray[Any]) -> None:
    _stable_roots(slabs, work, pv[:, 0:1], clamp=False)
    lo, hi = work[0], work[1]
    np.minimum(work[1], work[2], out=lo)
    np.maximum(work[1], work[2], out=hi)
    np.maximum(lo, slabs[_CAP_LO], out=lo)
    np.minimum(hi, slabs[_CAP_HI], out=hi)
    np.fmin(lo, np.inf, out=lo)  # NaN (the line misses) -> +inf
    finish_interval(lo, hi, hi, out)


def _stable_opens_up(slabs: NDArray[Any], work: Any, out: NDArray[Any], pv: NDArray[Any]) -> None:
    _stable_roots(slabs, work, pv[:, 0:1], clamp=True)
    lo = work[0]
    np.maximum(work[1], work[2], out=lo)
    np.maximum(lo, slabs[_CAP_LO], out=lo)
    np.fmin(lo, np.inf, out=lo)
    finish_interval(lo, slabs[_CAP_HI], work[1], out)


def _stable_opens_down(slabs: NDArray[Any], work: Any, out: NDArray[Any], pv: NDArray[Any]) -> None:
    _stable_roots(slabs, work, pv[:, 0:1], clamp=True)
    hi = work[0]
    np.minimum(work[1], work[2], out=hi)
    np.minimum(hi, slabs[_CAP_HI], out=hi)
    np.fmax(hi, -np.inf, out=hi)  # NaN -> -inf: no interval
    finish_interval(slabs[_CAP_LO], hi, hi, out)


def _simple_sqrt(slabs: NDArray[Any], w: NDArray[Any], clamp: bool) -> None:
    """w = sqrt(disc) / |A|, NaN where the line misses unless ``clamp``."""
    np.multiply(slabs[_S_CS], slabs[_S_CS], out=w)
    np.subtract(slabs[_S_DISC], w, out=w)
    if clamp:
        np.maximum(w, 0.0, out=w)
    np.sqrt(w, out=w)


def _simple_bounded(slabs: NDArray[Any], work: Any, out: NDArray[Any], pv: NDArray[Any]) -> None:
    hi, lo = work[0], work[1]
    _simple_sqrt(slabs, hi, clamp=False)
    np.subtract(slabs[_S_BNA], hi, out=lo)
    np.add(slabs[_S_BNA], hi, out=hi)
    np.maximum(lo, slabs[_S_CAP_LO], out=lo)
    np.minimum(hi, slabs[_S_CAP_HI], out=hi)
    np.fmin(lo, np.inf, out=lo)  # NaN (the line misses) -> +inf
    finish_interval(lo, hi, hi, out)


def _simple_opens_up(slabs: NDArray[Any], work: Any, out: NDArray[Any], pv: NDArray[Any]) -> None:
    lo = work[0]
    _simple_sqrt(slabs, lo, clamp=True)
    np.add(slabs[_S_BNA], lo, out=lo)
    np.maximum(lo, slabs[_S_CAP_LO], out=lo)
    finish_interval(lo, slabs[_S_CAP_HI], work[1], out)


def _simple_opens_down(slabs: NDArray[Any], work: Any, out: NDArray[Any], pv: NDArray[Any]) -> None:
    hi = work[0]
    _simple_sqrt(slabs, hi, clamp=True)
    np.subtract(slabs[_S_BNA], hi, out=hi)
    np.minimum(hi, slabs[_S_CAP_HI], out=hi)
    finish_interval(slabs[_S_CAP_LO], hi, hi, out)


def upright_cylinder(slabs: NDArray[Any], work: Any, out: NDArray[Any], pv: NDArray[Any]) -> None:
    """Bottom cap inside the disc (row 0 = rho**2 - r**2 <= 0), +inf outside."""
    np.multiply(slabs[0], np.inf, out=work[0])
    np.fmax(slabs[1], work[0], out=out)


#: The stable form's function for each pose case.
STABLE_COMBINE = {
    BOUNDED: _stable_bounded,
    OPENS_UP: _stable_opens_up,
    OPENS_DOWN: _stable_opens_down,
}
#: The simple form's function for each pose case.
SIMPLE_COMBINE = {
    BOUNDED: _simple_bounded,
    OPENS_UP: _simple_opens_up,
    OPENS_DOWN: _simple_opens_down,
}
