"""Rewrite the generated blocks: the README's benchmark table and reproduce timings, the bank table.

Usage, from the repository root: ``python benchmarks/render_readme.py [README.md]``.
Inputs: ``docs/results/bench/*.json`` (``python benchmarks/SCRIPT.py --record``),
``docs/results/bench/variants/*.json`` (runs with other options) and
``docs/results/*.timing.json`` (``taxelkit reproduce``). The bank table of
``docs/tutorials/stream-many-arrays.md`` (block ``bank-table``) is rendered
from the ``bench_bank`` record and its variants.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

from taxelkit.experiments.readme_tables import (
    bench_markdown,
    replace_generated_block,
    span,
    timings_markdown,
)

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "docs" / "results"
BANK_TUTORIAL = ROOT / "docs" / "tutorials" / "stream-many-arrays.md"
#: Frame rate of the bank benchmark's arrays, Hz (the latency of a batch).
BANK_RATE_HZ = 240.0


def bench_records() -> list[dict[str, Any]]:
    """Every benchmark record."""
    return [json.loads(p.read_text("utf-8")) for p in sorted((RESULTS / "bench").glob("*.json"))]


def timings() -> dict[str, float]:
    """Wall-clock seconds per experiment of the committed run."""
    out = {}
    for p in sorted(RESULTS.glob("*.timing.json")):
        doc = json.loads(p.read_text("utf-8"))
        out[str(doc["experiment"])] = float(doc["seconds"])
    return out


def bank_records() -> list[dict[str, Any]]:
    """The ``bench_bank`` record and its variants, by batch length and ``evaluate_every``."""
    paths = [RESULTS / "bench" / "bench_bank.json"]
    paths += sorted((RESULTS / "bench" / "variants").glob("bench_bank-*.json"))
    docs = [json.loads(p.read_text("utf-8")) for p in paths if p.exists()]
    return sorted(
        docs,
        key=lambda d: (d["measured"]["batch_frames"], d["measured"].get("evaluate_every", 1)),
    )


def bank_table(records: list[dict[str, Any]]) -> str:
    """The tutorial's table: each skin of each bank run, with its latency and pushes."""
    rows = []
    for doc in records:
        m = doc["measured"]
        b, every = m["batch_frames"], m.get("evaluate_every", 1)
        latency_ms = 1e3 * b / BANK_RATE_HZ
        latency = f"{latency_ms:.0f} ms" if latency_ms < 1000 else f"{latency_ms / 1e3:.2f} s"
        for active, skin in sorted(m["skins"].items(), key=lambda kv: float(kv[0])):
            runs = skin["runs"]
            rates = [r["rate"] for r in runs]
            rows.append(
                (float(active), b, every, latency, span(rates, step=1000),
                 span([r["push_mean_ms"] for r in runs], 1),
                 span([r["push_max_ms"] for r in runs]),
                 span([r / skin["separate"] for r in rates], 1), len(runs),
                 doc["machine"]["load_average_1min"], doc["date"])
            )  # fmt: skip
    lines = [
        "| arrays touched | `batch_frames` | `evaluate_every` | latency at 240 frames/s | "
        "bank, frames/s | mean push, ms | longest push, ms | vs 1,000 `SmartSensor.push` | "
        "runs (load, date) |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for active, b, every, latency, rate, mean, longest, ratio, n, load, date in sorted(rows):
        lines.append(
            f"| {active:.0%} | {b} | {every} | {latency} | {rate} | {mean} | {longest} | "
            f"{ratio}x | {n} ({load:g}, {date}) |"
        )
    return "\n".join(lines)


def render_tutorial(text: str) -> str:
    """The bank tutorial with its ``bank-table`` block rendered anew."""
    return replace_generated_block(text, "bank-table", bank_table(bank_records()))


def render(text: str) -> str:
    """``text`` (the README) with both generated blocks rendered anew."""
    text = replace_generated_block(text, "bench", bench_markdown(bench_records()))
    return replace_generated_block(text, "timings", timings_markdown(timings()))


def main(readme: Path) -> None:
    for path, renderer in ((readme, render), (BANK_TUTORIAL, render_tutorial)):
        before = path.read_text(encoding="utf-8")
        after = renderer(before)
        if after != before:
            path.write_text(after, encoding="utf-8")
        print(f"{path.name}: generated blocks {'rewritten' if after != before else 'unchanged'}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "README.md")
