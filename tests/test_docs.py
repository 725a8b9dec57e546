"""Every Python block of the tutorials runs as written (in a temporary folder)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[1] / "docs"
TUTORIALS = sorted((DOCS / "tutorials").glob("*.md"))
_BLOCK = re.compile(r"^```python\n(.*?)^```", re.MULTILINE | re.DOTALL)


def python_blocks(page: Path) -> list[str]:
    """The ```python blocks of a Markdown page, in order."""
    return _BLOCK.findall(page.read_text(encoding="utf-8"))


def test_there_are_tutorials_with_code() -> None:
    assert len(TUTORIALS) >= 3
    assert all(python_blocks(page) for page in TUTORIALS)


@pytest.mark.parametrize("page", TUTORIALS, ids=lambda p: p.stem)
def test_tutorial_runs(page: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from taxelkit.io import source_plugins

    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("MPLBACKEND", "Agg")
    monkeypatch.setattr(source_plugins, "_REGISTERED", {})  # a tutorial may register a source
    namespace: dict[str, object] = {"__name__": "__tutorial__"}
    for k, block in enumerate(python_blocks(page)):
        code = compile(block, f"{page.name} block {k + 1}", "exec")
        exec(code, namespace)


def test_gym_page_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    pytest.importorskip("gymnasium", reason="the gym page needs the gym extra")
    monkeypatch.chdir(tmp_path)
    namespace: dict[str, object] = {"__name__": "__tutorial__"}
    for block in python_blocks(DOCS / "gym.md"):
        exec(compile(block, "gym.md", "exec"), namespace)
