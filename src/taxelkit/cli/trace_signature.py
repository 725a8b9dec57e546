"""``taxelkit trace`` with the order-aware signature rules, and the trace command's output."""

from __future__ import annotations

import json
from typing import Any

import click
import numpy as np

from taxelkit.errors import InputError

__all__ = [
    "SIGNATURE_RULE_NAMES",
    "check_signature_options",
    "echo_trace",
    "signature_trace_doc",
]

#: The signature rules ``trace --rule`` accepts (``taxelkit.memory.SIGNATURE_RULES``;
#: written out so that the CLI starts without importing the memory).
SIGNATURE_RULE_NAMES: tuple[str, ...] = ("signature", "signature-dense")


def check_signature_options(memory: object, plot: object, view_wanted: bool) -> None:
    """Refuse what the signature rules cannot do yet, in one line."""
    if memory is not None:
        raise InputError(
            "--rule signature and signature-dense recall from the built-in shapes only "
            "(memory files hold chain codes); drop --memory or choose a chain-code rule"
        )
    if plot is not None or view_wanted:
        raise InputError(
            "--plot and --view draw chain-code recall curves; choose a chain-code rule"
        )


def signature_trace_doc(trace: Any, rule: str) -> dict[str, Any]:
    """The JSON of ``trace`` for a signature rule: verdict, scores and recall curve.

    The memory holds the five reference traces' signatures; the curve is
    evaluated at :data:`~taxelkit.memory.contour_recall.DEFAULT_S_GRID` on
    prefixes of the trace coded from the part traced alone. The scores are
    not calibrated probabilities: ``probabilities`` and ``unknown`` are None.
    """
    from taxelkit.experiments.capacity_rules import prefix_moves
    from taxelkit.experiments.paper000_common import reference_traces
    from taxelkit.memory.contour_recall import DEFAULT_S_GRID
    from taxelkit.memory.open_set import decided_at_s
    from taxelkit.memory.signature_memory import SignatureMemory
    from taxelkit.memory.turning_signature import tangent_signature
    from taxelkit.world.relief import SHAPE_NAMES

    mem = SignatureMemory.from_moves(
        SHAPE_NAMES, [t.moves_mm for t in reference_traces()], rule=rule
    )
    grid = [float(s) for s in DEFAULT_S_GRID]
    res = mem.recall([tangent_signature(prefix_moves(trace.moves_mm, s), closed=False)
                      for s in grid])  # fmt: skip

    def margin(k: int) -> float | None:
        value = float(res.margin[k])
        return round(value, 6) if np.isfinite(value) else None

    return {
        "trajectory_mm": trace.points_mm.round(4).tolist(),
        "closed": trace.closed,
        "stop_reason": trace.stop_reason,
        "recognised": res.recognised[-1],
        "verdict": res.verdicts[-1],
        "margin": margin(-1),
        "correlations": {n: float(c) for n, c in zip(res.names, res.scores[-1], strict=True)},
        "recall_curve": [
            {
                "s": s,
                "scores": {n: float(c) for n, c in zip(res.names, row, strict=True)},
                "margin": margin(k),
                "verdict": v,
            }
            for k, (s, row, v) in enumerate(zip(grid, res.scores, res.verdicts, strict=True))
        ],
        "rule": rule,
        "probabilities": None,
        "unknown": None,
        "open_set_verdict": None,
        "decided_at_s": decided_at_s(grid, res.verdicts),
        "calibrated": False,
    }


def echo_trace(tr: Any, doc: dict[str, Any], as_json: bool) -> None:
    """Print the trace's result: one JSON object, or the verdict and the scores."""
    if as_json:
        click.echo(json.dumps(doc))
        return
    click.echo(
        f"traced {tr.n_sections} sections ({'closed' if tr.closed else tr.stop_reason}); "
        f"recognised: {doc['verdict']}"
    )
    for n, c in sorted(doc["correlations"].items(), key=lambda kv: -kv[1]):
        click.echo(f"  {n:16s} c = {c:+.3f}")
