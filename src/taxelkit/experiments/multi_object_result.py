"""Records and summaries of the ``multi-object`` experiment (:mod:`.multi_object`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["IMPERFECTIONS", "OUTCOMES", "RATES_HZ", "MultiObjectResult", "SceneOutcome"]

#: Outcomes of an object.
OUTCOMES = ("identified", "wrong", "unknown", "undecided", "missed")
#: How each scene is seen: as the sensor gives it (its noise), then through these
#: fault models (:data:`~taxelkit.sensors.faults.FAULT_PRESETS`).
IMPERFECTIONS: tuple[str, ...] = ("none", "all")
#: Frame rates of the scenes, Hz: the robustness matrix's default rate first, then the
#: faster ones (the same motions, drawn from the same seeds).
RATES_HZ: tuple[float, ...] = (20.0, 100.0, 240.0)


@dataclass(frozen=True)
class SceneOutcome:
    """The score of one scene.

    Attributes
    ----------
    engine : str
    n_objects, trial : int
    names : tuple of str
        The objects, in tile order (ground truth).
    outcomes : tuple of str
        Per object, one of :data:`OUTCOMES`.
    purities : tuple of float
        Per accepted track.
    mixed_wrong : int
        Wrong names from tracks of purity below 1.
    n_tracks : int
        Accepted tracks.
    merges, splits : int
        Tracker events.
    imperfection : str
        The fault model the frames were seen through (``"none"``: the
        sensor's noise only).
    rate_hz : float
        Frame rate, Hz.
    """

    engine: str
    n_objects: int
    trial: int
    names: tuple[str, ...]
    outcomes: tuple[str, ...]
    purities: tuple[float, ...]
    mixed_wrong: int
    n_tracks: int
    merges: int
    splits: int
    imperfection: str = "none"
    rate_hz: float = RATES_HZ[0]


@dataclass(frozen=True, eq=False)
class MultiObjectResult:
    """Every scene's score.

    Attributes
    ----------
    scenes : tuple of SceneOutcome
        Sorted by engine, object count, trial, then imperfection.
    engines : tuple of str
    counts : tuple of int
    imperfections : tuple of str
        The fault models each scene was seen through (``"none"`` first).
    rates_hz : tuple of float
        The frame rates each scene was seen at (the reference rate first).
    n_trials : int
        Scenes per object count with the kinematic engine.
    mujoco_trials : int
        Scenes per object count with the MuJoCo engine.
    skipped : dict of str to str
        Engines that could not run, with the reason.
    """

    scenes: tuple[SceneOutcome, ...]
    engines: tuple[str, ...]
    counts: tuple[int, ...]
    n_trials: int
    mujoco_trials: int
    skipped: dict[str, str]
    imperfections: tuple[str, ...] = IMPERFECTIONS
    rates_hz: tuple[float, ...] = RATES_HZ[:1]

    def summary(
        self,
        engine: str,
        n_objects: int,
        imperfection: str = "none",
        rate_hz: float = RATES_HZ[0],
    ) -> dict[str, Any]:
        """Figures of one engine, object count, imperfection and frame rate."""
        rows = [
            s
            for s in self.scenes
            if s.engine == engine
            and s.n_objects == n_objects
            and s.imperfection == imperfection
            and s.rate_hz == rate_hz
        ]
        outcomes = [o for s in rows for o in s.outcomes]
        purities = [p for s in rows for p in s.purities]
        n_obj = len(outcomes)
        counts = {k: outcomes.count(k) for k in OUTCOMES}
        return {
            "engine": engine,
            "rate_hz": rate_hz,
            "imperfection": imperfection,
            "n_objects": n_objects,
            "scenes": len(rows),
            "objects": n_obj,
            **counts,
            "identified_rate": counts["identified"] / n_obj if n_obj else float("nan"),
            "mixed_wrong": sum(s.mixed_wrong for s in rows),
            "tracks": len(purities),
            "mean_purity": float(np.mean(purities)) if purities else float("nan"),
            "pure_tracks": float(np.mean(np.asarray(purities) == 1.0))
            if purities
            else float("nan"),
            "merges": sum(s.merges for s in rows),
            "splits": sum(s.splits for s in rows),
        }

    def to_json(self) -> dict[str, Any]:
        """Summaries per engine, rate, imperfection and count, the acceptance, every scene.

        The acceptance is judged on the scenes as the sensor gives them
        (``"none"``), at every rate; ``acceptance_imperfect`` applies the same
        checks to each other imperfection.
        """
        summaries = [
            self.summary(e, n, f, r)
            for e in self.engines
            for r in self.rates_hz
            for f in self.imperfections
            for n in self.counts
        ]

        def checks(imperfection: str) -> dict[str, bool]:
            two = [
                s for s in summaries if s["n_objects"] == 2 and s["imperfection"] == imperfection
            ]
            return {
                "two_objects_identified_ge_95": bool(two)
                and all(s["identified_rate"] >= 0.95 for s in two),
                "two_objects_no_mixed_wrong": all(s["mixed_wrong"] == 0 for s in two),
            }

        return {
            "experiment": "multi-object",
            "n_trials": self.n_trials,
            "mujoco_trials": self.mujoco_trials,
            "rates_hz": list(self.rates_hz),
            "engines": list(self.engines),
            "imperfections": list(self.imperfections),
            "skipped": dict(self.skipped),
            "summaries": summaries,
            "acceptance": checks("none"),
            "acceptance_imperfect": {f: checks(f) for f in self.imperfections if f != "none"},
            "scenes": [
                {
                    "engine": s.engine,
                    "rate_hz": s.rate_hz,
                    "imperfection": s.imperfection,
                    "n_objects": s.n_objects,
                    "trial": s.trial,
                    "names": list(s.names),
                    "outcomes": list(s.outcomes),
                    "purities": list(s.purities),
                    "mixed_wrong": s.mixed_wrong,
                    "merges": s.merges,
                    "splits": s.splits,
                }
                for s in self.scenes
            ],
        }
