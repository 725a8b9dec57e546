"""``taxelkit trace`` and ``memorise``: the paper-000 system."""

from __future__ import annotations

import io
from pathlib import Path
from typing import Any

import click
import numpy as np

from taxelkit.cli.common import (
    check_figure_suffix,
    check_outputs,
    save_figure,
    specimen_from_options,
)
from taxelkit.cli.options import (
    COORDINATE_MM,
    RECALL_RULE,
    SEED,
    TRACE_RULE,
    relief_options,
)
from taxelkit.cli.trace_signature import (
    SIGNATURE_RULE_NAMES,
    check_signature_options,
    echo_trace,
    signature_trace_doc,
)
from taxelkit.cli.view import ViewTarget, view_options, with_view
from taxelkit.errors import InputError

__all__ = ["memorise", "trace"]


def _load_memory(path: Path | None, rule: str) -> Any:
    from taxelkit.experiments.paper000_common import (
        FAITHFUL,
        IMPROVED,
        RecallSetup,
        reference_memory,
    )
    from taxelkit.memory.recall_rules import get_recall_rule

    get_recall_rule(rule)  # validates the name
    if path is None:
        if rule == "hebbian":
            return reference_memory(FAITHFUL)
        return reference_memory(RecallSetup(rule, rule, IMPROVED.phases, IMPROVED.config))

    from taxelkit.io.memory_file import read_memory

    return read_memory(path).with_rule(rule)


def _indistinguishable(mem: Any) -> list[tuple[str, ...]]:
    """Groups of stored shapes that recall of their own codes leaves tied (sorted names)."""
    result = mem.recall(mem.patterns)
    return sorted({names for names in result.tied if len(names) > 1})


def _open_set_fields(
    tr: Any, mem: Any, *, rule: str, built_in: bool, phases: int
) -> dict[str, Any]:
    """``probabilities``, ``unknown``, ``decided_at_s`` and the open-set verdict of a trace.

    The calibration is the one fitted by ``taxelkit reproduce open-set`` for
    the built-in memory and the default rule; with another rule the
    probabilities are not calibrated (``calibrated`` false), and with a user
    memory the compactness test is skipped (its shapes' references are unknown).
    """
    import dataclasses

    from taxelkit.experiments.open_set import REFERENCE_CALIBRATION, judge_trace

    cal = REFERENCE_CALIBRATION
    if not built_in:
        cal = dataclasses.replace(cal, reference_compactness=())
    verdict, decided = judge_trace(tr, mem, cal, phases=phases)
    probs = verdict.probabilities[-1]
    return {
        "probabilities": {n: float(p) for n, p in zip(verdict.names, probs, strict=True)},
        "unknown": bool(verdict.unknown[-1]),
        "open_set_verdict": verdict.verdicts[-1],
        "decided_at_s": decided,
        "calibrated": rule == "matched",
    }


