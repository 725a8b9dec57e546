"""README blocks of the smart sensor's robustness sweeps (``robustness``, ``robustness-heldout``).

The matrix of accuracies, the held-out seed beside the seed the thresholds
were set on, and the cells that miss: which rolls fail in them and what the
wrong identities were named.
"""

from __future__ import annotations

import math
from collections import Counter
from typing import Any

from scipy.stats import binom, binomtest

__all__ = [
    "cell_interval",
    "robustness_heldout_markdown",
    "robustness_markdown",
    "robustness_misses_markdown",
]

#: The accuracy every in-set cell at 20 frames/s and above should reach.
TARGET_ACCURACY = 0.98


def cell_interval(correct: int, n: int, level: float = 0.95) -> tuple[float, float]:
    """Wilson score interval of a cell's accuracy: ``(low, high)``, fractions.

    Parameters
    ----------
    correct, n : int
        Trials identified correctly, trials (``n >= 1``).
    level : float
        Confidence level.
    """
    ci = binomtest(correct, n).proportion_ci(confidence_level=level, method="wilson")
    return float(ci.low), float(ci.high)


def _sampling(cells: list[dict[str, Any]], target: float = TARGET_ACCURACY) -> str:
    """How many cells below ``target`` the trials establish, and how many chance alone gives.

    A cell is below ``target`` beyond sampling doubt when the upper end of its
    95 % Wilson interval is; the count chance alone would give is the expected
    number of cells below ``target`` had every cell the pooled accuracy.
    """
    n_all = sum(c["n"] for c in cells)
    if not cells or n_all == 0:
        return ""
    pooled = sum(c["correct"] for c in cells) / n_all
    low = [c for c in cells if c["accuracy"] < target]
    sure = sum(cell_interval(c["correct"], c["n"])[1] < target for c in low)
    # below target: fewer than ceil(target n) correct (rounded first: 0.98 x 50 is 49.000...01)
    chance = sum(
        float(binom.cdf(math.ceil(round(target * c["n"], 9)) - 1, c["n"], pooled)) for c in cells
    )
    verb = "lies" if sure == 1 else "lie"
    return (
        f"- Of the {len(low)} cells below {target:g} at 20 frames/s and above, {sure} "
        f"{verb} below it beyond sampling doubt (the upper end of their 95 % Wilson "
        f"interval is under {target:g}); the others miss by fewer trials than the "
        f"cell's size can tell from {target:g}. Had every cell the pooled accuracy "
        f"({_pct(pooled)} %), chance alone would leave about {chance:.0f} of the "
        f"{len(cells)} below {target:g}.{_rolls(low)}"
    )


def _rolls(low: list[dict[str, Any]]) -> str:
    """The rolls whose misses put ``low`` (cells) below target: how many, how many in several.

    A roll is one motion (engine, object, trial) seen at every rate and
    imperfection, so one hard motion can miss in many cells.
    """
    seen: dict[tuple[str, str, int], int] = {}
    for c in low:
        for trial, _ in c.get("missed", []):
            key = (c["engine"], c["object"], int(trial))
            seen[key] = seen.get(key, 0) + 1
    if not seen:
        return ""
    many = sum(n > 1 for n in seen.values())
    most = max(seen.values())
    return (
        f" Their misses are {len(seen)} roll(s), {many} of them missed in more than one "
        f"of these cells (at most {most}): a cell's trials are motions, each seen at every "
        "rate and imperfection."
    )


def _named(overall: dict[str, Any]) -> str:
    """Rolls whose events named a wrong object at some moment (absent from older results)."""
    n = overall.get("named_wrongly")
    if n is None:
        return ""
    return (
        f" Counting every event, not only the final verdicts: {n} of the {overall['n']} "
        "named a wrong object at some moment (a later event withdrew the name where the final "
        "verdict is not wrong)."
    )


