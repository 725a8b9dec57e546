"""The ``slip`` experiment: slip detected from the frames, against the slip of the simulated body.

Three kinds of trial, per engine and object, each seen at 20, 100 and 240
frames/s (the same motion) on the Bonneville array with its noise, and the
same frames again through each of ``imperfections`` (by default every fault
model of the robustness matrix at once, ``"all"``, with a seed of its own;
reported beside the acceptance, which is judged on the frames as the array
gives them):

``roll``
    The rolling scripts of :mod:`taxelkit.motion.scenarios` (no slip
    scripted): false alarms.
``partial``
    A roll with one slipping phase
    (:func:`~taxelkit.motion.slip_scenarios.make_partial_slip_scenario`;
    kinematic engine only): detection, and recognition under partial slip.
``slide``
    The sliding script (a face dragged and/or spun): detection, and the
    object must never be identified.

Ground truth (for scoring only): a *slip phase* is a run of steps in which
the material contact points move faster than :data:`GT_SLIP_MM_S` along the
plane (:meth:`~taxelkit.motion.rolling.Scenario.slip_mm`: rolling without
slip gives about 0, tipping up to 2 mm/s), runs less than
:data:`GT_MERGE_S` apart merged, phases shorter than :data:`GT_MIN_S`
ignored. Its kind is the body's most frequent contact over it, a tie going
to the one seen first (``area``, ``line``,
``point``; :attr:`~taxelkit.motion.rolling.Scenario.contact`, with the
tolerances of the engine's poses: a MuJoCo face rests level only to
micrometres), ``area spin`` when the engine labels most of it as spinning.

Scoring
    * A phase is *detected* by the earliest slip of the recogniser decided
      between :data:`EARLY_S` before its start and :data:`LATE_S` after its
      end; *latency* is the decision time less the phase's start (0 if
      earlier); *in time* is a latency of at most :data:`LATENCY_S`.
    * Beside it (not the acceptance's figure): what the sensor can resolve.
      A binary footprint changes where a taxel edge is crossed, and a slow
      slide (3-5 mm/s) moves less than one pitch (1.76 mm) in 0.2 s. *In
      time from one pitch* is a decision within :data:`LATENCY_S` of the
      phase's slip having reached one pitch (:func:`pitch_reached_s`);
      phases that slid less than a pitch in all are counted apart.
    * A detected slip matching no phase is a *false alarm*.
    * The verdict of each trial is also taken without slip detection
      (``TactemeConfig(slip=None)``, the table's sliding rows eliminating
      everything as before) for comparison.
"""

from __future__ import annotations

import os
from collections import Counter
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.experiments.sensor_views import check_views
from taxelkit.experiments.slip_result import (
    EARLY_S,
    GT_MERGE_S,
    GT_MIN_S,
    GT_SLIP_MM_S,
    LATE_S,
    LATENCY_S,
    RATES_HZ,
    TRIAL_KINDS,
    SlipResult,
    SlipTrial,
)
from taxelkit.experiments.work_units import run_units
from taxelkit.motion.engines.registry import engines_to_run, scenarios_from_engine
from taxelkit.motion.rolling import Scenario, frames_from_scenario
from taxelkit.motion.slip_scenarios import make_partial_slip_scenario
from taxelkit.sensors.faults import fault_model
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart.recogniser import recognise
from taxelkit.smart.tacteme_table import OBJECTS
from taxelkit.smart.tactemes import TactemeConfig

__all__ = [
    "GT_SLIP_MM_S",
    "IMPERFECTIONS",
    "LATENCY_S",
    "TRIAL_KINDS",
    "SlipResult",
    "SlipTrial",
    "pitch_reached_s",
    "run_slip",
    "slip_phases",
]