@click.command()
@relief_options
@click.option(
    "--start-mm",
    type=COORDINATE_MM,
    default=None,
    help="Where the sensor first meets the edge X,Y, mm (default: searched from the centre).",
)
@click.option(
    "--rule",
    type=TRACE_RULE,
    default="matched",
    show_default=True,
    help="Recall rule: hebbian is the paper's (12 x 4 code); the others use a 24 x 8 code; "
    "signature and signature-dense use the order-aware tangent signature (built-in shapes).",
)
@click.option(
    "--memory",
    type=click.Path(path_type=Path),
    default=None,
    help="Memory file from 'taxelkit memorise' (default: the five built-in shapes).",
)
@click.option("--seed", type=SEED, default=0, show_default=True, help="Seed of the sensor noise.")
@click.option(
    "--plot",
    type=click.Path(path_type=Path),
    default=None,
    help="Also draw the trace and the recall curve to this figure (.png, .pdf, .svg, .jpg).",
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@click.option("--force", is_flag=True, help="Overwrite an existing --plot or --save-view file.")
@view_options
def trace(
    shape: str | None,
    specimen: Path | None,
    rotate_deg: float,
    offset_mm: tuple[float, float],
    diameter_mm: float,
    step_height_um: float,
    start_mm: tuple[float, float] | None,
    rule: str,
    memory: Path | None,
    seed: int,
    plot: Path | None,
    as_json: bool,
    force: bool,
    view: ViewTarget,
) -> None:
    """Trace a relief specimen's edge and recognise its shape (paper 000).

    Recognition uses only the trajectory the tracer produced, never the
    specimen. With --view, --view-url or --save-view the probe path, the
    estimated edges and the recall curve are logged to rerun, section by
    section (docs/viewer.md).
    """
    from taxelkit.memory.contour_recall import recall_curve
    from taxelkit.motion.probe import SimulatedProbe
    from taxelkit.tracing.tracer import find_edge, trace_edge

    if plot is not None:
        check_figure_suffix(plot)
        check_outputs([plot], force)
    if view.save_path is not None:
        check_outputs([view.save_path], force)
    by_signature = rule in SIGNATURE_RULE_NAMES
    if by_signature:
        check_signature_options(memory, plot, view.wanted)
    relief, centre = specimen_from_options(
        shape, specimen, rotate_deg, offset_mm, diameter_mm, step_height_um
    )
    mem: Any = None if by_signature else _load_memory(memory, rule)
    probe = SimulatedProbe(relief, rng=seed)
    start = start_mm
    if start is None:
        start = tuple(find_edge(probe, centre))
    tr = trace_edge(probe, start)
    if by_signature:
        echo_trace(tr, signature_trace_doc(tr, rule), as_json)
        return
    phases = 1 if rule == "hebbian" else 2
    curve = recall_curve(tr.moves_mm, mem, phases=phases)
    final = {n: float(c) for n, c in zip(curve.names, curve.correlations[-1], strict=True)}
    open_set = _open_set_fields(tr, mem, rule=rule, built_in=memory is None, phases=phases)
    doc = {
        "trajectory_mm": tr.points_mm.round(4).tolist(),
        "closed": tr.closed,
        "stop_reason": tr.stop_reason,
        "recognised": curve.recognised[-1],
        "verdict": curve.verdicts[-1],
        "margin": float(curve.margin[-1]) if np.isfinite(curve.margin[-1]) else None,
        "correlations": final,
        "recall_curve": curve.to_json(),
        "rule": rule,
        **open_set,
    }
    if view.wanted:
        from taxelkit.viewer.trace_view import view_trace

        def log(where: ViewTarget) -> int:
            return view_trace(
                tr, curve, save_path=where.save_path, spawn=where.spawn, connect_url=where.url
            )

        with_view(view, log, force=force)
    if plot is not None:
        from taxelkit.plotting.paper000 import plot_trace_recall

        save_figure(plot_trace_recall(tr, curve, rule=rule), plot, force=force)
    echo_trace(tr, doc, as_json)


@click.command()
@click.option(
    "--specimen",
    "specimens",
    type=click.Path(path_type=Path),
    multiple=True,
    help="Heightmap .npz to trace and store (repeatable).",
)
@click.option(
    "--name", "names", multiple=True, help="Name for each --specimen, in order (repeatable)."
)
@click.option(
    "--base",
    type=click.Path(path_type=Path),
    default=None,
    help="Start from this memory file instead of the five built-in shapes.",
)
@click.option(
    "--rule",
    type=RECALL_RULE,
    default="matched",
    show_default=True,
    help="Recall rule the memory is stored for (must match 'trace --rule').",
)
@click.option("--seed", type=SEED, default=0, show_default=True, help="Seed of the sensor noise.")
@click.option("--out", type=click.Path(path_type=Path), required=True, help="Memory file (.npz).")
@click.option("--force", is_flag=True, help="Overwrite an existing --out file.")
def memorise(
    specimens: tuple[Path, ...],
    names: tuple[str, ...],
    base: Path | None,
    rule: str,
    seed: int,
    out: Path,
    force: bool,
) -> None:
    """Trace your own specimens and save a memory that 'taxelkit trace --memory' recalls from."""
    from taxelkit.io.atomic import atomic_write
    from taxelkit.memory.contour_recall import memorise_contours
    from taxelkit.motion.probe import SimulatedProbe
    from taxelkit.tracing.tracer import find_edge, trace_edge
    from taxelkit.world.relief import load_heightmap

    if out.suffix.lower() != ".npz":
        raise InputError(f"--out must end in .npz, got {out.name!r}")
    if len(specimens) != len(names):
        raise InputError(f"give one --name per --specimen ({len(specimens)} vs {len(names)})")
    check_outputs([out], force)
    mem = _load_memory(base, rule)
    phases = 1 if rule == "hebbian" else 2
    for path, name in zip(specimens, names, strict=True):
        relief = load_heightmap(path)
        x0, x1, y0, y1 = relief.extent_mm
        probe = SimulatedProbe(relief, rng=seed)
        tr = trace_edge(probe, find_edge(probe, ((x0 + x1) / 2, (y0 + y1) / 2)))
        if not tr.closed:
            click.echo(f"warning: the trace of {path} did not close ({tr.stop_reason})", err=True)
        code = memorise_contours(
            [name], [tr.moves_mm], rule=rule, phases=phases, config=mem.config
        ).patterns[0]
        mem = mem.with_pattern(name, code)
        click.echo(f"stored {name!r} from {path} ({tr.n_sections} sections)")

    for names_alike in _indistinguishable(mem):
        click.echo(
            f"warning: this memory cannot tell apart {' and '.join(names_alike)} "
            "(their codes tie at the top when recalled from each other)",
            err=True,
        )

    def writer(tmp: Path) -> None:
        buf = io.BytesIO()
        np.savez(buf, **mem.to_arrays())
        tmp.write_bytes(buf.getvalue())

    atomic_write(out, writer, force=force)
    click.echo(f"wrote {out}: {', '.join(mem.names)}")
