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
from dataclasses import dataclass
from typing import Any

from taxelkit.experiments.new_objects import (
    EXPLORE_HANDLINGS,
    NewObjectsResult,
    run_new_objects,
)
from taxelkit.experiments.robustness_heldout import HELD_OUT_OFFSET, held_out_json

__all__ = ["HeldOutNewObjects", "run_new_objects_heldout"]


@dataclass(frozen=True, eq=False)
class HeldOutNewObjects:
    """``new-objects`` on the held-out seed.

    Attributes
    ----------
    result : NewObjectsResult
    seed : int
        The seed the rules were set on; the trials ran on ``seed + HELD_OUT_OFFSET``.
    """

    result: NewObjectsResult
    seed: int

    def to_json(self) -> dict[str, Any]:
        """The ``new-objects`` document, marked ``new-objects-heldout`` with both seeds."""
        return held_out_json(self.result.to_json(), self.seed, experiment="new-objects-heldout")


def run_new_objects_heldout(
    *,
    seed: int = 0,
    n_trials: int = 100,
    n_outside: int = 100,
    handlings: int = EXPLORE_HANDLINGS,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> HeldOutNewObjects:
    """Run :func:`~taxelkit.experiments.new_objects.run_new_objects` on ``seed + HELD_OUT_OFFSET``.

    Parameters
    ----------
    seed : int
        The seed the rules were set on.
    n_trials, n_outside, handlings, workers, progress
        As :func:`~taxelkit.experiments.new_objects.run_new_objects`.

    Returns
    -------
    HeldOutNewObjects
    """
    result = run_new_objects(
        seed=int(seed) + HELD_OUT_OFFSET,
        n_trials=n_trials,
        n_outside=n_outside,
        handlings=handlings,
        workers=workers,
        progress=progress,
    )
    return HeldOutNewObjects(result, int(seed))
