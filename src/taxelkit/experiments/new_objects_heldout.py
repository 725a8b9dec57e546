"""The ``new-objects-heldout`` experiment: new objects on trials no rule was set on.

The rules that decide the learnt objects (the face-shape limits, the
superset rule of :class:`~taxelkit.smart.object_table.ObjectTable`) were
set while looking at ``new-objects`` and ``robustness`` trials of seeds 0
and 3. The same experiment on ``seed + HELD_OUT_OFFSET`` (seed 11 for the
committed seed 0) draws other rolls, other check rolls for the learnt rows
(so the rows may differ: :mod:`taxelkit.learn.check` adds what its rolls
saw) and other explorations. Nothing else differs.
"""

from __future__ import annotations

from collections.abc import Callable

from taxelkit.experiments.new_objects import EXPLORE_HANDLINGS, run_new_objects
from taxelkit.experiments.robustness_heldout import HELD_OUT_OFFSET, HeldOut

__all__ = ["run_new_objects_heldout"]


def run_new_objects_heldout(
    *,
    seed: int = 0,
    n_trials: int = 100,
    n_outside: int = 100,
    handlings: int = EXPLORE_HANDLINGS,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> HeldOut:
    """Run :func:`~taxelkit.experiments.new_objects.run_new_objects` on ``seed + HELD_OUT_OFFSET``.

    Parameters
    ----------
    seed : int
        The seed the rules were set on.
    n_trials, n_outside, handlings, workers, progress
        As :func:`~taxelkit.experiments.new_objects.run_new_objects`.

    Returns
    -------
    HeldOut
        ``to_json()``: the ``new-objects`` document marked ``new-objects-heldout``
        with ``tuned_on_seed`` and ``held_out_seed``.
    """
    result = run_new_objects(
        seed=int(seed) + HELD_OUT_OFFSET,
        n_trials=n_trials,
        n_outside=n_outside,
        handlings=handlings,
        workers=workers,
        progress=progress,
    )
    return HeldOut(result, int(seed), "new-objects-heldout")
