"""The ``slip-heldout`` experiment: the slip experiment on motions no threshold was set on.

The thresholds of :class:`~taxelkit.smart.slip.SlipConfig` were set while
looking at trials of the ``slip`` experiment's seeds 777, 3, 0 and 5 (each
option's docstring says which). The same experiment on ``seed +
HELD_OUT_OFFSET`` (seed 11 for the committed seed 0) draws other motions,
noise and imperfections; nothing else differs (engines, kinds, rates,
imperfections and scoring are the ``slip`` experiment's).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from taxelkit.experiments.robustness_heldout import HELD_OUT_OFFSET, HeldOut
from taxelkit.experiments.slip import IMPERFECTIONS, run_slip
from taxelkit.experiments.slip_result import RATES_HZ

__all__ = ["run_slip_heldout"]


def run_slip_heldout(
    *,
    seed: int = 0,
    n_trials: int = 30,
    mujoco_trials: int | None = None,
    engines: Sequence[str] | None = None,
    imperfections: Sequence[str] = IMPERFECTIONS,
    rates_hz: Sequence[float] = RATES_HZ,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> HeldOut:
    """Run :func:`~taxelkit.experiments.slip.run_slip` on ``seed + HELD_OUT_OFFSET``.

    Parameters
    ----------
    seed : int
        The seed the thresholds were set on.
    n_trials, mujoco_trials, engines, imperfections, rates_hz, workers, progress
        As :func:`~taxelkit.experiments.slip.run_slip`.

    Returns
    -------
    HeldOut
        ``to_json()``: the ``slip`` document marked ``slip-heldout``, with
        ``tuned_on_seed`` and ``held_out_seed``.
    """
    result = run_slip(
        seed=int(seed) + HELD_OUT_OFFSET,
        n_trials=n_trials,
        mujoco_trials=mujoco_trials,
        engines=engines,
        imperfections=imperfections,
        rates_hz=rates_hz,
        workers=workers,
        progress=progress,
    )
    return HeldOut(result, int(seed), "slip-heldout")
