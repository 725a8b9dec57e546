"""What a reproduce run records of the machine and libraries it ran on."""

from __future__ import annotations

import doctest
import json
from pathlib import Path

import numpy as np
from click.testing import CliRunner

import taxelkit.experiments.run_environment as env_module
from taxelkit.cli import cli
from taxelkit.experiments.run_environment import run_environment
from tests.test_schemas import assert_valid


def test_docstring_examples() -> None:
    assert doctest.testmod(env_module).failed == 0


def test_the_environment_names_numpy_and_its_blas() -> None:
    env = run_environment()
    assert env["libraries"]["numpy"] == np.__version__
    assert env["blas"] and env["cpu"] and env["python"].count(".") == 2
    assert all(isinstance(s, str) for s in env["numpy_simd"])
    json.dumps(env)  # JSON-serialisable as it is


def test_the_openblas_override_is_recorded(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    monkeypatch.setenv("OPENBLAS_CORETYPE", "Prescott")
    assert run_environment()["openblas_coretype"] == "Prescott"
    monkeypatch.delenv("OPENBLAS_CORETYPE")
    assert run_environment()["openblas_coretype"] is None


def test_numpys_disabled_simd_targets_are_recorded(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    monkeypatch.setenv("NPY_DISABLE_CPU_FEATURES", "X86_V4")
    assert run_environment()["numpy_disabled_features"] == "X86_V4"
    monkeypatch.delenv("NPY_DISABLE_CPU_FEATURES")
    assert run_environment()["numpy_disabled_features"] is None


def test_reproduce_writes_the_environment_beside_the_timing(tmp_path: Path) -> None:
    res = CliRunner().invoke(cli, ["reproduce", "fig7", "--out", str(tmp_path)])
    assert res.exit_code == 0, res.output
    timing = json.loads((tmp_path / "fig7.timing.json").read_text(encoding="utf-8"))
    assert_valid("experiment-timing", timing)
    assert timing["environment"]["libraries"]["numpy"] == np.__version__
    assert "environment" not in json.loads((tmp_path / "fig7.json").read_text(encoding="utf-8"))
