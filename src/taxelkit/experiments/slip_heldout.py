"""The ``slip-heldout`` experiment: the slip experiment on motions no threshold was set on.

The thresholds of :class:`~taxelkit.smart.slip.SlipConfig` were set while
looking at trials of the ``slip`` experiment's seeds 777, 3, 0 and 5 (each
option's docstring says which). The same experiment on ``seed +
HELD_OUT_OFFSET`` (seed 11 for the committed seed 0) draws other motions,
noise and imperfections; nothing else differs (engines, kinds, rates,
imperfections and scoring are the ``slip`` experiment's).
"""

from __future__ import annotations

from typing import Any

from taxelkit.experiments.robustness_heldout import HELD_OUT_OFFSET, HeldOut
from taxelkit.experiments.slip import run_slip

__all__ = ["run_slip_heldout"]


def run_slip_heldout(*, seed: int = 0, **options: Any) -> HeldOut:
    """Run :func:`~taxelkit.experiments.slip.run_slip` on ``seed + HELD_OUT_OFFSET``.

    Parameters
    ----------
    seed : int
        The seed the thresholds were set on.
    **options
        ``n_trials`` (default 30), ``mujoco_trials``, ``engines``,
        ``imperfections``, ``rates_hz``, ``workers``, ``progress``: as
        :func:`~taxelkit.experiments.slip.run_slip`.

    Returns
    -------
    HeldOut
        ``to_json()``: the ``slip`` document marked ``slip-heldout``, with
        ``tuned_on_seed`` and ``held_out_seed``.
    """
    result = run_slip(seed=int(seed) + HELD_OUT_OFFSET, **options)
    return HeldOut(result, int(seed), "slip-heldout")
