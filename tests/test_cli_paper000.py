"""End-to-end tests of ``taxelkit trace``, ``memorise`` and ``reproduce`` (paper 000)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from taxelkit.cli import run
from taxelkit.world.relief import heightmap_from_relief, relief_from_vertices, relief_shape


def _run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = run(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_trace_shape_json_recognises_a_rotated_translated_hexagon(
    capsys: pytest.CaptureFixture[str],
) -> None:
    code, out, err = _run(
        capsys, "trace", "--shape", "hexagon", "--rotate-deg", "20", "--offset-mm", "3,4",
        "--seed", "1", "--json",
    )  # fmt: skip
    assert code == 0, err
    doc = json.loads(out)
    assert set(doc) >= {"trajectory_mm", "closed", "recognised", "correlations", "recall_curve"}
    assert doc["closed"] is True
    assert doc["recognised"] == "hexagon"
    assert set(doc["correlations"]) == {"circle", "square", "triangle", "star", "hexagon"}
    assert doc["recall_curve"][-1]["s"] == pytest.approx(1.0)
    # Open-set fields: calibrated probabilities, unknown, when it was decided, the margin.
    assert set(doc["probabilities"]) == set(doc["correlations"])
    assert sum(doc["probabilities"].values()) == pytest.approx(1.0)
    assert max(doc["probabilities"], key=doc["probabilities"].get) == "hexagon"
    assert doc["unknown"] is False and doc["open_set_verdict"] == "hexagon"
    assert 0.0 < doc["decided_at_s"] <= 1.0 and doc["calibrated"] is True
    assert doc["margin"] > 0 and doc["verdict"] == "hexagon"
    traj = np.asarray(doc["trajectory_mm"])
    assert traj.shape[1] == 2 and traj.shape[0] > 50


def _save_heightmap(relief: object, path: Path, pixel_mm: float, half_mm: float) -> None:
    hm = heightmap_from_relief(relief, pixel_mm=pixel_mm, extent_mm=(-half_mm, half_mm) * 2)  # type: ignore[arg-type]
    np.savez(path, **hm.to_arrays())


def test_trace_user_heightmap_uses_only_the_trajectory(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A user-made heightmap of a rotated, translated, scaled square is recognised as a square."""
    relief = relief_shape("square", diameter_mm=90.0, rotation_deg=37.0, offset_mm=(6.0, -4.0),
                          scale=0.9)  # fmt: skip
    spec = tmp_path / "my_square.npz"
    _save_heightmap(relief, spec, 0.25, 60.0)
    code, out, err = _run(capsys, "trace", "--specimen", str(spec), "--json")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["closed"] and doc["recognised"] == "square"


def test_memorise_a_new_shape_then_recall_it(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # A long bar: its direction histogram (0.38 / 0.12 per side) differs from the square's.
    # (An L-shape would not do: its edges give exactly the square's histogram, which no
    # chain code can tell apart.)
    bar = relief_from_vertices([(-40, -12), (40, -12), (40, 12), (-40, 12)])
    spec = tmp_path / "bar.npz"
    _save_heightmap(bar, spec, 0.25, 45.0)
    mem = tmp_path / "mem.npz"
    code, out, err = _run(
        capsys, "memorise", "--specimen", str(spec), "--name", "bar", "--out", str(mem)
    )
    assert code == 0, err
    assert "bar" in out
    code, out, err = _run(capsys, "trace", "--specimen", str(spec), "--memory", str(mem),
                          "--seed", "5", "--json")  # fmt: skip
    assert code == 0, err
    assert json.loads(out)["recognised"] == "bar"
    code, _, err = _run(capsys, "memorise", "--specimen", str(spec), "--name", "bar",
                        "--out", str(mem))  # fmt: skip
    assert code == 2 and "--force" in err


def test_memorise_reports_shapes_it_cannot_tell_apart(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # An L-shape has the square's direction histogram: the memory cannot tell them apart.
    ell = relief_from_vertices([(-30, -30), (30, -30), (30, 0), (0, 0), (0, 30), (-30, 30)])
    spec = tmp_path / "ell.npz"
    _save_heightmap(ell, spec, 0.25, 40.0)
    code, _, err = _run(capsys, "memorise", "--specimen", str(spec), "--name", "ell",
                          "--out", str(tmp_path / "mem.npz"))  # fmt: skip
    assert code == 0, err
    assert "cannot tell apart ell and square" in err


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["trace"], "exactly one of"),
        (["trace", "--shape", "blob"], "blob"),
        (["trace", "--shape", "star", "--rule", "nope"], "nope"),
        (["reproduce", "fig99", "--out", "x"], "fig99"),
        (["trace", "--shape", "star", "--memory", "missing.npz"], "missing.npz"),
    ],
)
def test_bad_paper000_input_is_one_line_exit_2(
    argv: list[str], needle: str, capsys: pytest.CaptureFixture[str]
) -> None:
    code, _, err = _run(capsys, *argv)
    assert code == 2
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and needle in lines[0]


def test_reproduce_recall_vs_s_small_run_has_the_documented_keys(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, _, err = _run(capsys, "reproduce", "recall-vs-s", "--out", str(tmp_path),
                        "--trials", "2", "--workers", "1")  # fmt: skip
    assert code == 0, err
    doc = json.loads((tmp_path / "recall-vs-s.json").read_text())
    assert doc["s"][0] == 0.2 and doc["s"][-1] == 1.0
    assert set(doc["improved"]["fraction_correct"]) == {
        "circle", "square", "triangle", "star", "hexagon"
    }  # fmt: skip
    assert doc["n_trials_per_shape"] == 2
