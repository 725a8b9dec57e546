"""The ``robustness-heldout`` experiment: the robustness sweep on motions nobody tuned to.

The Level 3 thresholds that the :mod:`~taxelkit.experiments.robustness`
matrix exercises hardest (the cone / truncated-cone pivot band, the pivot
hold, the hysteresis of the contact limits) were chosen while looking at the
trials of ``reproduce robustness --seed S`` (the committed ``S = 0``). The
same sweep on motions, noise and imperfections drawn from another seed,
``S + HELD_OUT_OFFSET``, measures what those choices are worth on trials
they were not chosen on. Nothing else differs: the engines, rates,
imperfections, objects and arrays are the main sweep's.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

from taxelkit.experiments.robustness import (
    OTHER_ARRAYS,
    RATES_HZ,
    run_robustness,
)

__all__ = [
    "HELD_OUT_OFFSET",
    "HeldOut",
    "HeldOutRobustness",
    "held_out_json",
    "run_robustness_heldout",
]

#: Offset of the held-out seed from the seed the thresholds were set on.
HELD_OUT_OFFSET = 11


def held_out_json(
    doc: dict[str, Any], seed: int, *, experiment: str = "robustness-heldout"
) -> dict[str, Any]:
    """An experiment's document marked as its held-out run for ``seed``.

    Parameters
    ----------
    doc : dict
        The experiment's JSON (for example :meth:`RobustnessResult.to_json`)
        from its run on ``seed + HELD_OUT_OFFSET``.
    seed : int
        The seed the thresholds were set on (the CLI's ``--seed``).
    experiment : str
        The held-out experiment's registry name.

    Returns
    -------
    dict
        ``doc`` with ``experiment`` set, and ``tuned_on_seed`` and ``held_out_seed``.
    """
    return {
        **doc,
        "experiment": experiment,
        "tuned_on_seed": int(seed),
        "held_out_seed": int(seed) + HELD_OUT_OFFSET,
    }


@dataclass(frozen=True, eq=False)
class HeldOut:
    """An experiment's result on the held-out seed.

    Attributes
    ----------
    result : ExperimentResult
        Anything with ``to_json()`` (the experiment's own result).
    seed : int
        The seed the thresholds were set on; the run used ``seed + HELD_OUT_OFFSET``.
    experiment : str
        The held-out experiment's registry name.
    """

    result: Any
    seed: int
    experiment: str = "robustness-heldout"

    def to_json(self) -> dict[str, Any]:
        """The experiment's document marked as held out (:func:`held_out_json`)."""
        return held_out_json(self.result.to_json(), self.seed, experiment=self.experiment)


#: The robustness sweep on the held-out seed (``result``: a RobustnessResult).
HeldOutRobustness = HeldOut


def run_robustness_heldout(
    *,
    seed: int = 0,
    n_trials: int = 50,
    engines: Sequence[str] | None = None,
    rates_hz: Sequence[float] = RATES_HZ,
    arrays: Sequence[tuple[int, float]] = OTHER_ARRAYS,
    array_trials: int | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> HeldOutRobustness:
    """Run :func:`~taxelkit.experiments.robustness.run_robustness` on ``seed + HELD_OUT_OFFSET``.

    Parameters
    ----------
    seed : int
        The seed the thresholds were set on.
    n_trials : int
        Randomised motions per cell (50 by default, as the main sweep, so that
        cells compare one to one).
    engines, rates_hz, arrays, array_trials, workers, scheduler, progress
        As :func:`~taxelkit.experiments.robustness.run_robustness`.

    Returns
    -------
    HeldOutRobustness
    """
    result = run_robustness(
        seed=int(seed) + HELD_OUT_OFFSET,
        n_trials=n_trials,
        engines=engines,
        rates_hz=rates_hz,
        arrays=arrays,
        array_trials=array_trials,
        workers=workers,
        scheduler=scheduler,
        progress=progress,
    )
    return HeldOut(result, int(seed))
