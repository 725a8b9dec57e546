"""The ``robustness-heldout`` experiment: the robustness sweep on motions nobody tuned to.

The Level 3 thresholds that the :mod:`~taxelkit.experiments.robustness`
matrix exercises hardest (the cone / truncated-cone pivot band, the pivot
hold, the hysteresis of the contact limits) were chosen while looking at the
trials of ``reproduce robustness --seed S`` (the committed ``S = 0``). The
same sweep on motions, noise and imperfections drawn from another seed,
``S + HELD_OUT_OFFSET``, measures what those choices are worth on trials
they were not chosen on. Nothing else differs: the engines, rates,
imperfections, objects and arrays are the main sweep's. One exception: the
limits of the pressed pivot ratio (``TactemeConfig.pivot_end_ratio`` and
``pivot_band`` with ``pivot_pressed_half``) were searched on the cone and
truncated-cone rolls of seeds 0 and 11 together, so this leg does not hold
them out.

The held-out motions are also seen at frame rates the matrix does not hold
(:data:`UNTUNED_RATES_HZ`), at which the matrix's thresholds were never
looked at (the rule for sparse frames, ``TactemeConfig.max_motion_gap_s``,
was set on seed 0's motions at 1 to 3 frames/s after this leg's first run
found wrong names there; seed 11's results at 2 and 3 frames/s prompted
its edge-angle part, and its MuJoCo tetrahedra at 2 frames/s
``TactemeConfig.edge_apart_pitches``, so those rates are not strictly held
out for these rules): the same simulation sampled at more rates (the matrix's rates come first, so
their frames, imperfections and outcomes are those of the sweep without the
extra rates). Their outcomes are kept apart from the matrix's
(:attr:`HeldOut.untuned`), so the held-out matrix compares cell for cell
with the tuned one.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

from taxelkit.errors import InputError
from taxelkit.experiments.robustness import (
    OTHER_ARRAYS,
    RATES_HZ,
    RobustnessResult,
    run_robustness,
)
from taxelkit.experiments.robustness_outcomes import MAIN_ARRAY

__all__ = [
    "HELD_OUT_OFFSET",
    "UNTUNED_RATES_HZ",
    "HeldOut",
    "HeldOutRobustness",
    "held_out_json",
    "run_robustness_heldout",
]

#: Offset of the held-out seed from the seed the thresholds were set on.
HELD_OUT_OFFSET = 11

#: Frame rates outside the matrix's (5, 20, 100 and 240 frames/s) at which the
#: held-out motions are also seen: common camera and array rates, from the
#: slowest the imperfection models allow (see the module's note on 1-3 frames/s).
UNTUNED_RATES_HZ: tuple[float, ...] = (1.0, 2.0, 3.0, 10.0, 30.0, 60.0, 120.0)


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
    untuned : RobustnessResult, optional
        The same motions at frame rates outside the matrix (``robustness-heldout``).
    """

    result: Any
    seed: int
    experiment: str = "robustness-heldout"
    untuned: RobustnessResult | None = None

    def to_json(self) -> dict[str, Any]:
        """The experiment's document marked as held out (:func:`held_out_json`).

        With :attr:`untuned`, its cells, summaries and totals under
        ``untuned_rates`` (keys ``rates_hz``, ``cells``, ``summary``,
        ``overall``, ``sliding``).
        """
        doc = held_out_json(self.result.to_json(), self.seed, experiment=self.experiment)
        if self.untuned is not None:
            extra = self.untuned.to_json()
            keys = ("rates_hz", "cells", "summary", "overall", "sliding")
            doc["untuned_rates"] = {k: extra[k] for k in keys}
        return doc


#: The robustness sweep on the held-out seed (``result``: a RobustnessResult).
HeldOutRobustness = HeldOut


def run_robustness_heldout(
    *,
    seed: int = 0,
    n_trials: int = 50,
    engines: Sequence[str] | None = None,
    rates_hz: Sequence[float] = RATES_HZ,
    untuned_rates_hz: Sequence[float] = UNTUNED_RATES_HZ,
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
    untuned_rates_hz : sequence of float
        Frame rates outside the matrix at which the same motions are also seen
        (empty: none); their outcomes go to :attr:`HeldOut.untuned`.

    Returns
    -------
    HeldOutRobustness

    Raises
    ------
    InputError
        For a rate in both ``rates_hz`` and ``untuned_rates_hz``.
    """
    matrix = tuple(float(r) for r in rates_hz)
    extra = tuple(float(r) for r in untuned_rates_hz)
    both = sorted(set(matrix) & set(extra))
    if both:
        raise InputError(f"rates {both} are both in the matrix and outside it")
    result = run_robustness(
        seed=int(seed) + HELD_OUT_OFFSET,
        n_trials=n_trials,
        engines=engines,
        rates_hz=(*matrix, *extra),  # the matrix's first: its outcomes do not change
        arrays=arrays,
        array_trials=array_trials,
        workers=workers,
        scheduler=scheduler,
        progress=progress,
    )
    if not extra:
        return HeldOut(result, int(seed))
    main, untuned = _split(result, matrix)
    return HeldOut(main, int(seed), untuned=untuned)


def _split(
    result: RobustnessResult, matrix: tuple[float, ...]
) -> tuple[RobustnessResult, RobustnessResult]:
    """The outcomes at the matrix's rates (and on other arrays), and those at the others."""
    keep = set(matrix)
    inside = tuple(o for o in result.outcomes if o.rate_hz in keep or o.array != MAIN_ARRAY)
    outside = tuple(o for o in result.outcomes if o.rate_hz not in keep and o.array == MAIN_ARRAY)
    rates = tuple(r for r in result.rates_hz if r not in keep)
    return (
        replace(result, outcomes=inside, rates_hz=matrix),
        replace(result, outcomes=outside, rates_hz=rates),
    )
