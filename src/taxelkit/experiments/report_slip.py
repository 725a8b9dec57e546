"""The README block of the ``slip`` experiment (see :mod:`taxelkit.experiments.report`)."""

from __future__ import annotations

import itertools
from typing import Any

from taxelkit.experiments.slip_result import acceptance_checks

__all__ = ["slip_heldout_markdown", "slip_markdown"]


def _pct(num: int, den: int) -> str:
    return f"{num}/{den} ({100.0 * num / den:.1f} %)" if den else "-"


def _from_pitch(p: dict[str, Any] | None) -> str:
    if p is None:
        return "-"
    return f"{_pct(p['in_time'], p['phases'])} ({p['unresolvable']}: {p['unresolvable_detected']})"


def slip_markdown(doc: dict[str, Any]) -> str:
    """Detection of slip phases, false alarms on rolling, recognition under slip, per engine."""
    rates = " and ".join(f"{r:g}" for r in doc["rates_hz"])
    lines = [
        f"Rolls, rolls with one slipping phase (kinematic only) and slides of the six objects, "
        f"each seen at {rates} frames/s on the Bonneville array with its noise "
        f"({doc['n_trials']} kinematic and {doc['mujoco_trials']} MuJoCo trials per kind and "
        f"object). Ground truth (scoring only): a slip phase is a run of contact points moving "
        f"faster than {doc['gt_slip_mm_s']:g} mm/s along the plate; *in time*: decided within "
        f"{doc['latency_s']:g} s of its start. Detectable kinds: a face (area) sliding and a line "
        "sliding along itself; a point skidding and an isotropic face spinning leave the "
        "footprint a rolling body leaves, and are listed apart. *From one pitch* (beside the "
        "acceptance's figure, not instead of it): what a binary footprint can resolve; a slow "
        "slide moves it less than a taxel pitch in 0.2 s. In time from one pitch: decided "
        f"within {doc['latency_s']:g} s of the phase's slip having reached one pitch (the "
        "contact points' slip summed from its start); phases that slid less than a pitch in "
        "all are counted apart." + _imperfect_intro(doc),
        "",
        "| engine | rate | kind | trials | faces and lines in time (found) | median latency "
        "| other slip found | false alarms (trials, per s) | identified / wrong / not "
        "(slid) | identified without slip detection |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for s in doc["summaries"]:
        det = s["detectable"]
        other = {k: v for k, v in s["by_slip_kind"].items() if k not in doc["detectable_kinds"]}
        other_txt = ", ".join(f"{k} {v['detected']}/{v['phases']}" for k, v in other.items())
        v, w = s["verdicts"], s["verdicts_without_slip"]
        lat = det["median_latency_s"]
        lines.append(
            f"| {s['engine']} | {s['rate_hz']:g} | {s['kind']} | {s['trials']} "
            f"| {_pct(det['in_time'], det['phases'])} ({det['detected']}) "
            f"| {'-' if lat != lat else f'{lat:.2f} s'} | {other_txt or '-'} "
            f"| {s['false_alarms']} ({s['trials_with_false_alarm']} trials, "
            f"{s['false_alarms_per_s']:.3f}/s) "
            f"| {v['identified']} / {v['wrong']} / {v['not_identified']} ({s['slid']}) "
            f"| {w['identified']} / {w['wrong']} |"
        )
    bands = next(iter(doc["overall"].values()))["detectable_by_speed"]
    edges = [b["from_mm_s"] for b in bands] + [None]
    band_names = [
        f"from {lo:g} mm/s" if hi is None else f"{lo:g}-{hi:g} mm/s" if lo else f"below {hi:g} mm/s"
        for lo, hi in itertools.pairwise(edges)
    ]
    lines += ["", "| rate | imperfection | faces and lines in time | in time by the phase's speed: "
              + ", ".join(band_names) + " | faces and lines in time from one pitch "
              "(slid less than a pitch: found) | rolls with a false alarm "
              "| partial slip identified (without slip detection) | slides identified |",
              "| --- | --- | --- | --- | --- | --- | --- | --- |"]  # fmt: skip
    views = [("none", doc["overall"]), *doc.get("overall_imperfect", {}).items()]
    for rate in doc["overall"]:
        for name, overall in views:
            o = overall[rate]
            det, part, base = o["detectable"], o["partial"], o["partial_without_slip"]
            n_part = sum(part.values())
            by_speed = ", ".join(_pct(b["in_time"], b["phases"]) for b in o["detectable_by_speed"])
            lines.append(
                f"| {rate} frames/s | {name} | {_pct(det['in_time'], det['phases'])} | {by_speed} "
                f"| {_from_pitch(o.get('detectable_from_pitch'))} "
                f"| {100 * o['roll_false_alarm_trial_rate']:.1f} % "
                f"| {_pct(part['identified'], n_part)} ({base['identified']}), "
                f"{part['wrong']} wrong | {o['sliding_identified']} |"
            )
    verdicts = [f"{rate} frames/s: {_holds(acc)}" for rate, acc in doc["acceptance"].items()]
    imperfect = [
        f"{rate} frames/s with imperfection {name}: {_holds(acceptance_checks(o))}"
        for name, overall in doc.get("overall_imperfect", {}).items()
        for rate, o in overall.items()
    ]
    skipped = "".join(f" Skipped: {k} ({v})." for k, v in doc["skipped"].items())
    lines += ["", "Acceptance (imperfection none): " + ". ".join(verdicts) + "." + skipped]
    if imperfect:
        lines[-1] += " The same checks beside it: " + ". ".join(imperfect) + "."
    return "\n".join(lines)


def slip_heldout_markdown(docs: dict[str, dict[str, Any]]) -> str:
    """``slip`` beside its held-out seed: per rate and imperfection, the acceptance's figures."""
    tuned, held = docs["slip"], docs["slip-heldout"]
    a, b = held["tuned_on_seed"], held["held_out_seed"]
    lines = [
        f"The same experiment on seed {b} (the detector's thresholds were set on seeds 777, "
        f"3, 0 and 5), seed {a} / seed {b}:",
        "",
        "| rate | imperfection | faces and lines in time | in time from one pitch "
        "| rolls with a false alarm | partial slip identified (wrong) | slides identified |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]

    def views(doc: dict[str, Any]) -> dict[str, dict[str, Any]]:
        return {"none": doc["overall"], **doc.get("overall_imperfect", {})}

    left, right = views(tuned), views(held)
    for rate in held["overall"]:
        for name in right:
            if name not in left or rate not in left[name]:
                continue
            cells = []
            for o in (left[name][rate], right[name][rate]):
                det, part = o["detectable"], o["partial"]
                pitch = o.get("detectable_from_pitch")
                cells.append(
                    (
                        _pct(det["in_time"], det["phases"]),
                        "-" if pitch is None else _pct(pitch["in_time"], pitch["phases"]),
                        f"{100 * o['roll_false_alarm_trial_rate']:.1f} %",
                        f"{part['identified']}/{sum(part.values())} ({part['wrong']})",
                        str(o["sliding_identified"]),
                    )
                )
            pairs = " | ".join(f"{x} / {y}" for x, y in zip(*cells, strict=True))
            lines.append(f"| {rate} frames/s | {name} | {pairs} |")
    verdicts = [f"{rate} frames/s: {_holds(acc)}" for rate, acc in held["acceptance"].items()]
    lines += ["", f"Acceptance on seed {b} (imperfection none): " + ". ".join(verdicts) + "."]
    return "\n".join(lines)


def _holds(acc: dict[str, bool]) -> str:
    holds = [("slip phases in time >= 95 %", acc["detectable_in_time_ge_95"]),
             ("false alarms on rolls <= 2 %", acc["roll_false_alarms_le_2"]),
             ("slides never identified", acc["sliding_never_identified"])]  # fmt: skip
    return "; ".join(f"{n} {'holds' if h else 'fails'}" for n, h in holds)


def _imperfect_intro(doc: dict[str, Any]) -> str:
    names = [f for f in doc.get("imperfections", ["none"]) if f != "none"]
    if not names:
        return ""
    described = ", ".join(
        "every imperfection of the robustness matrix at once (`all`)"
        if f == "all"
        else f"the `{f}` fault model"
        for f in names
    )
    return (
        f" Every trial's frames are recognised again through {described}; the first table "
        "and the acceptance are those of the frames as the array gives them (imperfection "
        "none)."
    )
