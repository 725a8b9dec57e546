"""The ``multi-object`` experiment: two and three of the six solids on one array at once.

One *unit* is one scene (:func:`~taxelkit.motion.multi_scenes.multi_scene`):
``n`` distinct objects drawn at random from the six, each moved by the
chosen engine in its own tile of a ``16 x 16 n`` array, each after a random
delay, composed and seen with the sensor's noise; then recognised again through
each of ``imperfections`` (fault models of :func:`~taxelkit.sensors.faults.fault_model`,
by default all at once, ``"all"``, seeded apart). The recogniser
(:func:`~taxelkit.smart.objects.recognise_objects`, default robust pipeline)
sees only the frames; the ground truth (which object pressed each taxel)
serves only to score.

Scoring
    * A track's *frame owner* is the object that pressed most of the track's
      taxels in that frame; its *true object* the most frequent frame owner;
      its *purity* the fraction of its frames owned by its true object.
    * Only tracks whose recogniser accepted a contact count (shorter ones
      conclude nothing).
    * An object is **identified** when one of its tracks names it, **wrong**
      when one of its tracks names another object, **unknown** when a track
      answers "unknown", else **undecided** (or **missed**: no track).
    * A **mixed-up** wrong identity is a wrong name from a track of purity
      below 1 (the acceptance asks for none with two objects).

Units run on a local process pool or a Dask cluster; each has its own
:class:`numpy.random.SeedSequence` child (the result does not depend on where units ran).
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.experiments.work_units import run_units
from taxelkit.motion.engines import engines_to_run
from taxelkit.motion.multi_scenes import frames_from_multi_scene, multi_scene
from taxelkit.sensors.faults import FAULT_PRESETS, fault_model
from taxelkit.smart.levels12 import DEFAULT_THRESHOLD_MM
from taxelkit.smart.objects import ObjectRecognition, recognise_objects
from taxelkit.smart.tacteme_table import OBJECTS

__all__ = [
    "IMPERFECTIONS",
    "OBJECT_COUNTS",
    "MultiObjectResult",
    "SceneOutcome",
    "run_multi_object",
    "score_scene",
]

#: Objects per scene.
OBJECT_COUNTS: tuple[int, ...] = (2, 3)
#: How each scene is seen: as the sensor gives it (its noise), then through these
#: fault models (:data:`~taxelkit.sensors.faults.FAULT_PRESETS`).
IMPERFECTIONS: tuple[str, ...] = ("none", "all")
#: Frame rate of the scenes, Hz (the robustness matrix's default rate).
RATE_HZ = 20.0
#: Outcomes of an object.
OUTCOMES = ("identified", "wrong", "unknown", "undecided", "missed")


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


def score_scene(
    result: ObjectRecognition, owner: NDArray[np.int8], names: Sequence[str]
) -> tuple[tuple[str, ...], tuple[float, ...], int]:
    """Score a recognition against the ground truth (rules in the module docstring).

    Parameters
    ----------
    result : ObjectRecognition
        With its track map (``keep_map=True``).
    owner : (T, rows, cols) int
        Object pressing each taxel hardest, -1 none.
    names : sequence of str

    Returns
    -------
    outcomes : tuple of str
        Per object.
    purities : tuple of float
        Per accepted track.
    mixed_wrong : int
    """
    if result.track_map is None:
        raise InputError("result must keep its track map (keep_map=True)")
    tmap = result.track_map
    n = len(names)
    said: list[list[str | None]] = [[] for _ in range(n)]
    purities: list[float] = []
    mixed_wrong = 0
    for obj in result.objects:
        if not obj.accepted:
            continue
        mine = tmap == obj.track
        frames = np.flatnonzero(mine.any(axis=(1, 2)))
        votes = np.zeros((frames.size, n + 1), np.intp)  # column n: nobody (noise)
        for col in range(n + 1):
            who = col if col < n else -1
            votes[:, col] = (mine[frames] & (owner[frames] == who)).sum(axis=(1, 2))
        frame_owner = np.argmax(votes[:, :n], axis=1)
        if frames.size == 0 or not votes[:, :n].any():
            continue
        true = int(np.bincount(frame_owner, minlength=n).argmax())
        purity = float(np.mean(frame_owner == true))
        purities.append(purity)
        said[true].append(obj.identified)
        if obj.identified not in (None, "unknown", names[true]) and purity < 1.0:
            mixed_wrong += 1
    outcomes = []
    for k, name in enumerate(names):
        s = said[k]
        if any(v not in (None, "unknown", name) for v in s):
            outcomes.append("wrong")
        elif name in s:
            outcomes.append("identified")
        elif "unknown" in s:
            outcomes.append("unknown")
        elif s:
            outcomes.append("undecided")
        else:
            outcomes.append("missed")
    return tuple(outcomes), tuple(purities), mixed_wrong


@dataclass(frozen=True)
class _Unit:
    engine: str
    n_objects: int
    trial: int
    entropy: int
    imperfections: tuple[str, ...] = IMPERFECTIONS


def _run_unit(unit: _Unit) -> tuple[SceneOutcome, ...]:
    """One scene, scored as the sensor gives it and through each imperfection."""
    rng = np.random.default_rng(np.random.SeedSequence(unit.entropy))
    names = tuple(str(x) for x in rng.choice(OBJECTS, size=unit.n_objects, replace=False))
    scene = multi_scene(names, engine=unit.engine, rng=rng, rate_hz=RATE_HZ)
    frames = frames_from_multi_scene(scene, rng=rng)
    # each imperfection's own seed, apart from the scene's stream (its results unchanged)
    seeds = np.random.SeedSequence(unit.entropy).spawn(len(unit.imperfections))
    out = []
    for name, fseed in zip(unit.imperfections, seeds, strict=True):
        recording = frames.recording
        if name != "none":
            recording = fault_model(name).apply(
                recording, threshold=DEFAULT_THRESHOLD_MM, rng=np.random.default_rng(fseed)
            )
        result = recognise_objects(recording, keep_map=True)
        outcomes, purities, mixed = score_scene(result, frames.owner, names)
        kinds = [e.kind for e in result.events]
        out.append(
            SceneOutcome(
                engine=unit.engine,
                n_objects=unit.n_objects,
                trial=unit.trial,
                names=names,
                outcomes=outcomes,
                purities=purities,
                mixed_wrong=mixed,
                n_tracks=len(purities),
                merges=kinds.count("merge"),
                splits=kinds.count("split"),
                imperfection=name,
            )
        )
    return tuple(out)


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

    def summary(self, engine: str, n_objects: int, imperfection: str = "none") -> dict[str, Any]:
        """Figures of one engine, object count and imperfection."""
        rows = [
            s
            for s in self.scenes
            if s.engine == engine and s.n_objects == n_objects and s.imperfection == imperfection
        ]
        outcomes = [o for s in rows for o in s.outcomes]
        purities = [p for s in rows for p in s.purities]
        n_obj = len(outcomes)
        counts = {k: outcomes.count(k) for k in OUTCOMES}
        return {
            "engine": engine,
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
        """Summaries per engine, imperfection and count, the acceptance checks, every scene.

        The acceptance is judged on the scenes as the sensor gives them
        (``"none"``); ``acceptance_imperfect`` applies the same checks to
        each other imperfection.
        """
        summaries = [
            self.summary(e, n, f)
            for e in self.engines
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
            "rate_hz": RATE_HZ,
            "engines": list(self.engines),
            "imperfections": list(self.imperfections),
            "skipped": dict(self.skipped),
            "summaries": summaries,
            "acceptance": checks("none"),
            "acceptance_imperfect": {f: checks(f) for f in self.imperfections if f != "none"},
            "scenes": [
                {
                    "engine": s.engine,
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


def run_multi_object(
    *,
    seed: int = 0,
    n_trials: int = 100,
    engines: Sequence[str] | None = None,
    mujoco_trials: int | None = None,
    counts: Sequence[int] = OBJECT_COUNTS,
    imperfections: Sequence[str] = IMPERFECTIONS,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> MultiObjectResult:
    """Run the multi-object experiment.

    Parameters
    ----------
    seed : int
        Seed of every scene: the same seed gives the same result wherever the
        units run.
    n_trials : int
        Scenes per object count with the kinematic engine.
    mujoco_trials : int, optional
        Scenes per object count with the MuJoCo engine (default a fifth of
        ``n_trials``, at least 1: a physics scene costs about 30 times a
        kinematic one).
    engines : sequence of str, optional
        Default: both, MuJoCo skipped (and listed) when not installed.
    counts : sequence of int
        Objects per scene (2 to 6).
    imperfections : sequence of str
        Fault models each scene is also seen through (names of
        :data:`~taxelkit.sensors.faults.FAULT_PRESETS`); ``"none"`` (the
        sensor's noise only) is always first.
    workers : int, optional
        Local worker processes (default: the CPU count).
    scheduler : str, optional
        Address of a Dask scheduler: run the units there.
    progress : callable, optional
        ``progress(done, total)`` after each scene.

    Returns
    -------
    MultiObjectResult
    """
    if int(n_trials) < 1:
        raise InputError(f"n_trials must be >= 1, got {n_trials!r}")
    for c in counts:
        if not 1 <= int(c) <= len(OBJECTS):
            raise InputError(f"counts must lie in 1..{len(OBJECTS)}, got {c!r}")
    for name in imperfections:
        if name not in FAULT_PRESETS:
            raise InputError(f"unknown imperfection {name!r}; known: {', '.join(FAULT_PRESETS)}")
    imps = ("none", *dict.fromkeys(str(f) for f in imperfections if f != "none"))
    chosen, skipped = engines_to_run(engines)
    n_mujoco = max(1, int(n_trials) // 5) if mujoco_trials is None else int(mujoco_trials)
    units = []
    for engine in chosen:
        e_key = int.from_bytes(engine.encode()[:8], "little")
        for n in counts:
            for trial in range(n_mujoco if engine == "mujoco" else int(n_trials)):
                ent = np.random.SeedSequence([int(seed), e_key, int(n), trial]).generate_state(1)
                units.append(_Unit(engine, int(n), trial, int(ent[0]), imps))
    n_workers = (os.cpu_count() or 1) if workers is None else max(1, int(workers))
    stream = run_units(_run_unit, units, workers=n_workers, scheduler=scheduler)
    results: list[tuple[SceneOutcome, ...] | None] = [None] * len(units)
    for done, (i, res) in enumerate(stream, start=1):
        results[i] = res
        if progress is not None:
            progress(done, len(units))
    return MultiObjectResult(
        scenes=tuple(s for r in results if r is not None for s in r),
        engines=tuple(chosen),
        counts=tuple(int(c) for c in counts),
        n_trials=int(n_trials),
        mujoco_trials=n_mujoco,
        skipped=skipped,
        imperfections=imps,
    )
