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
from taxelkit.experiments.report_capacity import (
    capacity_markdown,
    capacity_partial_markdown,
    capacity_twins_markdown,
)
from taxelkit.experiments.report_new_objects import imperfect_lines, imperfect_summary
from taxelkit.experiments.report_paper000 import (
    fig9_markdown,
    fig9_readings_markdown,
    open_set_markdown,
    recall_vs_s_markdown,
    trace_robustness_markdown,
)
from taxelkit.experiments.report_robustness import (
    robustness_heldout_markdown,
    robustness_markdown,
    robustness_misses_markdown,
)
from taxelkit.experiments.report_slip import slip_heldout_markdown, slip_markdown

__all__ = [
    "BLOCKS",
    "fig9_markdown",
    "fig9_readings_markdown",
    "multi_object_markdown",
    "new_objects_heldout_markdown",
    "new_objects_markdown",
    "open_set_markdown",
    "paper001_markdown",
    "recall_vs_s_markdown",
    "render_block",
    "robustness_heldout_markdown",
    "robustness_markdown",
    "robustness_misses_markdown",
    "slip_heldout_markdown",
    "slip_markdown",
    "trace_robustness_markdown",
    "update_blocks",
]


def _pct(x: float | None) -> str:
    return "n/a" if x is None else f"{100 * x:.1f}"


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


def multi_object_markdown(doc: dict[str, Any]) -> str:
    """The ``multi-object`` experiment: accuracy per object and track purity, per engine."""
    imps = doc.get("imperfections", ["none"])
    rates = doc.get("rates_hz", [doc.get("rate_hz", 20.0)])
    described = [
        "every imperfection of the robustness matrix at once (`all`)"
        if f == "all"
        else f"the `{f}` fault model"
        for f in imps
        if f != "none"
    ]
    seen = "noise on" + (
        "; each scene is recognised again through " + ", ".join(described) if described else ""
    )
    counts = sorted({s["n_objects"] for s in doc["summaries"]})
    head = " | ".join(f"{n} objects: identified (wrong, mixed-up)" for n in counts)
    lines = [
        f"Scenes of {' and '.join(str(n) for n in counts)} distinct objects of the six at "
        f"{', '.join(f'{r:g}' for r in rates)} frames/s (the same motions at each rate), each "
        f"object in its own 16 x 16 tile of one array, staggered starts, {seen} "
        f"({doc['n_trials']} kinematic and {doc['mujoco_trials']} MuJoCo scenes per count). "
        "Purity: fraction of a track's frames owned by one object (ground truth, scoring only); "
        "columns with two figures give them for each object count in turn.",
        "",
        f"| engine | frames/s | imperfection | {head} | unknown / undecided / missed "
        "| pure tracks | merges / splits |",
        "| --- | --- | --- |" + " --- |" * len(counts) + " --- | --- | --- |",
    ]
    groups: dict[tuple[str, float, str], list[dict[str, Any]]] = {}
    for s in doc["summaries"]:
        key = (s["engine"], s.get("rate_hz", rates[0]), s.get("imperfection", "none"))
        groups.setdefault(key, []).append(s)
    for (engine, rate, imp), rows in groups.items():
        cells = " | ".join(
            f"{s['identified']}/{s['objects']} ({100 * s['identified_rate']:.1f} %) "
            f"({s['wrong']}, {s['mixed_wrong']})"
            for s in rows
        )
        missed = "; ".join(f"{s['unknown']} / {s['undecided']} / {s['missed']}" for s in rows)
        pure = " / ".join(f"{100 * s['pure_tracks']:.1f} %" for s in rows)
        events = "; ".join(f"{s['merges']} / {s['splits']}" for s in rows)
        lines.append(f"| {engine} | {rate:g} | {imp} | {cells} | {missed} | {pure} | {events} |")

    def verdicts(acc: dict[str, bool]) -> str:
        return (
            f">= 95 % identified {'holds' if acc['two_objects_identified_ge_95'] else 'fails'}; "
            "no wrong identity from a mixed-up track "
            f"{'holds' if acc['two_objects_no_mixed_wrong'] else 'fails'}"
        )

    skipped = "".join(f" Skipped: {k} ({v})." for k, v in doc["skipped"].items())
    imperfect = "".join(
        f" Same checks with imperfection {f} (beside the acceptance): {verdicts(acc)}."
        for f, acc in doc.get("acceptance_imperfect", {}).items()
    )
    lines += [
        "",
        f"Acceptance, two objects (imperfection none, every rate): {verdicts(doc['acceptance'])}."
        + imperfect
        + skipped,
    ]
    return "\n".join(lines)


