"""The ``robustness`` experiment: the smart sensor on motion, sensors and rates nobody tuned it to.

A matrix of engine (kinematic scripts, MuJoCo physics) x frame rate (5, 20,
100, 240 frames/s) x sensor imperfection (none, dead, stuck, flicker,
crosstalk, threshold spread, all together; :mod:`taxelkit.sensors.faults`) x
object, ``n_trials`` randomised trials per cell, plus sliding trials (never to
be identified) and lift-off trials (a 70 ms loss of contact mid-motion, which
the evidence must survive).

One *unit* of work is one motion: the engine moves one object (or slides
one) at one rate; the skin model turns the poses into frames with the
sensor's noise; each imperfection is then applied with its own seed and the
recogniser (default, robust pipeline) sees the result. The scenario's ground
truth (object name, sliding) is used only to score.

Units run on a local process pool by default, or on a Dask cluster given a
scheduler address (``dask.distributed``, optional extra ``taxelkit[dask]``).
Results are sorted by unit, so the outcome does not depend on where or in
which order units ran.
"""

from __future__ import annotations

import dataclasses
import importlib.util
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from taxelkit.errors import InputError
from taxelkit.experiments.robustness_outcomes import (
    ARRAY_FAULTS,
    ARRAY_RATE_HZ,
    LIFT_OFF,
    MAIN_ARRAY,
    SLIDING,
    TrialOutcome,
    outcomes_json,
)
from taxelkit.experiments.work_units import run_units
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.sensors.array_geometry import TaxelArray
from taxelkit.sensors.faults import fault_model
from taxelkit.sensors.presets import BONNEVILLE_16X16, Sensor
from taxelkit.smart.recogniser import recognise
from taxelkit.smart.tacteme_table import OBJECTS
from taxelkit.smart.tactemes import PAPER_LEVEL3

__all__ = [
    "FAULTS",
    "OTHER_ARRAYS",
    "RATES_HZ",
    "RobustnessResult",
    "TrialOutcome",
    "array_sensor",
    "available_engines",
    "run_robustness",
]

#: Frame rates of the matrix, Hz: the paper's "10 to 50 times" 1 Hz, our
#: default, a common camera-like rate and the Bonneville's maximum.
RATES_HZ: tuple[float, ...] = (5.0, 20.0, 100.0, 240.0)
#: Imperfections of the matrix (presets of :func:`~taxelkit.sensors.faults.fault_model`).
FAULTS: tuple[str, ...] = (
    "none",
    "dead",
    "stuck",
    "flicker",
    "crosstalk",
    "threshold-spread",
    "all",
)
#: Contact threshold of the simulated Bonneville frames, mm.
THRESHOLD_MM = BONNEVILLE_16X16.contact_threshold_mm
#: Other arrays, about as wide (28-32 mm) with other pitches and sizes, mm:
#: the same objects rolled at 20 frames/s, seen clean and with every
#: imperfection at once.
OTHER_ARRAYS: tuple[tuple[int, float], ...] = ((8, 3.5), (12, 2.5), (20, 1.5), (32, 1.0))


def array_sensor(rows: int, pitch_mm: float) -> Sensor:
    """The Bonneville preset with another square array (the skin and threshold kept)."""
    array = TaxelArray(rows=rows, cols=rows, pitch_mm=pitch_mm, element_size_mm=0.85 * pitch_mm)
    return dataclasses.replace(BONNEVILLE_16X16, name=f"{rows}x{rows}@{pitch_mm:g}", array=array)


def available_engines() -> dict[str, str | None]:
    """Each engine with None if it can run here, else the reason it cannot."""
    from taxelkit.motion.engines import ENGINE_NAMES, MUJOCO_INSTALL_HINT

    has_mujoco = importlib.util.find_spec("mujoco") is not None
    why = None if has_mujoco else f"MuJoCo is not installed ({MUJOCO_INSTALL_HINT})"
    return {e: (why if e == "mujoco" else None) for e in ENGINE_NAMES}


