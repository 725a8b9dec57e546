"""The ``new-objects`` README block's part for imperfect arrays (see :mod:`.report`)."""

from __future__ import annotations

from typing import Any

__all__ = ["imperfect_lines", "imperfect_summary"]


def _wrong_names(outcomes: dict[str, int], name: str, objects: list[str]) -> str:
    named = [f"{k} {v}" for k, v in sorted(outcomes.items()) if k in objects and k != name]
    return f" ({', '.join(named)})" if named else ""


def imperfect_lines(doc: dict[str, Any]) -> list[str]:
    """Per imperfection: each object's first roll and exploration, the same motions."""
    lines: list[str] = []
    objects = doc["objects"]
    for fault, view in doc.get("imperfect", {}).items():
        what = (
            "every imperfection of the robustness matrix at once (`all`)"
            if fault == "all"
            else f"the `{fault}` fault model"
        )
        explored = {r["object"]: r for r in view["explore"]["per_object"]}
        lines += [
            "",
            f"The same motions seen through {what}, ten-object table: one roll, and handled "
            "until decided (wrong names in brackets, with what was named):",
            "",
            "| object | one roll: identified | wrong | unknown | undecided "
            "| handled until decided: identified | wrong |",
            "| --- | --- | --- | --- | --- | --- | --- |",
        ]
        for r in view["per_object"]:
            e = explored[r["object"]]
            lines.append(
                f"| {r['object']} | {r['identified']}/{r['trials']} | {r['wrong']}"
                f"{_wrong_names(r['outcomes'], r['object'], objects)} | {r['unknown']} "
                f"| {r['undecided']} | {e['identified']}/{e['trials']} | {e['wrong']}"
                f"{_wrong_names(e['outcomes'], r['object'], objects)} |"
            )
        one, ex = view["summary"], view["explore"]["summary"]
        lines += [
            "",
            f"With {fault}: distinguishable objects identified {one['distinguishable_identified']}"
            f"/{one['distinguishable_trials']} in one roll, {ex['distinguishable_identified']}/"
            f"{ex['distinguishable_trials']} handled until decided; wrong identities "
            f"{one['wrong']} and {ex['wrong']}; objects in neither table named "
            f"{one['outside_named']} and {ex['outside_named']}.",
        ]
    return lines


def imperfect_summary(tuned: dict[str, Any], held: dict[str, Any]) -> list[str]:
    """One sentence per imperfection: both seeds' figures side by side."""
    out = []
    for fault, view in held.get("imperfect", {}).items():
        other = tuned.get("imperfect", {}).get(fault)
        if other is None:
            continue
        pairs = [(other["summary"], view["summary"]),
                 (other["explore"]["summary"], view["explore"]["summary"])]  # fmt: skip
        ident = [f"{a['distinguishable_identified']} / {b['distinguishable_identified']}"
                 for a, b in pairs]  # fmt: skip
        wrong = [f"{a['wrong']} / {b['wrong']}" for a, b in pairs]
        named = [f"{a['outside_named']} / {b['outside_named']}" for a, b in pairs]
        out.append(
            f"Through imperfection {fault} (the same motions), seed {held['tuned_on_seed']} / "
            f"seed {held['held_out_seed']}: distinguishable identified {ident[0]} of "
            f"{view['summary']['distinguishable_trials']} in one roll, {ident[1]} handled until "
            f"decided; wrong names {wrong[0]} and {wrong[1]}; objects in neither table named "
            f"{named[0]} and {named[1]}."
        )
    return out