def new_objects_markdown(doc: dict[str, Any]) -> str:
    """The ``new-objects`` experiment: the ten objects with both tables, and objects outside."""
    lines = [
        f"{doc['n_trials']} kinematic rolls per object at 20 frames/s, noise on; the six with "
        "their scripts (sizes +-30 %), the four learnt ones with the mesh scripts at their "
        "learnt size. Columns: outcome with the ten-object table and face tactemes; "
        "*decidable*: rolls whose tactemes (those the object's row holds) rule out every "
        "other object; *six-object table*: the same frames recognised as before.",
        "",
        "| object | identified | wrong | unknown | undecided | decidable (identified) "
        "| distinguishable | six-object table: right / wrong |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for r in doc["per_object"]:
        in_six = r["object"] in doc["objects"][:6]
        lines.append(
            f"| {r['object']} | {r['identified']}/{r['trials']} | {r['wrong']} | {r['unknown']} "
            f"| {r['undecided']} | {r['decidable']} ({r['decidable_identified']}) "
            f"| {'yes' if r['distinguishable'] else 'no'} "
            f"| {r['baseline_identified'] if in_six else '-'} / {r['baseline_wrong']} |"
        )
    s, acc = doc["summary"], doc["acceptance"]
    outside = "; ".join(
        f"{name}: {', '.join(f'{k} {v}' for k, v in sorted(d.items()))} (six-object table: "
        + ", ".join(f"{k} {v}" for k, v in sorted(doc["outside_baseline"][name].items()))
        + ")"
        for name, d in sorted(doc["outside"].items())
    )
    lines += [
        "",
        f"Distinguishable objects identified: {s['distinguishable_identified']}/"
        f"{s['distinguishable_trials']} ({100 * s['distinguishable_rate']:.1f} %); decidable "
        f"rolls identified: {s['decidable_identified']}/{s['decidable_trials']} "
        f"({100 * s['decidable_rate']:.1f} %); wrong identities: {s['wrong']}.",
        f"Objects in neither table ({doc['n_outside']} rolls each): {outside}.",
        "",
        *_explore_lines(doc["explore"]),
        *imperfect_lines(doc),
        "",
        "Not distinguishable with these tactemes (learn-object says so):",
        "",
        *[f"- {o['sentence']}" for o in doc["overlaps"]],
        "",
        "Acceptance (the rolls as the array gives them): rows learnt from the six meshes "
        "agree with Table 1 "
        f"{'holds' if acc['six_rows_agree'] else 'fails'}; >= 95 % identified where "
        f"distinguishable {'holds' if acc['identified_ge_95_where_distinguishable'] else 'fails'}"
        f"; no wrong identity {'holds' if acc['no_wrong_identity'] else 'fails'}; objects "
        f"outside the table never named {'holds' if acc['outside_never_named'] else 'fails'}.",
    ]
    return "\n".join(lines)


def new_objects_heldout_markdown(docs: dict[str, dict[str, Any]]) -> str:
    """``new-objects`` beside its held-out seed: per object, one roll and handled until decided."""
    tuned, held = docs["new-objects"], docs["new-objects-heldout"]
    k = held["explore"]["handlings"]
    lines = [
        f"The same experiment on seed {held['held_out_seed']} (rules set on seeds 0 and 3; "
        f"the learnt rows come from the check rolls of each seed). Identified of "
        f"{held['n_trials']} (wrong names in brackets), one roll and handled until decided "
        f"(up to {k} rolls), seed {held['tuned_on_seed']} / seed {held['held_out_seed']}:",
        "",
        "| object | distinguishable | one roll | handled until decided |",
        "| --- | --- | --- | --- |",
    ]
    one = {s: {r["object"]: r for r in d["per_object"]} for s, d in (("t", tuned), ("h", held))}
    ex = {
        s: {r["object"]: r for r in d["explore"]["per_object"]}
        for s, d in (("t", tuned), ("h", held))
    }
    for name in held["objects"]:
        t1, h1, te, he = one["t"][name], one["h"][name], ex["t"][name], ex["h"][name]
        lines.append(
            f"| {name} | {'yes' if h1['distinguishable'] else 'no'} "
            f"| {t1['identified']} ({t1['wrong']}) / {h1['identified']} ({h1['wrong']}) "
            f"| {te['identified']} ({te['wrong']}) / {he['identified']} ({he['wrong']}) |"
        )
    for name in sorted(held["outside"]):
        te, he = ex["t"][name], ex["h"][name]
        lines.append(
            f"| {name} (in neither table: named) | - "
            f"| {tuned['summary']['outside_named']} / {held['summary']['outside_named']} "
            f"| {te['wrong']} / {he['wrong']} |"
        )
    s1, s2 = held["summary"], held["explore"]["summary"]
    changed = [
        f"{name}: {', '.join(sorted(set(held['rows'][name]) ^ set(tuned['rows'][name])))}"
        for name in held["objects"]
        if set(held["rows"][name]) != set(tuned["rows"][name])
    ]
    lines += [
        "",
        f"Held-out seed: distinguishable identified {s1['distinguishable_identified']}/"
        f"{s1['distinguishable_trials']} in one roll, {s2['distinguishable_identified']}/"
        f"{s2['distinguishable_trials']} ({100 * s2['distinguishable_rate']:.1f} %) handled "
        f"until decided; wrong names {s1['wrong']} and {s2['wrong']}. Learnt rows that differ "
        f"from seed {held['tuned_on_seed']}'s: {'; '.join(changed) if changed else 'none'}.",
    ]
    added = [
        f"{name}: {_added(tuned['checks'].get(name, {}))} / {_added(held['checks'].get(name, {}))}"
        for name in held["objects"]
        if tuned["checks"].get(name, {}).get("added") or held["checks"].get(name, {}).get("added")
    ]
    if added:
        lines.append(
            f"Tactemes the learning check added beyond the geometry, seed {held['tuned_on_seed']}"
            f" / seed {held['held_out_seed']} (*rare*: seen in one or two rolls, never names "
            f"the object alone): {'; '.join(added)}."
        )
    lines += imperfect_summary(tuned, held)
    return "\n".join(lines)


def _added(check: dict[str, Any]) -> str:
    """The tactemes a learning check added, the rare ones marked (``"none"`` if none)."""
    rare = set(check.get("rare", ()))
    names = [f"{t} (rare)" if t in rare else t for t in check.get("added", ())]
    return ", ".join(names) or "none"


def _explore_lines(ex: dict[str, Any]) -> list[str]:
    """The exploration of ``new-objects``: identified after each number of handlings."""
    k = ex["handlings"]
    lines = [
        "",
        f"Handled until decided (up to {k} rolls of the same object, each drawn anew; "
        "Level 4 over the tactemes of all its contacts, `recognize --one-object`): "
        "identified after each number of rolls, and the outcome after the last.",
        "",
        "| object | "
        + " | ".join(f"{h} roll{'s' if h > 1 else ''}" for h in range(1, k + 1))
        + " | wrong | unknown | undecided | mean rolls |",
        "| --- | " + " | ".join("---" for _ in range(k)) + " | --- | --- | --- | --- |",
    ]
    for r in ex["per_object"]:
        lines.append(
            f"| {r['object']}{'' if r['inside'] else ' (in neither table)'} | "
            + " | ".join(str(n) for n in r["identified_by_handling"])
            + f" | {r['wrong']} | {r['unknown']} | {r['undecided']} | {r['mean_handlings']:.2f} |"
        )
    s, acc = ex["summary"], ex["acceptance"]
    lines += [
        "",
        f"Distinguishable objects identified: {s['distinguishable_identified']}/"
        f"{s['distinguishable_trials']} ({100 * s['distinguishable_rate']:.1f} %); wrong "
        f"identities: {s['wrong']}; rolls of objects in neither table given a name: "
        f"{s['outside_named']}. Acceptance (handled until decided): >= 95 % identified where "
        f"distinguishable {'holds' if acc['identified_ge_95_where_distinguishable'] else 'fails'}"
        f"; no wrong identity {'holds' if acc['no_wrong_identity'] else 'fails'}; objects "
        f"outside the table never named {'holds' if acc['outside_never_named'] else 'fails'}.",
    ]
    return lines


#: Blocks of the README rendered from results: name -> (experiments it needs, renderer).
BLOCKS: dict[str, tuple[tuple[str, ...], Callable[[dict[str, dict[str, Any]]], str]]] = {
    "fig9": (("fig9",), lambda docs: fig9_markdown(docs["fig9"])),
    "recall-vs-s": (("recall-vs-s",), lambda docs: recall_vs_s_markdown(docs["recall-vs-s"])),
    "open-set": (("open-set",), lambda docs: open_set_markdown(docs["open-set"])),
    "fig9-readings": (
        ("fig9-readings",),
        lambda docs: fig9_readings_markdown(docs["fig9-readings"]),
    ),
    "robustness": (("robustness",), lambda docs: robustness_markdown(docs["robustness"])),
    "robustness-heldout": (("robustness", "robustness-heldout"), robustness_heldout_markdown),
    "robustness-misses": (("robustness", "robustness-heldout"), robustness_misses_markdown),
    "multi-object": (
        ("multi-object",),
        lambda docs: multi_object_markdown(docs["multi-object"]),
    ),
    "slip": (("slip",), lambda docs: slip_markdown(docs["slip"])),
    "slip-heldout": (("slip", "slip-heldout"), slip_heldout_markdown),
    "new-objects": (("new-objects",), lambda docs: new_objects_markdown(docs["new-objects"])),
    "new-objects-heldout": (("new-objects", "new-objects-heldout"), new_objects_heldout_markdown),
    "capacity": (("capacity",), lambda docs: capacity_markdown(docs["capacity"])),
    "capacity-twins": (("capacity",), lambda docs: capacity_twins_markdown(docs["capacity"])),
    "capacity-partial": (
        ("capacity",),
        lambda docs: capacity_partial_markdown(docs["capacity"]),
    ),
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
