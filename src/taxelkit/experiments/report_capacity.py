"""README blocks of the ``capacity`` experiment: accuracy per rule and the histogram twins."""

from __future__ import annotations

from typing import Any

__all__ = ["capacity_markdown", "capacity_partial_markdown", "capacity_twins_markdown"]


def _pct(x: float) -> str:
    return f"{100 * x:.1f}"


def _kind(rule: dict[str, Any]) -> str:
    kind = "associative" if rule["associative"] else "template matching"
    return f"{kind}, paper" if rule["faithful"] else kind


def capacity_markdown(doc: dict[str, Any]) -> str:
    """Accuracy of every rule against stored shapes (s = 0.6 and 1) and against s (100 shapes)."""
    sizes, s = doc["sizes"], doc["s"]
    t = doc["target"]
    lines = [
        f"{doc['n_shapes']} generated shapes ({doc['kinds']['polygon']} polygons, "
        f"{doc['kinds']['curve']} curves, pairwise difference >= {doc['min_difference']}), "
        f"{doc['n_queries']} query traces ({doc['n_trials_per_shape']} per shape, random pose "
        f"and start; {_pct(doc['closed_fraction'])} % of all traces closed). Percent named "
        "right (a tie is never right), in brackets the undecided:",
        "",
    ]
    for s_at in (0.6, 1.0):
        if s_at not in s:
            continue
        j = s.index(s_at)
        lines += [
            f"| rule (s = {s_at:g}) | kind | "
            + " | ".join(f"{k} shapes" for k in sizes) + " |",
            "| --- | --- |" + " --- |" * len(sizes),
        ]  # fmt: skip
        for name, r in doc["rules"].items():
            cells = [
                _pct(a[j]) + (f" ({_pct(u[j])})" if u[j] > 0 else "")
                for a, u in zip(r["accuracy"], r["undecided"], strict=True)
            ]
            lines.append(f"| {r['label']} (`{name}`) | {_kind(r)} | " + " | ".join(cells) + " |")
        lines.append("")
    if t["size"] in sizes:
        i = sizes.index(t["size"])
        lines += [
            f"| rule ({t['size']} shapes) | " + " | ".join(f"s = {v:g}" for v in s) + " |",
            "| --- |" + " --- |" * len(s),
        ]
        for name, r in doc["rules"].items():
            lines.append(f"| `{name}` | " + " | ".join(_pct(a) for a in r["accuracy"][i]) + " |")
        lines.append("")
    if "measured" in t:
        verdict = "met" if t["met"] else "missed"
        lines.append(
            f"Target (best associative rule >= {_pct(t['accuracy'])} % at {t['size']} shapes, "
            f"s = {t['s']:g}): {verdict}, {_pct(t['measured'])} % (`{t['best_associative']}`)."
        )
    return "\n".join(lines).rstrip()


def capacity_twins_markdown(doc: dict[str, Any]) -> str:
    """Told-apart rates of the histogram twins, the order-aware code against the chain code."""
    tw = doc["twins"]
    s = tw["s"]
    rules = ("signature", "matched", "hebbian")
    head = "| pair (queries) | rule | " + " | ".join(f"s = {v:g}" for v in s) + " |"
    lines = [
        "Percent of the queries of either shape named right by a memory of the two:",
        "",
        head,
        "| --- | --- |" + " --- |" * len(s),
    ]
    rows = [(p, tw["named_queries"][p], v) for p, v in tw["named"].items()]
    rows += [
        (f"generated, {code} ({len(tw['generator_pairs'][code])} pairs)",
         tw["generator_queries"][code], v)
        for code, v in tw["generator"].items()
    ]  # fmt: skip
    for pair, n, table in rows:
        for r in rules:
            if r in table:
                lines.append(
                    f"| {pair} ({n}) | `{r}` | " + " | ".join(_pct(x) for x in table[r]) + " |"
                )
    empty = [c for c, ps in tw["generator_pairs"].items() if not ps]
    if empty:
        lines += ["", f"No generated pair found with {' or '.join(empty)}."]
    t = tw["target"]
    if t["measured_min_full_contour"] is not None:
        verdict = "met" if t["met"] else "missed"
        lines += [
            "",
            f"Target (order-aware code tells every twin pair apart >= {_pct(t['told_apart'])} % "
            f"at full contour): {verdict}, worst pair {_pct(t['measured_min_full_contour'])} %.",
        ]
    return "\n".join(lines)


def capacity_partial_markdown(doc: dict[str, Any]) -> str:
    """The limitation on partial traces among many shapes, with the figures of ``capacity``."""
    sizes, s = doc["sizes"], doc["s"]
    size = doc["target"]["size"]
    low = [v for v in sorted(s) if v < 0.6]
    if size not in sizes or 0.6 not in s or not low:
        return f"(no run at {size} shapes and s < 0.6)"
    i, j = sizes.index(size), s.index(0.6)
    name, best = max(doc["rules"].items(), key=lambda kv: kv[1]["accuracy"][i][j])
    named = " and ".join(
        f"{_pct(best['accuracy'][i][s.index(v)])} % from {100 * v:.0f} %" for v in reversed(low)
    )
    chain = max(
        r["accuracy"][i][s.index(v)] for r in doc["rules"].values() if r["code"] == "chain"
        for v in low
    )  # fmt: skip
    return (
        f"- **Partial traces among many shapes.** Among {size} stored shapes the best rule "
        f"(`{name}`) names {named} of a contour; no chain-code rule names more than "
        f"{_pct(chain)} % from those fractions (`capacity`)."
    )
