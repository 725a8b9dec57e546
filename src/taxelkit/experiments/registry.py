"""Registry of reproducible experiments: name -> runner returning a result with ``to_json()``."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

from taxelkit.errors import InputError

__all__ = ["EXPERIMENTS", "Experiment", "ExperimentResult", "get_experiment"]


class ExperimentResult(Protocol):
    """What every experiment returns."""

    def to_json(self) -> dict[str, Any]:
        """The experiment's figures as plain JSON types."""
        ...


@dataclass(frozen=True)
class Experiment:
    """A registered experiment.

    Attributes
    ----------
    name : str
        Registry name (``taxelkit reproduce NAME``).
    title : str
        One line.
    run : callable
        ``run(*, seed, progress, ...) -> ExperimentResult``.
    unit : str
        What one step of ``progress(done, total)`` counts (``"trial"``, ``"shape"``).
    trials : int or None
        ``n_trials`` the experiment runs unless told otherwise (the setting of
        the committed results, ``docs/results/``); None if it takes no
        ``n_trials`` (a fixed set of cases).
    workers : bool
        Whether ``run`` takes ``workers`` (local worker processes).
    scheduler : bool
        Whether ``run`` takes ``scheduler`` (a Dask scheduler address).
    """

    name: str
    title: str
    run: Callable[..., ExperimentResult]
    unit: str = "step"
    trials: int | None = None
    workers: bool = False
    scheduler: bool = False


def _fig7(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.fig7 import run_fig7

    return run_fig7(**kw)


def _fig8(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.fig8 import run_fig8

    return run_fig8(**kw)


def _fig9(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.fig9 import run_fig9

    return run_fig9(**kw)


def _fig9_readings(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.fig9_readings import run_fig9_readings

    return run_fig9_readings(**kw)


def _open_set(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.open_set import run_open_set

    return run_open_set(**kw)


def _recall_vs_s(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.recall_vs_s import run_recall_vs_s

    return run_recall_vs_s(**kw)


def _trace_robustness(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.trace_robustness import run_trace_robustness

    return run_trace_robustness(**kw)


def _capacity(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.capacity import run_capacity

    return run_capacity(**kw)


def _cylinder(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.paper001 import run_cylinder

    return run_cylinder(**kw)


def _smart_sensor(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.paper001 import run_smart_sensor

    return run_smart_sensor(**kw)


def _tacteme_table(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.paper001 import run_tacteme_table

    return run_tacteme_table(**kw)


def _contact_classes(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.contact_classes import run_contact_classes

    return run_contact_classes(**kw)


def _multi_object(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.multi_object import run_multi_object

    return run_multi_object(**kw)


def _slip(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.slip import run_slip

    return run_slip(**kw)


def _slip_heldout(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.slip_heldout import run_slip_heldout

    return run_slip_heldout(**kw)


def _new_objects(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.new_objects import run_new_objects

    return run_new_objects(**kw)


def _new_objects_heldout(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.new_objects_heldout import run_new_objects_heldout

    return run_new_objects_heldout(**kw)


def _robustness(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.robustness import run_robustness

    return run_robustness(**kw)


def _robustness_heldout(**kw: Any) -> ExperimentResult:
    from taxelkit.experiments.robustness_heldout import run_robustness_heldout

    return run_robustness_heldout(**kw)


#: All registered experiments, in the order ``reproduce all`` runs them.
EXPERIMENTS: dict[str, Experiment] = {
    e.name: e
    for e in (
        Experiment("fig7", "Paper 000 Fig. 7: tracing straight 50 um edges", _fig7, "trace"),
        Experiment("fig8", "Paper 000 Fig. 8: tracing the five 200 um specimens", _fig8, "shape"),
        Experiment("fig9", "Paper 000 Fig. 9: correlation against arc length", _fig9, "shape"),
        Experiment(
            "fig9-readings",
            "Paper 000 Fig. 9: readings of the faithful code and rule",
            _fig9_readings,
            "reading",
        ),
        Experiment(
            "recall-vs-s",
            "Paper 000: recognition rate against s",
            _recall_vs_s,
            "trial",
            trials=50,
            workers=True,
        ),
        Experiment(
            "open-set",
            "Paper 000 beyond five shapes: unknown shapes, calibrated confidence",
            _open_set,
            "trace",
            trials=20,
            workers=True,
        ),
        Experiment(
            "trace-robustness",
            "Paper 000 tracer on rough, tilted, resized and re-entrant specimens",
            _trace_robustness,
            "specimen",
            trials=2,
            workers=True,
        ),
        Experiment(
            "capacity",
            "Paper 000 beyond five shapes: recall against stored shapes and s, every rule",
            _capacity,
            "trace",
            trials=2,
            workers=True,
            scheduler=True,
        ),
        Experiment(
            "contact-classes", "Paper 001 Level 2: hand-set and trained", _contact_classes, "stage"
        ),
        Experiment("cylinder", "Paper 001 Fig. 3: the rolling cylinder", _cylinder, "roll"),
        Experiment(
            "smart-sensor",
            "Paper 001: randomised trials, confusion",
            _smart_sensor,
            "trial",
            trials=100,
            workers=True,
        ),
        Experiment(
            "tacteme-table",
            "Paper 001 Table 1 checked by simulation",
            _tacteme_table,
            "trial",
            trials=50,
            workers=True,
        ),
        Experiment(
            "robustness",
            "Smart sensor: engines x rates x sensor imperfections x objects",
            _robustness,
            "motion",
            trials=50,
            workers=True,
            scheduler=True,
        ),
        Experiment(
            "robustness-heldout",
            "Smart sensor: the robustness sweep on a seed its thresholds were not set on",
            _robustness_heldout,
            "motion",
            trials=50,
            workers=True,
            scheduler=True,
        ),
        Experiment(
            "multi-object",
            "Smart sensor: two and three objects on the array at once, one verdict per track",
            _multi_object,
            "scene",
            trials=100,
            workers=True,
            scheduler=True,
        ),
        Experiment(
            "slip",
            "Smart sensor: slip found from the frames, recognition under partial slip",
            _slip,
            "motion",
            trials=30,
            workers=True,
        ),
        Experiment(
            "slip-heldout",
            "Smart sensor: the slip experiment on a seed its thresholds were not set on",
            _slip_heldout,
            "motion",
            trials=30,
            workers=True,
        ),
        Experiment(
            "new-objects",
            "Smart sensor: the six objects and four learnt from meshes, confusion",
            _new_objects,
            "trial",
            trials=100,
            workers=True,
        ),
        Experiment(
            "new-objects-heldout",
            "Smart sensor: new-objects on a seed its rules were not set on",
            _new_objects_heldout,
            "trial",
            trials=100,
            workers=True,
        ),
    )
}


def get_experiment(name: str) -> Experiment:
    """Look up an experiment; unknown names raise InputError listing the known ones."""
    try:
        return EXPERIMENTS[name]
    except KeyError:
        known = ", ".join([*EXPERIMENTS, "all"])
        raise InputError(f"unknown experiment {name!r}; known: {known}") from None
