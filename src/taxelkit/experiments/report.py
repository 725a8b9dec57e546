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

__all__ = ["BLOCKS", "render_block", "robustness_markdown", "update_blocks"]


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


#: Blocks of the README rendered from results, by experiment name.
BLOCKS: dict[str, Callable[[dict[str, Any]], str]] = {"robustness": robustness_markdown}


def render_block(name: str, doc: dict[str, Any]) -> str:
    """The README block of experiment ``name`` from its JSON document."""
    if name not in BLOCKS:
        raise InputError(f"no README block for {name!r}; known: {', '.join(BLOCKS)}")
    return BLOCKS[name](doc)


def update_blocks(text: str, docs: dict[str, dict[str, Any]]) -> str:
    """Rewrite the ``<!-- results:NAME -->`` blocks of ``text`` for which ``docs`` has results.

    Raises
    ------
    InputError
        If a block to rewrite has no closing marker.
    """
    for name, doc in docs.items():
        if name not in BLOCKS:
            continue
        start, end = f"<!-- results:{name} -->", f"<!-- /results:{name} -->"
        if start not in text:
            continue
        if end not in text:
            raise InputError(f"README block {start} has no closing {end}")
        pattern = re.compile(re.escape(start) + r".*?" + re.escape(end), re.DOTALL)
        body = f"{start}\n{render_block(name, doc)}\n{end}"

        def replacement(_match: re.Match[str], body: str = body) -> str:
            return body

        text = pattern.sub(replacement, text)
    return text
