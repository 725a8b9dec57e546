"""The README's generated blocks (benchmarks, reproduce timings) match their JSON sources."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType

import pytest

from taxelkit.errors import InputError
from taxelkit.experiments.readme_tables import (
    bench_markdown,
    replace_generated_block,
    timings_markdown,
)

ROOT = Path(__file__).resolve().parents[2]


def render_module() -> ModuleType:
    spec = importlib.util.spec_from_file_location(
        "render_readme", ROOT / "benchmarks" / "render_readme.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_readme_generated_blocks_match_the_records() -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert render_module().render(readme) == readme, (
        "README generated blocks are stale: run python benchmarks/render_readme.py"
    )


def test_the_bank_tutorial_table_matches_the_bank_records() -> None:
    module = render_module()
    text = module.BANK_TUTORIAL.read_text(encoding="utf-8")
    assert module.render_tutorial(text) == text, (
        "the bank table of stream-many-arrays.md is stale: run python benchmarks/render_readme.py"
    )
    records = module.bank_records()
    assert records[0]["measured"]["batch_frames"] <= records[-1]["measured"]["batch_frames"]
    table = module.bank_table(records)
    assert table.count("\n") == 1 + sum(len(r["measured"]["skins"]) for r in records)


def test_every_benchmark_record_names_a_script() -> None:
    scripts = {p.stem for p in (ROOT / "benchmarks").glob("bench_*.py")}
    bench = ROOT / "docs" / "results" / "bench"
    records = {p.stem for p in bench.glob("*.json")}
    assert records and records <= scripts
    variants = {p.stem.split("-")[0] for p in (bench / "variants").glob("*.json")}
    assert variants <= scripts


def test_bench_rows_say_whether_they_were_generated() -> None:
    gen = {"script": "bench_x.py", "generated": True, "figure": "1 frame/s", "ratio": "2x",
           "date": "2026-01-02", "machine": {"cpus": 2, "load_average_1min": 3.5}}  # fmt: skip
    hand = {"script": "bench_solids.py", "generated": False, "figure": "f", "ratio": "r"}
    cpu = {**gen, "script": "bench_y.py", "machine": {**gen["machine"], "cpu": "Xeon"}}
    lines = bench_markdown([gen, hand, cpu]).splitlines()
    assert lines[2] == "| `bench_solids.py` | f [copied by hand from an earlier run] | r |"
    assert lines[3] == "| `bench_x.py` | 1 frame/s [2026-01-02, 2 CPUs, load average 3.5] | 2x |"
    assert lines[4] == (
        "| `bench_y.py` | 1 frame/s [2026-01-02, 2 CPUs (Xeon), load average 3.5] | 2x |"
    )


def test_timings_and_block_replacement() -> None:
    text = timings_markdown({"a": 600.0, "b": 60.0, "c": 30.0, "d": 1.0}, longest=2)
    assert text.startswith("The 4 experiments took 12 min") and "`a` 10 min, `b` 1 min)" in text
    src = "x <!-- generated:t -->\nold\n<!-- /generated:t --> y"
    assert (
        replace_generated_block(src, "t", "new")
        == "x <!-- generated:t -->\nnew\n<!-- /generated:t --> y"
    )
    with pytest.raises(InputError, match="generated:u"):
        replace_generated_block(src, "u", "new")


def test_reproduce_readme_rewrites_the_timings_block(tmp_path: Path) -> None:
    from taxelkit.cli import run

    readme = tmp_path / "README.md"
    readme.write_text("a\n<!-- generated:timings -->\nold\n<!-- /generated:timings -->\n")
    (tmp_path / "junk.timing.json").write_text("not json")  # skipped, not fatal
    assert run(["reproduce", "cylinder", "--out", str(tmp_path), "--readme", str(readme)]) == 0
    text = readme.read_text()
    assert "old" not in text and "The 1 experiment took 0 min" in text
    assert "`cylinder` 0 min" in text