@dataclass(frozen=True)
class _Unit:
    """One motion: an engine moves one object once; seen at every rate (and fault)."""

    engine: str
    rates_hz: tuple[float, ...]
    truth: str
    trial: int
    entropy: int
    array: tuple[int, float] | None = None  # None: the main matrix's array


def _run_unit(unit: _Unit) -> list[TrialOutcome]:
    """One motion, every rate, every imperfection (worker side)."""
    from taxelkit.motion.engines import scenarios_from_engine

    seq = np.random.SeedSequence([unit.entropy, unit.trial])
    motion_seed, noise_seed, fault_seed = seq.spawn(3)
    sensor = BONNEVILLE_16X16 if unit.array is None else array_sensor(*unit.array)
    label = MAIN_ARRAY if unit.array is None else sensor.name
    scenarios = scenarios_from_engine(
        unit.engine,
        unit.truth,
        rates_hz=unit.rates_hz,
        rng=np.random.default_rng(motion_seed),
        sensor=sensor,
    )
    if unit.array is not None:
        faults: tuple[str, ...] = ARRAY_FAULTS
    else:
        faults = (*FAULTS, LIFT_OFF) if unit.truth != SLIDING else FAULTS
    out = []
    for rate, sc in zip(unit.rates_hz, scenarios, strict=True):
        rec = frames_from_scenario(sensor, sc, rng=np.random.default_rng(noise_seed))
        for name, fseed in zip(faults, fault_seed.spawn(len(faults)), strict=True):
            seen = fault_model(name).apply(
                rec, threshold=THRESHOLD_MM, rng=np.random.default_rng(fseed)
            )
            r = recognise(seen, threshold=THRESHOLD_MM)
            paper = recognise(
                seen, threshold=THRESHOLD_MM, cleaning=None, limits=None, config=PAPER_LEVEL3
            )
            out.append(
                TrialOutcome(
                    unit.engine, rate, name, unit.truth, unit.trial, r.identified,
                    r.candidates, label, paper.identified,
                    tuple(str(e.value) for e in r.events if e.kind == "identified"),
                )
            )  # fmt: skip
    return out


def _units(
    engines: Sequence[str],
    rates: Sequence[float],
    n_trials: int,
    seed: int,
    arrays: Sequence[tuple[int, float]] = (),
    array_trials: int = 0,
) -> list[_Unit]:
    out: list[_Unit] = []
    rates_t = tuple(float(r) for r in rates)
    for engine in engines:
        e_i = int.from_bytes(engine.encode()[:8], "little")  # stable, whatever else runs
        for o_i, truth in enumerate((*OBJECTS, SLIDING)):
            entropy = int(np.random.SeedSequence([seed, e_i, o_i]).generate_state(1)[0])
            out.extend(_Unit(engine, rates_t, truth, t, entropy) for t in range(n_trials))
            for rows, pitch in arrays:
                a_seed = np.random.SeedSequence([seed, e_i, o_i, rows]).generate_state(1)[0]
                out.extend(
                    _Unit(engine, (ARRAY_RATE_HZ,), truth, t, int(a_seed), (rows, pitch))
                    for t in range(array_trials)
                )
    return out


@dataclass(frozen=True, eq=False)
class RobustnessResult:
    """Every outcome of the sweep.

    Attributes
    ----------
    outcomes : tuple of TrialOutcome
        Sorted by engine, rate, truth, trial, fault.
    engines, faults : tuple of str
    rates_hz : tuple of float
    n_trials : int
    skipped : dict of str to str
        Engines that could not run, with the reason.
    """

    outcomes: tuple[TrialOutcome, ...]
    engines: tuple[str, ...]
    rates_hz: tuple[float, ...]
    faults: tuple[str, ...]
    n_trials: int
    skipped: dict[str, str]

    def cell(self, engine: str, rate_hz: float, fault: str, truth: str) -> list[TrialOutcome]:
        """The outcomes of one cell."""
        return [
            o
            for o in self.outcomes
            if o.engine == engine and o.rate_hz == rate_hz and o.fault == fault and o.truth == truth
        ]

    def to_json(self) -> dict[str, Any]:
        """Per-cell counts and accuracy, summaries per engine x rate x fault, sliding, lift-off."""
        return outcomes_json(
            self.outcomes, self.engines, self.rates_hz, self.faults, self.n_trials, self.skipped
        )


