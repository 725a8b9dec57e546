"""How an experiment's trials are seen: fault models and frame rates, checked once."""

from __future__ import annotations

from collections.abc import Sequence

from taxelkit.errors import InputError
from taxelkit.sensors.faults import FAULT_PRESETS

__all__ = ["check_views"]


def check_views(
    imperfections: Sequence[str], rates_hz: Sequence[float] = (20.0,)
) -> tuple[tuple[str, ...], tuple[float, ...]]:
    """The fault models (``"none"`` first, no repeats) and frame rates (no repeats) to run.

    Parameters
    ----------
    imperfections : sequence of str
        Names of :data:`~taxelkit.sensors.faults.FAULT_PRESETS`.
    rates_hz : sequence of float
        Frame rates, Hz, each in 1-1000.

    Returns
    -------
    imperfections : tuple of str
        ``"none"`` (the frames as the array gives them) and the others, in order.
    rates : tuple of float

    Raises
    ------
    InputError
        An unknown fault model, no rate, or a rate outside 1-1000 Hz.
    """
    for name in imperfections:
        if name not in FAULT_PRESETS:
            raise InputError(f"unknown imperfection {name!r}; known: {', '.join(FAULT_PRESETS)}")
    imps = ("none", *dict.fromkeys(str(f) for f in imperfections if f != "none"))
    rates = tuple(dict.fromkeys(float(r) for r in rates_hz))
    if not rates or any(not 1.0 <= r <= 1000.0 for r in rates):
        raise InputError(f"rates_hz must lie in 1..1000 Hz, got {list(rates_hz)!r}")
    return imps, rates