def slip_phases(scenario: Scenario) -> list[tuple[int, int, str]]:
    """Ground-truth slip phases ``(first_frame, last_frame, kind)`` of a scenario.

    ``first_frame`` is the frame at which the slip starts (the first slipping
    step leaves it), ``last_frame`` the one at which it stops.
    """
    t = np.asarray(scenario.t_s)
    speed = scenario.slip_mm() / np.diff(t)
    slipping = np.nan_to_num(speed, nan=0.0) > GT_SLIP_MM_S
    idx = np.flatnonzero(slipping)
    if idx.size == 0:
        return []
    runs: list[list[int]] = [[int(idx[0]), int(idx[0]) + 1]]
    for i in idx[1:].tolist():
        if t[i] - t[runs[-1][1]] <= GT_MERGE_S:
            runs[-1][1] = i + 1
        else:
            runs.append([i, i + 1])
    out = []
    for a, b in runs:
        if t[b] - t[a] < GT_MIN_S:
            continue
        contact = [c for c in scenario.contact[a : b + 1] if c != "none"]
        # the most frequent contact, a tie going to the first seen (a set's order
        # is that of the process's string hashes: it changed with the process)
        kind = Counter(contact).most_common(1)[0][0] if contact else "none"
        labels = scenario.phase[a + 1 : b + 1]
        if kind == "area" and labels.count("spinning") > len(labels) / 2:
            kind = "area spin"
        out.append((a, b, kind))
    return out


def pitch_reached_s(
    scenario: Scenario, phases: list[tuple[int, int, str]], pitch_mm: float
) -> list[float | None]:
    """Time from each phase's start until its slip reached one taxel pitch, s (None: never).

    The slip is that of the ground truth (:meth:`Scenario.slip_mm`, the
    contact points' largest displacement per step, for scoring only), summed
    from the phase's start. A binary footprint changes only where a taxel
    edge is crossed; a phase that slid less than ``pitch_mm`` in all may
    change none.
    """
    slid = np.nan_to_num(scenario.slip_mm(), nan=0.0)
    t = np.asarray(scenario.t_s)
    out: list[float | None] = []
    for a, b, _ in phases:
        far = np.flatnonzero(np.cumsum(slid[a:b]) >= pitch_mm)
        out.append(float(t[a + far[0] + 1] - t[a]) if far.size else None)
    return out


def score_trial(
    t_s: NDArray[np.float64],
    phases: list[tuple[int, int, str]],
    detected: list[int],
) -> tuple[list[tuple[str, float | None]], int]:
    """Match detections (decision frames) to phases; the latencies and the false alarms."""
    used: set[int] = set()
    out: list[tuple[str, float | None]] = []
    for a, b, kind in phases:
        start, end = float(t_s[a]), float(t_s[b])
        hits = [
            j
            for j, f in enumerate(detected)
            if start - EARLY_S <= float(t_s[f]) <= end + LATE_S and j not in used
        ]
        if hits:
            used.update(hits)
            out.append((kind, max(0.0, float(t_s[detected[hits[0]]]) - start)))
        else:
            out.append((kind, None))
    return out, len(detected) - len(used)


#: How each trial's frames are seen: as the array gives them, then through these
#: fault models (:data:`~taxelkit.sensors.faults.FAULT_PRESETS`).
IMPERFECTIONS: tuple[str, ...] = ("none", "all")


@dataclass(frozen=True)
class _Unit:
    engine: str
    kind: str
    obj: str
    trial: int
    entropy: int
    imperfections: tuple[str, ...] = IMPERFECTIONS
    rates_hz: tuple[float, ...] = RATES_HZ


def _scenarios(unit: _Unit, rng: np.random.Generator) -> list[Scenario]:
    """The unit's motion at every rate of the unit (one seed: the same motion)."""
    if unit.kind == "partial":
        seed = int(rng.integers(2**63 - 1))
        return [make_partial_slip_scenario(unit.obj, rng=seed, rate_hz=r) for r in unit.rates_hz]
    name = "sliding" if unit.kind == "slide" else unit.obj
    return scenarios_from_engine(unit.engine, name, rates_hz=unit.rates_hz, rng=rng)


def _trials(
    unit: _Unit,
    sc: Scenario,
    rate_hz: float,
    rng: np.random.Generator,
    fault_seeds: list[np.random.SeedSequence],
) -> list[SlipTrial]:
    """One motion at one rate, scored as the array gives it and through each imperfection."""
    rec = frames_from_scenario(BONNEVILLE_16X16, sc, rng=rng)
    thr = BONNEVILLE_16X16.contact_threshold_mm
    t = np.asarray(sc.t_s)
    truth = slip_phases(sc)
    dt = float(np.median(np.diff(t)))
    slid_mm = np.nan_to_num(sc.slip_mm(), nan=0.0)
    speeds = tuple(float(slid_mm[a:b].sum() / (t[b] - t[a])) for a, b, _ in truth)
    pitch_s = tuple(pitch_reached_s(sc, truth, BONNEVILLE_16X16.array.pitch_mm))
    out = []
    for name, fseed in zip(unit.imperfections, fault_seeds, strict=True):
        seen = rec
        if name != "none":
            seen = fault_model(name).apply(rec, threshold=thr, rng=np.random.default_rng(fseed))
        res = recognise(seen, threshold=thr)
        without = recognise(seen, threshold=thr, config=TactemeConfig(slip=None))
        phases, false_alarms = score_trial(t, truth, [s.detected_frame for s in res.slips])
        out.append(
            SlipTrial(
                engine=unit.engine,
                kind=unit.kind,
                obj=sc.object_name,
                rate_hz=float(rate_hz),
                trial=unit.trial,
                identified=res.identified,
                reason=res.verdict.reason,
                identified_without=without.identified,
                phases=tuple(phases),
                phase_speeds_mm_s=speeds,
                pitch_s=pitch_s,
                false_alarms=false_alarms,
                contact_s=float(np.count_nonzero(sc.in_contact)) * dt,
                imperfection=name,
            )
        )
    return out


