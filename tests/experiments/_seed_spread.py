"""Measure the seed-to-seed spread of the cheap experiments and write the tolerances.

Run from the repository root (about 30 s on a loaded 2-core machine)::

    .venv/bin/python -m tests.experiments._seed_spread

It runs each experiment of :data:`EXPERIMENTS` at the seeds
:data:`tests.experiments._truth.SPREAD_SEEDS`, and writes, per numeric leaf of
its JSON that moved over the seeds, the mean, the sample standard deviation,
the range and the tolerance ``SIGMAS * std`` to
``tests/experiments/seed_spread.json`` (leaves that did not move are only
counted: they must stay as committed), which
``test_figure_truth.py`` reads. Rerun it when an experiment's JSON gains or
loses figures, and commit the file with the regenerated results.
"""

from __future__ import annotations

import json
import statistics
import sys
import time
from typing import Any

from taxelkit.experiments.registry import get_experiment
from tests.experiments._truth import SIGMAS, SPREAD_FILE, SPREAD_SEEDS, flatten, is_number

#: The experiments cheap enough to re-run in the default test suite.
EXPERIMENTS = ("fig7", "fig8", "fig9", "cylinder")


def spread(name: str) -> dict[str, Any]:
    """Run ``name`` at every seed and summarise each numeric leaf."""
    runs, seconds = [], []
    for seed in SPREAD_SEEDS:
        t0 = time.perf_counter()
        runs.append(flatten(get_experiment(name).run(seed=seed).to_json()))
        seconds.append(time.perf_counter() - t0)
    leaves, still = {}, 0
    for path, first in runs[0].items():
        values = [r.get(path) for r in runs]
        if not (is_number(first) and all(is_number(v) for v in values)):
            continue
        xs = [float(v) for v in values]
        sd = statistics.stdev(xs)
        if sd == 0.0:
            still += 1
            continue
        leaves[path] = {
            "mean": statistics.fmean(xs),
            "std": sd,
            "min": min(xs),
            "max": max(xs),
            "tolerance": SIGMAS * sd,
        }
    return {
        "seeds": list(SPREAD_SEEDS),
        "seconds_per_run": round(max(seconds), 2),
        "still_leaves": still,
        "leaves": leaves,
    }


def main(names: list[str]) -> None:
    doc = json.loads(SPREAD_FILE.read_text(encoding="utf-8")) if SPREAD_FILE.exists() else {}
    for name in names or EXPERIMENTS:
        doc[name] = spread(name)
        moved, still = len(doc[name]["leaves"]), doc[name]["still_leaves"]
        print(f"{name}: {moved + still} numeric leaves, {moved} moved over the seeds")
    SPREAD_FILE.write_text(json.dumps(doc, indent=1, sort_keys=True) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main(sys.argv[1:])
