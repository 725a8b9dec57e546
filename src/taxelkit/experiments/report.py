"""Markdown tables of experiment results, and the README blocks regenerated from them.

The README's results are not typed by hand: a block between
``<!-- results:NAME -->`` and ``<!-- /results:NAME -->`` is rendered from
``docs/results/NAME.json`` by :func:`render_block`, and
``taxelkit reproduce ... --readme README.md`` rewrites every block it has
results for. A test checks that the committed README matches the committed
JSON.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from typing import Any

from taxelkit.errors import InputError

__all__ = [
    "BLOCKS",
    "paper001_markdown",
    "render_block",
    "robustness_markdown",
    "trace_robustness_markdown",
    "update_blocks",
]


def _pct(x: float | None) -> str:
    return "n/a" if x is None else f"{100 * x:.1f}"


def robustness_markdown(doc: dict[str, Any]) -> str:
    """The robustness experiment as a README section (tables and headline figures)."""
    rates = doc["rates_hz"]
    rows = [*doc["faults"], doc["lift_off"]]
    summary = {(s["engine"], s["rate_hz"], s["fault"]): s for s in doc["summary"]}
    head = "| engine | imperfection | " + " | ".join(f"{r:g} frames/s" for r in rates) + " |"
    lines = [head, "| --- | --- |" + " --- |" * len(rates)]
    for e in doc["engines"]:
        for f in rows:
            cells = []
            for r in rates:
                s = summary.get((e, r, f))
                cells.append(
                    ""
                    if s is None
                    else f"{_pct(s['accuracy'])} ({s['wrong']}) / "
                    f"{_pct(s['faithful_accuracy'])} ({s['faithful_wrong']})"
                )
            lines.append(f"| {e} | {f} | " + " | ".join(cells) + " |")
    in_set = [c for c in doc["cells"] if c["object"] != "sliding"]
    fast = [c for c in in_set if c["rate_hz"] >= 20.0]
    slow = [c for c in in_set if c["rate_hz"] < 20.0]
    ok_fast = sum(c["accuracy"] >= 0.98 for c in fast)
    worst = max((c["wrong"] / c["n"] for c in in_set), default=0.0)
    o, sl = doc["overall"], doc["sliding"]
    text = [
        f"{doc['n_trials']} randomised trials per cell (engine x rate x imperfection x object); "
        "each entry is the accuracy over the six objects in % and, in brackets, the count of "
        "wrong identities: the robust default / paper 001's pipeline as printed, on the same "
        "frames.",
        "",
        *lines,
        "",
        f"- All {o['n']} in-set trials: {_pct(o['accuracy'])} % identified, {o['wrong']} wrong "
        f"identities, {o['undecided']} undecided, {o['unknown']} unknown; the worst cell has "
        f"{100 * worst:.1f} % wrong identities.",
        f"- Cells (one object, engine, rate and imperfection) at 20 frames/s and above with "
        f"accuracy >= 0.98: {ok_fast} of {len(fast)}; at 5 frames/s: "
        f"{sum(c['accuracy'] >= 0.98 for c in slow)} of {len(slow)}.",
        f"- Sliding: {sl['identified']} of {sl['n']} trials given an identity (paper 001's "
        f"pipeline as printed: {sl['faithful_wrong']}).",
    ]
    arrays = doc.get("arrays", {}).get("summary", [])
    if arrays:
        text += [
            "",
            f"Other arrays at {doc['arrays']['rate_hz']:g} frames/s "
            "(accuracy over the six objects in %, wrong identities in brackets; sliding trials "
            "given an identity):",
            "",
            "| array | engine | clean | every imperfection | sliding identified |",
            "| --- | --- | --- | --- | --- |",
        ]
        by = {(s["array"], s["engine"], s["fault"]): s for s in arrays}
        for a in sorted({s["array"] for s in arrays}, key=lambda x: int(x.split("x")[0])):
            for e in doc["engines"]:
                clean, bad = by.get((a, e, "none")), by.get((a, e, "all"))
                if clean is None or bad is None:
                    continue
                lines_a = (
                    f"| {a} mm | {e} | {_pct(clean['accuracy'])} ({clean['wrong']}) | "
                    f"{_pct(bad['accuracy'])} ({bad['wrong']}) | "
                    f"{clean['sliding_identified'] + bad['sliding_identified']} |"
                )
                text.append(lines_a)
    return "\n".join(text)


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


def paper001_markdown(docs: dict[str, dict[str, Any]]) -> str:
    """Paper 001's results table from ``contact-classes``, ``cylinder``, ``smart-sensor``
    and ``tacteme-table``."""
    cc, cyl = docs["contact-classes"], docs["cylinder"]
    ss, tt = docs["smart-sensor"], docs["tacteme-table"]
    rolls = cc["rolls"]["scores"]
    confusion = ss["confusion"]
    wrong_pairs = [
        f"a {obj} read as a {out}"
        for obj, row in confusion.items()
        for out, count in row.items()
        if out not in (obj, "unknown", "undecided") and count
    ]
    fig3 = ", ".join(t["name"] for t in cyl["tactemes"])
    robust3 = ", ".join(t["name"] for t in cyl["robust"]["tactemes"])
    n_rolls = len(tt["produced"]) * tt["n_trials_per_object"]
    rows = [
        "| experiment | taxelkit | paper |",
        "| --- | --- | --- |",
        f"| `contact-classes` (Level 2), pressed contacts | held-out accuracy "
        f"{cc['hand_set']['accuracy']:.3f} with hand-set weights, "
        f"{cc['trained']['accuracy']:.3f} trained by back-propagation ({cc['samples']} "
        "simulated contacts) | weights set by hand |",
        f"| `contact-classes`, frames of rolls ({', '.join(cc['rolls']['engines'])}; every "
        f"imperfection) | hand-set {rolls['hand_set']['all']['accuracy']:.3f}, trained on "
        f"rolls {rolls['trained_on_rolls']['all']['accuracy']:.3f} "
        f"({cc['rolls']['held_out_frames']} held-out frames) | n/a |",
        f"| `cylinder` (Fig. 3), paper's pipeline as printed | {fig3}: identified as the "
        f"{cyl['identified']} (robust pipeline: {robust3}, {cyl['robust']['identified']}) | "
        "AC, PC, LC, LCMP, cylinder |",
        f"| `smart-sensor`: {ss['member_trials']} randomised trials (sizes +-30 %, noise on, "
        f"20 frames/s) | accuracy {ss['accuracy']:.3f}; {ss['wrong']} wrong"
        + (f" ({'; '.join(wrong_pairs)})" if wrong_pairs else "")
        + f", {ss['unknown']} unknown, {ss['undecided']} undecided | 83 % (3 tests x 6 objects) |",
        f"| `smart-sensor`: {ss['sliding_trials']} sliding trials | {ss['sliding_identified']} "
        'given an identity | sliding ends in "unknown" |',
        f"| `tacteme-table`: tactemes produced in simulation vs the table | "
        f"{len(tt['violations'])} violations in {n_rolls} rolls | (Table 1 marks lost in our "
        "copy) |",
    ]
    return "\n".join(rows)


#: Blocks of the README rendered from results: name -> (experiments it needs, renderer).
BLOCKS: dict[str, tuple[tuple[str, ...], Callable[[dict[str, dict[str, Any]]], str]]] = {
    "robustness": (("robustness",), lambda docs: robustness_markdown(docs["robustness"])),
    "trace-robustness": (
        ("trace-robustness",),
        lambda docs: trace_robustness_markdown(docs["trace-robustness"]),
    ),
    "paper001": (
        ("contact-classes", "cylinder", "smart-sensor", "tacteme-table"),
        paper001_markdown,
    ),
}


def render_block(name: str, docs: dict[str, dict[str, Any]]) -> str:
    """The README block ``name`` from the JSON documents of the experiments it needs."""
    if name not in BLOCKS:
        raise InputError(f"no README block for {name!r}; known: {', '.join(BLOCKS)}")
    return BLOCKS[name][1](docs)


def update_blocks(text: str, docs: dict[str, dict[str, Any]]) -> str:
    """Rewrite the ``<!-- results:NAME -->`` blocks of ``text`` whose experiments ``docs`` has.

    Parameters
    ----------
    text : str
        The README.
    docs : dict of str to dict
        JSON documents by experiment name.

    Raises
    ------
    InputError
        If a block to rewrite has no closing marker.
    """
    for name, (needs, _) in BLOCKS.items():
        if not all(n in docs for n in needs):
            continue
        start, end = f"<!-- results:{name} -->", f"<!-- /results:{name} -->"
        if start not in text:
            continue
        if end not in text:
            raise InputError(f"README block {start} has no closing {end}")
        pattern = re.compile(re.escape(start) + r".*?" + re.escape(end), re.DOTALL)
        body = f"{start}\n{render_block(name, docs)}\n{end}"

        def replacement(_match: re.Match[str], body: str = body) -> str:
            return body

        text = pattern.sub(replacement, text)
    return text
