"""Write a benchmark's README row as JSON: ``docs/results/bench/SCRIPT.json``.

A script called with ``--record`` formats its row from the figures it has just
measured and writes it here; ``python benchmarks/render_readme.py`` renders the
README's benchmark table from these files (never by hand), and a test checks
that the README matches them.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
from pathlib import Path
from typing import Any

BENCH_DIR = Path(__file__).resolve().parents[1] / "docs" / "results" / "bench"


def add_record_option(ap: argparse.ArgumentParser) -> None:
    """``--record``: write the README row to docs/results/bench/SCRIPT.json."""
    ap.add_argument(
        "--record",
        action="store_true",
        help="write this run's README row to docs/results/bench/SCRIPT.json",
    )


def cpu_model() -> str | None:
    """The processor's model name (``/proc/cpuinfo``; ``platform.processor()`` elsewhere)."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            for line in fh:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].replace("(R)", "").replace("(TM)", "").strip()
    except OSError:
        pass
    return platform.processor() or None


def record(
    script: str,
    *,
    figure: str,
    ratio: str,
    measured: dict[str, Any],
    variant: str | None = None,
) -> Path:
    """Write the row of ``script`` (its ``__file__``) with the figures it measured.

    A ``variant`` (a run with other options than the README row's) goes to
    ``docs/results/bench/variants/SCRIPT-VARIANT.json`` instead: the docs render
    tables from those, and the README's benchmark table stays one row a script.
    """
    doc = {
        "script": Path(script).name,
        "generated": True,
        "figure": figure,
        "ratio": ratio,
        "measured": measured,
        "date": datetime.date.today().isoformat(),
        "machine": {
            "cpus": os.cpu_count(),
            "cpu": cpu_model(),
            "load_average_1min": round(os.getloadavg()[0], 1),
            "python": platform.python_version(),
        },
    }
    folder = BENCH_DIR if variant is None else BENCH_DIR / "variants"
    folder.mkdir(parents=True, exist_ok=True)
    stem = Path(script).stem if variant is None else f"{Path(script).stem}-{variant}"
    path = folder / f"{stem}.json"
    tmp = path.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(doc, indent=2) + "\n", encoding="utf-8")
    tmp.replace(path)
    print(f"recorded {path}")
    return path