def _wrong(n: int) -> str:
    """``"1 wrong identity"``, ``"3 wrong identities"``."""
    return f"{n} wrong identit{'y' if n == 1 else 'ies'}"


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
    ok_fast = sum(c["accuracy"] >= TARGET_ACCURACY for c in fast)
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
        f"- All {o['n']} in-set trials: {_pct(o['accuracy'])} % identified, "
        f"{_wrong(o['wrong'])}, {o['undecided']} undecided, {o['unknown']} unknown; "
        "the worst cell has "
        f"{100 * worst:.1f} % wrong identities.{_named(o)}",
        f"- Cells (one object, engine, rate and imperfection) at 20 frames/s and above with "
        f"accuracy >= 0.98: {ok_fast} of {len(fast)}; at 5 frames/s: "
        f"{sum(c['accuracy'] >= 0.98 for c in slow)} of {len(slow)}.",
        *([line] if (line := _sampling(fast)) else []),
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
        if all("named_wrongly" in s for s in arrays):
            n = sum(s["n"] for s in arrays)
            named = sum(s["named_wrongly"] for s in arrays)
            text += [
                "",
                f"Counting every event on the other arrays: {named} of {n} in-set rolls named a "
                "wrong object at some moment (the brackets count only final verdicts).",
            ]
    return "\n".join(text)


def _object_rows(doc: dict[str, Any]) -> dict[tuple[str, str], str]:
    """Per engine and object: cells >= 0.98 at >= 20 frames/s, the lowest, wrong identities."""
    out = {}
    for e in doc["engines"]:
        for obj in doc["objects"]:
            cells = [c for c in doc["cells"] if c["engine"] == e and c["object"] == obj]
            fast = [c for c in cells if c["rate_hz"] >= 20.0]
            slow = [c for c in cells if c["rate_hz"] < 20.0]
            n_slow = sum(c["n"] for c in slow)
            slow_acc = sum(c["correct"] for c in slow) / n_slow if n_slow else None
            out[(e, obj)] = (
                f"{sum(c['accuracy'] >= 0.98 for c in fast)}/{len(fast)}, lowest "
                f"{_pct(min((c['accuracy'] for c in fast), default=None))}, "
                f"{sum(c['wrong'] for c in cells)} wrong; 5 frames/s {_pct(slow_acc)}"
            )
    return out


def robustness_heldout_markdown(docs: dict[str, dict[str, Any]]) -> str:
    """The robustness sweep on the seed its thresholds were set on beside a held-out seed."""
    tuned, held = docs["robustness"], docs["robustness-heldout"]
    a, b = _object_rows(tuned), _object_rows(held)
    lines = [
        f"| engine | object | seed {held['tuned_on_seed']} ({tuned['n_trials']} per cell; "
        f"thresholds set here) | seed {held['held_out_seed']} ({held['n_trials']} per cell; "
        "held out) |",
        "| --- | --- | --- | --- |",
    ]
    lines += [f"| {e} | {o} | {a.get((e, o), 'n/a')} | {v} |" for (e, o), v in b.items()]
    out = []
    for name, doc in (("thresholds' seed", tuned), ("held-out seed", held)):
        o = doc["overall"]
        worst = max((c["wrong"] / c["n"] for c in doc["cells"] if c["n"]), default=0.0)
        fast = [c for c in doc["cells"] if c["object"] != "sliding" and c["rate_hz"] >= 20.0]
        low = [c for c in fast if c["accuracy"] < TARGET_ACCURACY]
        sure = sum(cell_interval(c["correct"], c["n"])[1] < TARGET_ACCURACY for c in low)
        out.append(
            f"- {name}: {_pct(o['accuracy'])} % of {o['n']} in-set trials identified, "
            f"{_wrong(o['wrong'])} (worst cell {100 * worst:.1f} %), "
            f"{o['undecided']} undecided, {o['unknown']} unknown; sliding "
            f"{doc['sliding']['identified']} of {doc['sliding']['n']} identified; cells at "
            f"20 frames/s and above below {TARGET_ACCURACY:g}: {len(low)} of {len(fast)}, "
            f"{sure} of them beyond sampling doubt (95 % Wilson interval).{_rolls(low)}"
            f"{_named(o)}"
        )
    return "\n".join(
        [
            "Each entry: cells (imperfection x rate) at 20 frames/s and above with accuracy "
            ">= 0.98, the lowest of them in %, the wrong identities over every rate, and the "
            "accuracy at 5 frames/s in %.",
            "",
            *lines,
            "",
            *out,
            *_untuned_rates(held),
        ]
    )


