"""``taxelkit reproduce``: nothing silently changed or ignored, progress that means something."""

from __future__ import annotations

import dataclasses
import io
import json
from pathlib import Path
from typing import Any

import pytest

from taxelkit.cli import run
from taxelkit.cli.common import progress_bar
from taxelkit.experiments.registry import EXPERIMENTS


class _Called(Exception):
    """Raised by a stub experiment to hand back the keywords it was called with."""


def _stub(monkeypatch: pytest.MonkeyPatch, name: str) -> None:
    def run_stub(**kwargs: Any) -> Any:
        raise _Called(kwargs)

    monkeypatch.setitem(EXPERIMENTS, name, dataclasses.replace(EXPERIMENTS[name], run=run_stub))


def _kwargs(argv: list[str]) -> dict[str, Any]:
    with pytest.raises(_Called) as called:
        run(argv)
    kwargs: dict[str, Any] = called.value.args[0]
    return kwargs


def test_each_experiment_runs_its_own_trials_unless_told(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    for name in ("recall-vs-s", "smart-sensor", "tacteme-table", "robustness"):
        _stub(monkeypatch, name)
        argv = ["reproduce", name, "--out", str(tmp_path)]
        assert _kwargs(argv)["n_trials"] == EXPERIMENTS[name].trials
        assert _kwargs([*argv, "--trials", "5"])["n_trials"] == 5  # used as given, not raised
    assert EXPERIMENTS["smart-sensor"].trials == 100  # the committed results' setting
    committed = Path(__file__).parents[2] / "docs" / "results" / "smart-sensor.json"
    assert json.loads(committed.read_text())["n_trials_per_object"] == 100


def test_smart_sensor_with_few_trials_runs_them(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["reproduce", "smart-sensor", "--trials", "1", "--workers", "1", "--out", str(tmp_path)]
    assert run(argv) == 0
    doc = json.loads((tmp_path / "smart-sensor.json").read_text())
    assert doc["n_trials_per_object"] == 1 and doc["member_trials"] == 6
    err = capsys.readouterr().err
    assert "smart-sensor" in err and "/106" in err and "trial" in err  # 6 + 100 sliding


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["reproduce", "fig7", "--trials", "5"], "--trials applies only to recall-vs-s"),
        (["reproduce", "cylinder", "--workers", "2"], "--workers applies only to"),
        (["reproduce", "smart-sensor", "--scheduler", "tcp://h:1"], "--scheduler applies only"),
    ],
)
def test_an_option_no_experiment_uses_is_refused(
    argv: list[str], needle: str, tmp_path: Path
) -> None:
    errors: list[str] = []
    assert run([*argv, "--out", str(tmp_path / "r")], echo_err=errors.append) == 2
    assert len(errors) == 1 and needle in errors[0], errors
    assert not (tmp_path / "r").exists()


def test_all_passes_trials_to_those_that_take_them(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    _stub(monkeypatch, "fig7")  # the first of 'all'
    kwargs = _kwargs(["reproduce", "all", "--trials", "3", "--out", str(tmp_path)])
    assert "n_trials" not in kwargs and "workers" not in kwargs


def test_progress_opens_with_a_known_total_and_a_unit() -> None:
    stream = io.StringIO()
    with pytest.MonkeyPatch.context() as m:
        m.setattr("sys.stderr", stream)
        with progress_bar("fig8", "shape") as progress:
            progress(1, 5)
            progress(5, 5)
    text = stream.getvalue()
    assert "fig8" in text and "/5" in text and "shape" in text
    assert "0run" not in text and "?run" not in text


def test_a_run_that_reports_nothing_draws_nothing() -> None:
    stream = io.StringIO()
    with pytest.MonkeyPatch.context() as m:
        m.setattr("sys.stderr", stream)
        with progress_bar("quiet", "trial"):
            pass
    assert stream.getvalue() == ""


def test_reproduce_progress_names_the_experiment_and_its_unit(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert run(["reproduce", "cylinder", "--out", str(tmp_path)]) == 0
    err = capsys.readouterr().err
    assert "cylinder:" in err and "/1" in err and "roll" in err
    assert "0run" not in err


def test_a_block_of_two_experiments_is_rendered_from_the_one_run_and_the_other_committed(
    tmp_path: Path,
) -> None:
    from taxelkit.cli.reproduce import _with_companions

    committed = Path(__file__).parents[2] / "docs" / "results"
    held = json.loads((committed / "new-objects-heldout.json").read_text())
    docs = _with_companions({"new-objects-heldout": held}, committed)
    assert set(docs) == {"new-objects-heldout", "new-objects"}  # the block's companion
    assert docs["new-objects"]["experiment"] == "new-objects"
    assert _with_companions({"new-objects-heldout": held}, tmp_path) == {
        "new-objects-heldout": held
    }  # nothing there: the block is left as it is
    assert set(_with_companions({"fig7": {}}, committed)) == {"fig7"}