def _run_unit(unit: _Unit) -> list[SlipTrial]:
    rng = np.random.default_rng(np.random.SeedSequence(unit.entropy))
    scenes = _scenarios(unit, rng)
    # the imperfections' seeds, apart from the motion's stream (its trials unchanged)
    seeds = np.random.SeedSequence(unit.entropy).spawn(len(unit.rates_hz) * len(unit.imperfections))
    k = len(unit.imperfections)
    return [
        trial
        for i, (sc, r) in enumerate(zip(scenes, unit.rates_hz, strict=True))
        for trial in _trials(unit, sc, r, rng, seeds[i * k : (i + 1) * k])
    ]


def run_slip(
    *,
    seed: int = 0,
    n_trials: int = 30,
    mujoco_trials: int | None = None,
    engines: Sequence[str] | None = None,
    imperfections: Sequence[str] = IMPERFECTIONS,
    rates_hz: Sequence[float] = RATES_HZ,
    workers: int | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> SlipResult:
    """Run the slip experiment.

    Parameters
    ----------
    seed : int
        Seed of every trial (the same seed, the same result).
    n_trials : int
        Kinematic trials per kind and object, each seen at every rate of
        :data:`RATES_HZ` (the ``slide`` kind: ``6 x n_trials`` trials, the
        object slid drawn by the script).
    mujoco_trials : int, optional
        MuJoCo trials per kind and object (default ``n_trials``); MuJoCo runs
        the ``roll`` and ``slide`` kinds (no partial-slip script).
    engines : sequence of str, optional
        Default both, MuJoCo skipped (and listed) when not installed.
    imperfections : sequence of str
        Fault models every trial's frames are also seen through (names of
        :data:`~taxelkit.sensors.faults.FAULT_PRESETS`); ``"none"`` (the
        array's noise only) is always first.
    rates_hz : sequence of float
        Frame rates every motion is seen at (default :data:`RATES_HZ`).
    workers : int, optional
        Local worker processes (default: the CPU count).
    progress : callable, optional
        ``progress(done, total)`` after each trial.

    Returns
    -------
    SlipResult
    """
    if int(n_trials) < 1:
        raise InputError(f"n_trials must be >= 1, got {n_trials!r}")
    imps, rates = check_views(imperfections, rates_hz)
    chosen, skipped = engines_to_run(engines)
    n_mj = int(n_trials) if mujoco_trials is None else int(mujoco_trials)
    units = []
    for engine in chosen:
        e_key = int.from_bytes(engine.encode()[:8], "little")
        kinds = TRIAL_KINDS if engine == "kinematic" else ("roll", "slide")
        for k_i, kind in enumerate(kinds):
            for o_i, obj in enumerate(OBJECTS):
                for trial in range(n_mj if engine == "mujoco" else int(n_trials)):
                    key = [int(seed), e_key, k_i, o_i, trial]
                    ent = np.random.SeedSequence(key).generate_state(1)
                    units.append(_Unit(engine, kind, obj, trial, int(ent[0]), imps, rates))
    n_workers = (os.cpu_count() or 1) if workers is None else max(1, int(workers))
    results: list[list[SlipTrial]] = [[] for _ in units]
    stream = run_units(_run_unit, units, workers=n_workers)
    for done, (i, res) in enumerate(stream, start=1):
        results[i] = res
        if progress is not None:
            progress(done, len(units))
    trials = [t for r in results for t in r]
    return SlipResult(tuple(trials), tuple(chosen), int(n_trials), n_mj, skipped, imps, rates)
