"""Markdown of the paper-000 experiments' results.

fig9, fig9-readings, open-set, recall-vs-s and trace-robustness; rendered into
the README's result blocks by :mod:`taxelkit.experiments.report`.
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = [
    "fig9_markdown",
    "fig9_readings_markdown",
    "open_set_markdown",
    "recall_vs_s_markdown",
    "trace_robustness_markdown",
]


def _from_s(found: dict[str, float | None]) -> str:
    return ", ".join(f"{n} {'never' if s is None else f'{s:.2f}'}" for n, s in found.items())


def _ties_text(s: list[float], ties: list[int]) -> str:
    tied = [f"{v:.2f} ({t})" for v, t in zip(s, ties, strict=True) if t]
    return "none" if not tied else ", ".join(tied)


def fig9_markdown(doc: dict[str, Any]) -> str:
    """The ``fig9`` rows of the paper-000 table: from which ``s``, ties and margins."""
    paper = doc["paper_recognised_from_s"]
    lines = ["| `fig9` (one trace per shape) | taxelkit | paper |", "| --- | --- | --- |"]
    for part in (doc, doc["faithful"]):
        final_margin = {n: m[-1] for n, m in part["winning_margin"].items()}
        undecided = {n: v for n, v in part["final_verdicts"].items() if v != n}
        lines += [
            f"| {part['rule']}: alone top-ranked from s = | {_from_s(part['recognised_from_s'])} "
            f"| triangle {paper['triangle']}; star vs circle until {paper['star']} |",
            f"| {part['rule']}: ties at the top, s (shapes tied) | "
            f"{_ties_text(part['s'], part['ties_per_s'])} | n/a |",
            f"| {part['rule']}: full contour | margins "
            + ", ".join(f"{n} {m:.3f}" for n, m in final_margin.items())
            + ("; " + "; ".join(f"{n}: {v}" for n, v in undecided.items()) if undecided else "")
            + " | n/a |",
        ]
    return "\n".join(lines)


def fig9_readings_markdown(doc: dict[str, Any]) -> str:
    """The readings of Fig. 9: the best five and whether any reproduces the figure."""
    lines = [
        ("Some reading reproduces" if doc["reproduced"] else "No reading reproduces")
        + f" Fig. 9's shape ({len(doc['readings'])} readings tried, "
        "`docs/results/fig9-readings.json` and `.png`). Best first:",
        "",
        "| reading | d_j | criteria met (rising, triangle, star, full) | triangle / star "
        "from s | star-circle gap before 0.66 | shapes right at s = 1 |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for r in doc["readings"][:5]:
        c = r["criteria"]
        marks = ", ".join("yes" if c[k] else "no" for k in ("rising", "triangle", "star", "full"))
        f = r["recognised_from_s"]
        lines.append(
            f"| {r['label']} | {', '.join(f'{v:g}' for v in r['d_j'])} | {r['criteria_met']}/4 "
            f"({marks}) | {f['triangle']} / {f['star']} | {r['star_circle_gap_before_0.66']} | "
            f"{r['recognised_at_full_contour']}/5 |"
        )
    return "\n".join(lines)


def _reasons(doc: dict[str, Any], split: str) -> str:
    counts = doc.get("unknown_reasons", {}).get(split, {})
    return f"{counts.get('score', 0)} / {counts.get('compactness', 0)}"


def open_set_markdown(doc: dict[str, Any]) -> str:
    """The ``open-set`` results: unknown rate, in-set recognition, ECE, against the targets."""
    ins, out, rel, tgt = doc["in_set"], doc["out_of_set"], doc["reliability"], doc["targets"]
    missed = {
        k: ", ".join(f"{v} {n}" for v, n in counts.items() if v != "unknown")
        for k, counts in out["per_kind"].items()
        if set(counts) != {"unknown"}
    }
    decided = [v for vals in ins["decided_at_s"].values() for v in vals if v is not None]
    cal = doc["calibration"]
    rows = [
        "| measure | taxelkit | target |",
        "| --- | --- | --- |",
        f'| out-of-set traces answered "unknown" ({len(out["kinds"])} kinds, {out["n"]} '
        f"traces) | {100 * out['unknown_rate']:.1f} %"
        + (
            " (named instead: " + "; ".join(f"{k}: {v}" for k, v in missed.items()) + ")"
            if missed
            else ""
        )
        + f" | >= {100 * tgt['unknown_rate']:.0f} % |",
        f"| in-set traces recognised at full contour ({ins['n']}) | "
        f"{100 * ins['recognised']:.1f} % ({ins['wrong_names']} wrong names, {ins['unknown']} "
        f"unknown, {ins['undecided']} undecided) | >= {100 * tgt['recognised']:.0f} %, 0 wrong |",
        f"| unknown by score / by compactness (out-of-set; in-set) | "
        f"{_reasons(doc, 'out')}; {_reasons(doc, 'in')} | n/a |",
        f"| expected calibration error, every s | {rel['ece']:.3f} | <= {tgt['ece']} |",
        f"| decided from s (in-set, median) | "
        f"{np.median(decided) if decided else float('nan'):.2f} | n/a |",
        f"| fitted: temperature, least top score, compactness tolerance | "
        f"{cal['temperature']:.4f}, {cal['min_top_score']:.3f}, "
        f"{cal['compactness_tolerance']:.3f} | held-out traces |",
    ]
    return "\n".join(rows)


def recall_vs_s_markdown(doc: dict[str, Any]) -> str:
    """The ``recall-vs-s`` rows: percent right per shape and s, ties per s, both rules."""
    s = doc["s"]
    head = "| rule | shape | " + " | ".join(f"s = {v:g}" for v in s) + " |"
    lines = [
        f"{doc['n_trials_per_shape']} random poses per shape (rotation, translation, start "
        "point); percent recognised (a tie is never right), in brackets the traces ending in a "
        "tie at the top:",
        "",
        head,
        "| --- | --- |" + " --- |" * len(s),
    ]
    for key in ("improved", "faithful"):
        part = doc[key]
        for name, fractions in part["fraction_correct"].items():
            ties = part["ties"][name]
            cells = [
                f"{100 * f:.0f}" + (f" ({t})" if t else "")
                for f, t in zip(fractions, ties, strict=True)
            ]
            lines.append(f"| {part['rule']} | {name} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def trace_robustness_markdown(doc: dict[str, Any]) -> str:
    """The ``trace-robustness`` experiment as a README table and the acceptance checks."""

    def cell(s: dict[str, Any]) -> str:
        if s["error_mean_mm"] is None:
            err = "n/a (no edge found in a search)"
        else:
            err = f"{s['error_mean_mm']:.2f} (worst {s['error_mean_worst_mm']:.2f})"
        known = s["n_recognisable"]
        named = f", named {s['recognised']}/{known}" if known else ""
        return f"{err}; closed {s['closed']}/{s['n']}{named}"

    lines = [
        f"{doc['n_trials_per_shape']} random poses per shape and condition; each entry: mean "
        "tracing error in mm (the worst trace's mean), loops closed, stored shapes named right "
        "(default recogniser). `faithful`: the paper's fixed 10 um dead zone; `robust`: the "
        "default, noise-adaptive.",
        "",
        "| condition | faithful | robust |",
        "| --- | --- | --- |",
    ]
    for c in doc["conditions"]:
        row = doc["summary"][c["name"]]
        lines.append(f"| {c['name']} | {cell(row['faithful'])} | {cell(row['robust'])} |")
    holds = doc["acceptance"]["holds"]
    checks = ", ".join(
        f"{name}: {'holds' if ok else 'not run' if ok is None else 'fails'}"
        for name, ok in holds["robust"].items()
    )
    lines += ["", f"Acceptance ({doc['acceptance']['target']}), robust tracer: {checks}."]
    return "\n".join(lines)
