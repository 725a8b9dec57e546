"""Rewrite the README's generated blocks: the benchmark table and the reproduce timings.

Usage, from the repository root: ``python benchmarks/render_readme.py [README.md]``.
Inputs: ``docs/results/bench/*.json`` (``python benchmarks/SCRIPT.py --record``)
and ``docs/results/*.timing.json`` (``taxelkit reproduce``).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

from taxelkit.experiments.readme_tables import (
    bench_markdown,
    replace_generated_block,
    timings_markdown,
)

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "docs" / "results"


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


def render(text: str) -> str:
    """``text`` (the README) with both generated blocks rendered anew."""
    text = replace_generated_block(text, "bench", bench_markdown(bench_records()))
    return replace_generated_block(text, "timings", timings_markdown(timings()))


def main(readme: Path) -> None:
    before = readme.read_text(encoding="utf-8")
    after = render(before)
    if after != before:
        readme.write_text(after, encoding="utf-8")
    print(f"{readme}: generated blocks {'rewritten' if after != before else 'unchanged'}")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "README.md")
