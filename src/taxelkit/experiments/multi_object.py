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

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.experiments.multi_object_result import (
    IMPERFECTIONS,
    OUTCOMES,
    RATES_HZ,
    MultiObjectResult,
    SceneOutcome,
)
from taxelkit.experiments.sensor_views import check_views
from taxelkit.experiments.work_units import run_units
from taxelkit.motion.engines import engines_to_run
from taxelkit.motion.multi_scenes import frames_from_multi_scene, multi_scene
from taxelkit.sensors.faults import fault_model
from taxelkit.smart.levels12 import DEFAULT_THRESHOLD_MM
from taxelkit.smart.objects import ObjectRecognition, recognise_objects
from taxelkit.smart.tacteme_table import OBJECTS

__all__ = [
    "IMPERFECTIONS",
    "OBJECT_COUNTS",
    "OUTCOMES",
    "RATES_HZ",
    "MultiObjectResult",
    "SceneOutcome",
    "run_multi_object",
    "score_scene",
]

#: Objects per scene.
OBJECT_COUNTS: tuple[int, ...] = (2, 3)


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
    rates_hz: tuple[float, ...] = RATES_HZ[:1]


def _run_unit(unit: _Unit) -> tuple[SceneOutcome, ...]:
    """One scene at each rate, scored as the sensor gives it and through each imperfection."""
    return tuple(o for i, r in enumerate(unit.rates_hz) for o in _run_rate(unit, r, i))


def _run_rate(unit: _Unit, rate_hz: float, i: int) -> list[SceneOutcome]:
    """The scene at one rate: the same objects and motions at every rate (one seed)."""
    rng = np.random.default_rng(np.random.SeedSequence(unit.entropy))
    names = tuple(str(x) for x in rng.choice(OBJECTS, size=unit.n_objects, replace=False))
    scene = multi_scene(names, engine=unit.engine, rng=rng, rate_hz=rate_hz)
    frames = frames_from_multi_scene(scene, rng=rng)
    # each imperfection's own seed, apart from the scene's stream (its results unchanged)
    root = np.random.SeedSequence(unit.entropy if i == 0 else [unit.entropy, i])
    seeds = root.spawn(len(unit.imperfections))
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
                rate_hz=float(rate_hz),
            )
        )
    return out


def run_multi_object(
    *,
    seed: int = 0,
    n_trials: int = 100,
    engines: Sequence[str] | None = None,
    mujoco_trials: int | None = None,
    counts: Sequence[int] = OBJECT_COUNTS,
    imperfections: Sequence[str] = IMPERFECTIONS,
    rates_hz: Sequence[float] = RATES_HZ,
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
    rates_hz : sequence of float
        Frame rates, Hz: each scene's motions at every rate (the first is the
        reference rate of the committed figures, 20 frames/s by default).
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
    imps, rates = check_views(imperfections, rates_hz)
    chosen, skipped = engines_to_run(engines)
    n_mujoco = max(1, int(n_trials) // 5) if mujoco_trials is None else int(mujoco_trials)
    units = []
    for engine in chosen:
        e_key = int.from_bytes(engine.encode()[:8], "little")
        for n in counts:
            for trial in range(n_mujoco if engine == "mujoco" else int(n_trials)):
                ent = np.random.SeedSequence([int(seed), e_key, int(n), trial]).generate_state(1)
                units.append(_Unit(engine, int(n), trial, int(ent[0]), imps, rates))
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
        rates_hz=rates,
    )
