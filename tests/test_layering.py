"""Data flows one way: the CLI imports the library, the library never imports the CLI.

Walks every module's import statements (``ast``, nothing is imported) and
checks the direction of the layers in STYLE.md: the core imports neither the
experiments, the plotting nor the CLI; only ``__main__`` and the CLI package
import ``taxelkit.cli``.
"""

from __future__ import annotations

import ast
from pathlib import Path

import taxelkit

ROOT = Path(taxelkit.__file__).parent
#: Top-level packages above the core, each importing the core only.
UPPER = ("cli", "experiments", "plotting", "envs", "viewer")


def _imports(path: Path) -> set[str]:
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.module:
            names.add(node.module)
        elif isinstance(node, ast.Import):
            names.update(a.name for a in node.names)
    return names


def _package(module: str) -> str | None:
    """The taxelkit sub-package a dotted import names (None for other libraries)."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[0] == "taxelkit" else None


def _layer(path: Path) -> str:
    return path.relative_to(ROOT).parts[0].removesuffix(".py")


def test_the_cli_is_a_package_of_command_modules() -> None:
    modules = {p.stem for p in (ROOT / "cli").glob("*.py")}
    assert {"__init__", "app", "common", "options", "convert", "live"} <= modules
    assert {"paper000", "simulate", "smart", "sources"} <= modules
    assert not list(ROOT.glob("cli_*.py")), "CLI modules live in taxelkit/cli/"


def test_nothing_below_the_cli_imports_it() -> None:
    bad = {
        str(path.relative_to(ROOT)): hits
        for path in ROOT.rglob("*.py")
        if _layer(path) not in ("cli", "__main__")
        and (hits := {m for m in _imports(path) if _package(m) == "cli"})
    }
    assert not bad


def test_the_core_imports_no_upper_layer() -> None:
    bad = {
        str(path.relative_to(ROOT)): hits
        for path in ROOT.rglob("*.py")
        if _layer(path) not in (*UPPER, "__main__")
        and (hits := {m for m in _imports(path) if _package(m) in UPPER})
    }
    assert not bad


def test_the_checks_see_an_upward_import(tmp_path: Path) -> None:
    module = tmp_path / "bad.py"
    module.write_text("from taxelkit.cli.options import SEED\nimport taxelkit.plotting.strip\n")
    assert {_package(m) for m in _imports(module)} == {"cli", "plotting"}
    assert _package("viewer") is None and _package("taxelkit") is None