def _untuned_rates(held: dict[str, Any]) -> list[str]:
    """The held-out motions at rates outside the matrix: cells, accuracy, wrong identities."""
    doc = held.get("untuned_rates")
    if not doc:
        return []
    lines = [
        "",
        f"The held-out motions seen at frame rates outside the matrix (seed "
        f"{held['held_out_seed']}, every imperfection and object):",
        "",
        "| engine | frames/s | cells >= 0.98 | identified | wrong identities | undecided "
        "| unknown | sliding identified |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    fast_ok = fast_n = wrong_all = 0
    engines = dict.fromkeys(c["engine"] for c in doc["cells"])
    for e in engines:
        for r in doc["rates_hz"]:
            cells = [c for c in doc["cells"] if c["engine"] == e and c["rate_hz"] == r]
            in_set = [c for c in cells if c["object"] != "sliding"]
            slide = [c for c in cells if c["object"] == "sliding"]
            if not in_set:
                continue
            n = sum(c["n"] for c in in_set)
            ok = sum(c["accuracy"] >= TARGET_ACCURACY for c in in_set)
            wrong = sum(c["wrong"] for c in in_set)
            if r >= 20.0:
                fast_ok, fast_n = fast_ok + ok, fast_n + len(in_set)
            wrong_all += wrong
            lines.append(
                f"| {e} | {r:g} | {ok} of {len(in_set)} | "
                f"{_pct(sum(c['correct'] for c in in_set) / n)} % | {wrong} | "
                f"{sum(c['undecided'] for c in in_set)} | {sum(c['unknown'] for c in in_set)} | "
                f"{sum(c['n'] - c['correct'] for c in slide)} of {sum(c['n'] for c in slide)} |"
            )
    lines += [
        "",
        f"- At these rates, 20 frames/s and above: {fast_ok} of {fast_n} cells >= "
        f"{TARGET_ACCURACY:g}; {_wrong(wrong_all)} at all of them (below 20 frames/s the "
        "frames resolve less of each roll: the accuracy there is what they resolve).",
    ]
    return lines


def _miss_rows(doc: dict[str, Any]) -> list[str]:
    """Rows per engine and object with a miss: cells below 0.98, recurring rolls, wrongs."""
    rows = []
    for e in doc["engines"]:
        for obj in doc["objects"]:
            cells = [c for c in doc["cells"] if c["engine"] == e and c["object"] == obj]
            fast = [c for c in cells if c["rate_hz"] >= 20.0]
            low = [c for c in fast if c["accuracy"] < 0.98]
            wrong = [
                f"{named} ({c['rate_hz']:g} frames/s, {c['fault']}, roll {trial})"
                for c in cells
                for trial, named in c.get("missed", [])
                if named not in (None, "unknown", obj)
            ]
            if not low and not wrong:
                continue
            counts = Counter(t for c in low for t, _ in c.get("missed", []))
            recurring = sorted(t for t, k in counts.items() if k >= 2 and 2 * k >= len(low))
            rolls = ", ".join(f"{t} ({counts[t]})" for t in recurring) or "none"
            rows.append(
                f"| {e} | {obj} | {len(low)} of {len(fast)} | {rolls} | "
                f"{'; '.join(wrong) or 'none'} |"
            )
    return rows


def robustness_misses_markdown(docs: dict[str, dict[str, Any]]) -> str:
    """The cells below 0.98 on both seeds, the rolls that fail in them, the wrong names given."""
    tuned, held = docs["robustness"], docs["robustness-heldout"]
    text = [
        "Per engine and object: the cells (imperfection x rate) at 20 frames/s and above "
        "below 98 %, the rolls (trial numbers) that fail in two or more of those cells and in "
        "at least half of them, with the number of cells each fails in, and every wrong "
        "identity at any rate (the name given, then the cell and roll).",
    ]
    for title, doc in (
        (f"Seed {held['tuned_on_seed']} (the thresholds were set here)", tuned),
        (f"Seed {held['held_out_seed']} (held out)", held),
    ):
        rows = _miss_rows(doc)
        text += ["", f"{title}:", ""]
        if not rows:
            text.append("No cell misses, no wrong identity.")
            continue
        text += [
            "| engine | object | cells below 98 % | recurring rolls (cells) | wrong identities |",
            "| --- | --- | --- | --- | --- |",
            *rows,
        ]
    return "\n".join(text)