def _choose_engines(engines: Sequence[str] | None) -> tuple[list[str], dict[str, Any]]:
    """The engines to run and the skipped ones with the reason (all available ones by default).

    Raises
    ------
    InputError
        For an unknown engine, one that cannot run here, or none available.
    """
    avail = available_engines()
    if engines is None:
        chosen = [e for e, why in avail.items() if why is None]
        skipped = {e: why for e, why in avail.items() if why is not None}
    else:
        unknown = [e for e in engines if e not in avail]
        if unknown:
            raise InputError(f"unknown engine(s) {unknown}; known: {', '.join(avail)}")
        blocked = {e: avail[e] for e in engines if avail[e] is not None}
        if blocked:
            e, why = next(iter(blocked.items()))
            raise InputError(f"engine {e} cannot run: {why}")
        chosen, skipped = list(engines), {}
    if not chosen:
        raise InputError("no simulation engine is available")
    return chosen, skipped


def run_robustness(
    *,
    seed: int = 0,
    n_trials: int = 30,
    engines: Sequence[str] | None = None,
    rates_hz: Sequence[float] = RATES_HZ,
    arrays: Sequence[tuple[int, float]] = OTHER_ARRAYS,
    array_trials: int | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: Callable[[int, int], None] | None = None,
) -> RobustnessResult:
    """Run the robustness sweep.

    Parameters
    ----------
    seed : int
        Seed of every motion, noise and imperfection: the same seed gives the
        same result wherever the units run.
    n_trials : int
        Randomised motions per object (and of sliding) per engine and rate.
    engines : sequence of str, optional
        Default: every engine available here (MuJoCo needs ``taxelkit[mujoco]``;
        skipped engines are listed in the result with the reason).
    rates_hz : sequence of float
    arrays : sequence of (rows, pitch_mm)
        Other square arrays to roll the objects on at :data:`ARRAY_RATE_HZ`
        (empty: the main matrix only).
    array_trials : int, optional
        Randomised motions per object on each of the other arrays (default: a
        third of ``n_trials``, at least 1).
    workers : int, optional
        Local worker processes (default: the CPU count).
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://HOST:PORT``): run the units there.
    progress : callable, optional
        ``progress(done, total)`` after each unit.

    Returns
    -------
    RobustnessResult

    Raises
    ------
    InputError
        For an unknown engine, or no engine available.
    """
    if int(n_trials) < 1:
        raise InputError(f"n_trials must be >= 1, got {n_trials!r}")
    chosen, skipped = _choose_engines(engines)
    per_array = max(1, int(n_trials) // 3) if array_trials is None else int(array_trials)
    units = _units(chosen, rates_hz, int(n_trials), int(seed), arrays, per_array)
    n_workers = (os.cpu_count() or 1) if workers is None else max(1, int(workers))
    stream = run_units(_run_unit, units, workers=n_workers, scheduler=scheduler)
    results: list[list[TrialOutcome] | None] = [None] * len(units)
    for done, (i, res) in enumerate(stream, start=1):
        results[i] = res
        if progress is not None:
            progress(done, len(units))
    outcomes = tuple(o for res in results if res is not None for o in res)
    return RobustnessResult(
        outcomes=outcomes,
        engines=tuple(chosen),
        rates_hz=tuple(float(r) for r in rates_hz),
        faults=FAULTS,
        n_trials=int(n_trials),
        skipped={k: str(v) for k, v in skipped.items()},
    )
