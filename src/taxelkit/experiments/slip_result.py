"""Records and summaries of the ``slip`` experiment (:mod:`taxelkit.experiments.slip`)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from taxelkit.smart.tacteme_table import OBJECTS

__all__ = [
    "DETECTABLE",
    "GT_SLIP_MM_S",
    "LATENCY_S",
    "RATES_HZ",
    "SPEED_BANDS_MM_S",
    "TRIAL_KINDS",
    "SlipResult",
    "SlipTrial",
    "acceptance_checks",
]

#: Kinds of trial.
TRIAL_KINDS: tuple[str, ...] = ("roll", "partial", "slide")
#: Frame rates, Hz: the default rate of every experiment, a faster one and the
#: Bonneville array's own (the same motions at each).
RATES_HZ: tuple[float, ...] = (20.0, 100.0, 240.0)
#: Ground truth: contact points moving faster than this along the plane slip, mm/s.
GT_SLIP_MM_S = 2.5
#: Ground-truth runs closer than this are one phase, s.
GT_MERGE_S = 0.1
#: Ground-truth phases shorter than this are ignored, s.
GT_MIN_S = 0.1
#: Acceptance: a phase detected within this time of its start, s.
LATENCY_S = 0.2
#: Bands of a phase's mean speed for the rate in time, mm/s (lower edges; the
#: scripted slides run at 3-6 mm/s, and a smooth motion reaches the detector's
#: 0.35 mm within 0.2 s only above about 3.7 mm/s, :mod:`taxelkit.smart.slip`).
SPEED_BANDS_MM_S: tuple[float, ...] = (0.0, 4.0, 5.0)
#: A detection may precede a phase's start by this much (the onset is estimated), s.
EARLY_S = 0.1
#: ... or follow its end by this much (a slip too slow to decide at once), s.
LATE_S = 0.3


@dataclass(frozen=True)
class SlipTrial:
    """One trial.

    Attributes
    ----------
    engine, kind, obj : str
        Engine, trial kind (:data:`TRIAL_KINDS`) and the object (ground truth).
    rate_hz : float
    trial : int
    identified : str or None
        The verdict with slip detection.
    reason : str or None
        Why not identified (``"slid"``, ``"ruled out"``, ``"undecided"``).
    identified_without : str or None
        The verdict without slip detection.
    phases : tuple of (kind, latency_s or None)
        Every ground-truth phase and its detection latency (None: missed).
    phase_speeds_mm_s : tuple of float
        Each phase's mean speed of the contact points along the plane, mm/s.
    pitch_s : tuple of (float or None)
        Each phase's time from its start until its slip reached one taxel
        pitch, s (None: it never did;
        :func:`~taxelkit.experiments.slip.pitch_reached_s`).
    false_alarms : int
        Detected slips matching no phase.
    contact_s : float
        Time in contact, s.
    imperfection : str
        The fault model the frames were seen through (``"none"``: the
        array's noise only; :func:`~taxelkit.sensors.faults.fault_model`).
    """

    engine: str
    kind: str
    obj: str
    rate_hz: float
    trial: int
    identified: str | None
    reason: str | None
    identified_without: str | None
    phases: tuple[tuple[str, float | None], ...]
    phase_speeds_mm_s: tuple[float, ...]
    false_alarms: int
    contact_s: float
    pitch_s: tuple[float | None, ...] = ()
    imperfection: str = "none"


#: Slip kinds a binary footprint can show (see :mod:`taxelkit.smart.slip`).
DETECTABLE: tuple[str, ...] = ("area", "line")


def _phase_stats(trials: Sequence[SlipTrial], kinds: Sequence[str] | None) -> dict[str, Any]:
    lat = [x for t in trials for k, x in t.phases if kinds is None or k in kinds]
    found = [x for x in lat if x is not None]
    in_time = sum(x <= LATENCY_S + 1e-9 for x in found)
    return {
        "phases": len(lat),
        "detected": len(found),
        "in_time": in_time,
        "in_time_rate": in_time / len(lat) if lat else float("nan"),
        "median_latency_s": float(np.median(found)) if found else float("nan"),
    }


def _by_speed(trials: Sequence[SlipTrial]) -> list[dict[str, Any]]:
    """The detectable phases in time per band of :data:`SPEED_BANDS_MM_S`."""
    rows = [
        (v, x)
        for t in trials
        for (k, x), v in zip(t.phases, t.phase_speeds_mm_s, strict=True)
        if k in DETECTABLE
    ]
    out = []
    for lo, hi in zip(SPEED_BANDS_MM_S, (*SPEED_BANDS_MM_S[1:], float("inf")), strict=True):
        lat = [x for v, x in rows if lo <= v < hi]
        in_time = sum(x is not None and x <= LATENCY_S + 1e-9 for x in lat)
        out.append({"from_mm_s": lo, "phases": len(lat), "in_time": in_time})
    return out


def _from_pitch(trials: Sequence[SlipTrial]) -> dict[str, Any]:
    """Detectable phases whose slip reached one pitch, in time from that moment.

    A decision within :data:`LATENCY_S` of the slip having reached one
    pitch (or before it) is in time; phases that slid less than a pitch are
    counted apart (``unresolvable``, and how many were found).
    """
    rows = [
        (x, p)
        for t in trials
        for (k, x), p in zip(t.phases, t.pitch_s or (None,) * len(t.phases), strict=True)
        if k in DETECTABLE
    ]
    resolvable = [(x, p) for x, p in rows if p is not None]
    in_time = sum(x is not None and x - p <= LATENCY_S + 1e-9 for x, p in resolvable)
    return {
        "phases": len(resolvable),
        "detected": sum(x is not None for x, _ in resolvable),
        "in_time": in_time,
        "in_time_rate": in_time / len(resolvable) if resolvable else float("nan"),
        "unresolvable": len(rows) - len(resolvable),
        "unresolvable_detected": sum(x is not None for x, p in rows if p is None),
    }


def acceptance_checks(o: dict[str, Any]) -> dict[str, bool]:
    """The acceptance's checks of one rate's entry of :meth:`SlipResult.overall`."""
    return {
        "detectable_in_time_ge_95": bool(o["detectable"]["in_time_rate"] >= 0.95),
        "roll_false_alarms_le_2": bool(o["roll_false_alarm_trial_rate"] <= 0.02),
        "sliding_never_identified": o["sliding_identified"] == 0,
    }


def _verdicts(trials: Sequence[SlipTrial], *, without: bool = False) -> dict[str, int]:
    said = [(t.identified_without if without else t.identified, t.obj) for t in trials]
    return {
        "identified": sum(v == o for v, o in said),
        "wrong": sum(v in OBJECTS and v != o for v, o in said),
        "not_identified": sum(v not in OBJECTS for v, _ in said),
    }


@dataclass(frozen=True, eq=False)
class SlipResult:
    """Every trial of the ``slip`` experiment.

    Attributes
    ----------
    trials : tuple of SlipTrial
        Sorted by engine, kind, object, trial, then rate and imperfection.
    engines : tuple of str
    n_trials : int
        Kinematic trials per kind and object (``slide``: per object slid).
    mujoco_trials : int
        MuJoCo trials per kind and object.
    skipped : dict of str to str
    imperfections : tuple of str
        The fault models every trial's frames were also seen through
        (``"none"`` first: the summaries and the acceptance).
    rates_hz : tuple of float
        The frame rates every motion was seen at.
    """

    trials: tuple[SlipTrial, ...]
    engines: tuple[str, ...]
    n_trials: int
    mujoco_trials: int
    skipped: dict[str, str]
    imperfections: tuple[str, ...] = ("none",)
    rates_hz: tuple[float, ...] = RATES_HZ

    def summary(
        self, engine: str, rate_hz: float, kind: str, imperfection: str = "none"
    ) -> dict[str, Any]:
        """Figures of one engine, frame rate, kind of trial and imperfection."""
        rows = [
            t
            for t in self.trials
            if t.engine == engine
            and t.kind == kind
            and t.rate_hz == rate_hz
            and t.imperfection == imperfection
        ]
        contact_s = sum(t.contact_s for t in rows)
        fa = sum(t.false_alarms for t in rows)
        by_kind = sorted({k for t in rows for k, _ in t.phases})
        return {
            "engine": engine,
            "rate_hz": rate_hz,
            "kind": kind,
            "trials": len(rows),
            "detectable": _phase_stats(rows, DETECTABLE),
            "by_slip_kind": {k: _phase_stats(rows, [k]) for k in by_kind},
            "false_alarms": fa,
            "trials_with_false_alarm": sum(t.false_alarms > 0 for t in rows),
            "false_alarm_trial_rate": (
                sum(t.false_alarms > 0 for t in rows) / len(rows) if rows else float("nan")
            ),
            "false_alarms_per_s": fa / contact_s if contact_s else float("nan"),
            "verdicts": _verdicts(rows),
            "verdicts_without_slip": _verdicts(rows, without=True),
            "slid": sum(t.reason == "slid" for t in rows),
            "per_object": {
                o: {
                    "trials": len(mine),
                    **_verdicts(mine),
                    "without_slip": _verdicts(mine, without=True)["identified"],
                    "slid": sum(t.reason == "slid" for t in mine),
                    "in_time": _phase_stats(mine, DETECTABLE)["in_time"],
                    "phases": _phase_stats(mine, DETECTABLE)["phases"],
                    "false_alarms": sum(t.false_alarms for t in mine),
                }
                for o in sorted({t.obj for t in rows})
                for mine in [[t for t in rows if t.obj == o]]
            },
        }

    def overall(self, imperfection: str = "none") -> dict[str, dict[str, Any]]:
        """Per frame rate, every engine and object together, through one imperfection."""
        overall: dict[str, dict[str, Any]] = {}
        for r in self.rates_hz:
            mine = [t for t in self.trials if t.rate_hz == r and t.imperfection == imperfection]
            slipping = [t for t in mine if t.kind != "roll"]
            rolling = [t for t in mine if t.kind == "roll"]
            sliding = [t for t in mine if t.kind == "slide"]
            fa = sum(t.false_alarms > 0 for t in rolling) / len(rolling) if rolling else 0.0
            overall[f"{r:g}"] = {
                "detectable": _phase_stats(slipping, DETECTABLE),
                "all_kinds": _phase_stats(slipping, None),
                "detectable_by_speed": _by_speed(slipping),
                "detectable_from_pitch": _from_pitch(slipping),
                "roll_false_alarm_trial_rate": fa,
                "roll_false_alarms_per_s": sum(t.false_alarms for t in rolling)
                / max(1e-9, sum(t.contact_s for t in rolling)),
                "sliding_identified": sum(t.identified in OBJECTS for t in sliding),
                "partial": _verdicts([t for t in mine if t.kind == "partial"]),
                "partial_without_slip": _verdicts(
                    [t for t in mine if t.kind == "partial"], without=True
                ),
            }
        return overall

    def to_json(self) -> dict[str, Any]:
        """Summaries per engine and kind, the acceptance checks, and every trial.

        The summaries, ``overall`` and the acceptance are those of the frames as
        the array gives them (imperfection ``"none"``); ``overall_imperfect``
        holds ``overall`` through each other imperfection.
        """
        clean = [t for t in self.trials if t.imperfection == "none"]
        summaries = [
            self.summary(e, r, k)
            for e in self.engines
            for r in self.rates_hz
            for k in TRIAL_KINDS
            if any(t.engine == e and t.kind == k and t.rate_hz == r for t in clean)
        ]
        overall = self.overall()
        return {
            "experiment": "slip",
            "n_trials": self.n_trials,
            "mujoco_trials": self.mujoco_trials,
            "rates_hz": list(self.rates_hz),
            "gt_slip_mm_s": GT_SLIP_MM_S,
            "latency_s": LATENCY_S,
            "engines": list(self.engines),
            "skipped": dict(self.skipped),
            "detectable_kinds": list(DETECTABLE),
            "imperfections": list(self.imperfections),
            "overall": overall,
            "overall_imperfect": {f: self.overall(f) for f in self.imperfections if f != "none"},
            "summaries": summaries,
            "acceptance": {f"{r}": acceptance_checks(o) for r, o in overall.items()},
            "trials": [
                {
                    "engine": t.engine,
                    "imperfection": t.imperfection,
                    "rate_hz": t.rate_hz,
                    "kind": t.kind,
                    "object": t.obj,
                    "trial": t.trial,
                    "identified": t.identified,
                    "reason": t.reason,
                    "identified_without_slip": t.identified_without,
                    "phases": [
                        {"kind": k, "latency_s": x, "speed_mm_s": round(v, 3), "pitch_s": p}
                        for (k, x), v, p in zip(
                            t.phases,
                            t.phase_speeds_mm_s,
                            t.pitch_s or (None,) * len(t.phases),
                            strict=True,
                        )
                    ],
                    "false_alarms": t.false_alarms,
                }
                for t in self.trials
            ],
        }
