"""The README's generated results blocks match the committed results."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from taxelkit.errors import InputError
from taxelkit.experiments.report import BLOCKS, render_block, update_blocks

ROOT = Path(__file__).resolve().parents[2]


def load(name: str) -> dict[str, object]:
    doc: dict[str, object] = json.loads(
        (ROOT / "docs" / "results" / f"{name}.json").read_text(encoding="utf-8")
    )
    return doc


@pytest.mark.parametrize("name", sorted(BLOCKS))
def test_readme_block_is_what_the_committed_results_render(name: str) -> None:
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    docs = {n: load(n) for n in BLOCKS[name][0]}
    start, end = f"<!-- results:{name} -->", f"<!-- /results:{name} -->"
    block = readme.split(start, 1)[1].split(end, 1)[0]
    assert block.strip() == render_block(name, docs).strip(), (
        f"README block {name} is stale: run taxelkit reproduce all --out docs/results "
        "--readme README.md"
    )


def test_update_blocks_rewrites_only_marked_blocks() -> None:
    doc = load("robustness")
    text = "a\n<!-- results:robustness -->\nSTALE-PLACEHOLDER\n<!-- /results:robustness -->\nb\n"
    new = update_blocks(text, {"robustness": doc, "fig7": {}})
    assert "| engine | imperfection |" in new
    assert new.endswith("<!-- /results:robustness -->\nb\n") and "STALE-PLACEHOLDER" not in new
    assert update_blocks("no markers", {"robustness": doc}) == "no markers"
    with pytest.raises(InputError, match="closing"):
        update_blocks("<!-- results:robustness --> open", {"robustness": doc})
