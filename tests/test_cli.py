"""End-to-end tests of the ``taxelkit`` command line."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from taxelkit.cli import cli, run
from taxelkit.io.recordings import read_recording


def _run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = run(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def _one_line_error(err: str) -> str:
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, f"expected one line on stderr, got {err!r}"
    assert lines[0].startswith("taxelkit: error:"), lines[0]
    assert "Traceback" not in err
    return lines[0]


def test_version_and_help_on_every_command(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = _run(capsys, "--version")
    assert code == 0 and "taxelkit" in out
    names = [[]] + [[c] for c in cli.commands]  # type: ignore[attr-defined]
    names += [["simulate", c] for c in cli.commands["simulate"].commands]  # type: ignore[attr-defined]
    for argv in names:
        code, out, _ = _run(capsys, *argv, "--help")
        assert code == 0, argv
        assert "Usage:" in out


@pytest.fixture
def good_npz(tmp_path: Path) -> Path:
    path = tmp_path / "good.npz"
    frames = np.random.default_rng(0).random((5, 4, 3))
    np.savez(path, frames=frames, t_s=np.arange(5) * 0.1, pitch_mm=2.0)
    return path


def test_info_summarises_a_recording(capsys: pytest.CaptureFixture[str], good_npz: Path) -> None:
    code, out, _ = _run(capsys, "info", str(good_npz), "--json")
    assert code == 0
    s = json.loads(out)
    assert (s["frames"], s["rows"], s["cols"]) == (5, 4, 3)
    assert s["pitch_mm"] == 2.0
    assert s["rate_hz"] == pytest.approx(10.0)
    assert s["duration_s"] == pytest.approx(0.4)
    code, out, _ = _run(capsys, "info", str(good_npz))
    assert code == 0 and "5 x 4 x 3" in out and "10 Hz" in out


def _bad_files(tmp: Path) -> dict[str, Path]:
    files: dict[str, Path] = {}
    files["ndim"] = tmp / "ndim.npz"
    np.savez(files["ndim"], frames=np.zeros((4, 4)))
    files["nan"] = tmp / "nan.npz"
    np.savez(files["nan"], frames=np.full((2, 3, 3), np.nan))
    files["inf_h5"] = tmp / "inf.h5"
    with h5py.File(files["inf_h5"], "w") as f:
        f["frames"] = np.full((2, 3, 3), np.inf)
    files["time"] = tmp / "time.npz"
    np.savez(files["time"], frames=np.zeros((3, 2, 2)), t_s=[0.0, 0.2, 0.1])
    files["empty"] = tmp / "empty.csv"
    files["empty"].write_bytes(b"")
    files["empty_npz"] = tmp / "empty.npz"
    files["empty_npz"].write_bytes(b"")
    files["zero_frames"] = tmp / "zero.npz"
    np.savez(files["zero_frames"], frames=np.zeros((0, 4, 4)))
    good = tmp / "good_src.npz"
    np.savez(good, frames=np.random.default_rng(1).random((50, 16, 16)))
    files["truncated"] = tmp / "truncated.npz"
    files["truncated"].write_bytes(good.read_bytes()[: good.stat().st_size // 2])
    files["corrupt_h5"] = tmp / "corrupt.h5"
    files["corrupt_h5"].write_bytes(b"\x89HDF\r\n\x1a\n" + bytes(range(256)) * 4)
    files["unknown_ext"] = tmp / "frames.mat"
    files["unknown_ext"].write_bytes(b"whatever")
    files["csv_columns"] = tmp / "columns.csv"
    files["csv_columns"].write_text("t_s,r0c0,r0c1,r1c1\n0,1,2,3\n")
    files["csv_ragged"] = tmp / "ragged.csv"
    files["csv_ragged"].write_text("t_s,r0c0,r0c1\n0,1,2\n1,2\n")
    files["missing"] = tmp / "does_not_exist.npz"
    return files


BAD = [
    "ndim",
    "nan",
    "inf_h5",
    "time",
    "empty",
    "empty_npz",
    "zero_frames",
    "truncated",
    "corrupt_h5",
    "unknown_ext",
    "csv_columns",
    "csv_ragged",
    "missing",
]


@pytest.mark.parametrize("case", BAD)
def test_bad_input_gives_one_line_and_exit_2(
    case: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _bad_files(tmp_path)[case]
    code, out, err = _run(capsys, "info", str(path))
    assert code == 2
    line = _one_line_error(err)
    assert path.name in line
    assert out == ""


def test_usage_errors_are_one_line_exit_2(capsys: pytest.CaptureFixture[str]) -> None:
    code, _, err = _run(capsys, "simulate", "solid", "--object", "cube", "--at", "1", "--out", "x")
    assert code == 2
    _one_line_error(err)
    code, _, err = _run(capsys, "no-such-command")
    assert code == 2
    _one_line_error(err)


@pytest.mark.parametrize("fmt", ["npz", "h5", "csv"])
def test_simulated_recording_reads_back_identical_in_every_format(
    fmt: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    paths = {}
    for ext in ("npz", "h5", "csv"):
        paths[ext] = tmp_path / f"press.{ext}"
        code, _, err = _run(
            capsys, "simulate", "press", "--shape", "square", "--at", "25,0", "--to", "35,0",
            "--frames", "6", "--seed", "3", "--out", str(paths[ext]),
        )  # fmt: skip
        assert code == 0, err
    ref = read_recording(paths["npz"])
    rec = read_recording(paths[fmt])
    assert rec.equals(ref)
    assert rec.shape == (6, 10, 13) and rec.sensor == "optical-3axis"
    assert rec.frames.max() > 0.2  # the 200 um step is under the array


def test_simulate_solid_contact_images(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "cube.csv"
    code, _, err = _run(
        capsys, "simulate", "solid", "--object", "cube", "--indent-mm", "0.3", "--frames", "4",
        "--contact", "--out", str(out),
    )  # fmt: skip
    assert code == 0, err
    rec = read_recording(out)
    assert rec.is_contact and rec.shape == (4, 16, 16)
    assert rec.frames[0].sum() == 0  # the press starts at zero depth
    assert rec.frames[-1].sum() > 30  # a 12 mm face covers dozens of taxels


def test_existing_output_is_not_overwritten_without_force(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "x.npz"
    out.write_bytes(b"precious")
    argv = ["simulate", "solid", "--object", "sphere", "--out", str(out)]
    code, _, err = _run(capsys, *argv)
    assert code == 2
    assert "--force" in _one_line_error(err)
    assert out.read_bytes() == b"precious"
    code, _, _ = _run(capsys, *argv, "--force")
    assert code == 0
    assert read_recording(out).n_frames == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.npz"]  # no temporary left


def test_show_writes_a_png(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    rec = tmp_path / "r.npz"
    np.savez(rec, frames=np.random.default_rng(2).random((20, 16, 16)))
    png = tmp_path / "strip.png"
    code, _, err = _run(capsys, "show", str(rec), "--out", str(png), "--max-frames", "5")
    assert code == 0, err
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    code, _, err = _run(capsys, "show", str(rec), "--out", str(png))
    assert code == 2 and "--force" in _one_line_error(err)
    code, _, err = _run(capsys, "show", str(rec), "--out", str(tmp_path / "strip.txt"))
    assert code == 2


def test_demo_writes_figures_and_recordings(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, out, err = _run(capsys, "demo", "--out", str(tmp_path / "d"))
    assert code == 0, err
    for name in (
        "demo-relief.png",
        "demo-solids.png",
        "demo-relief.npz",
        "demo-solids.npz",
        "demo-trace.png",
    ):
        assert (tmp_path / "d" / name).stat().st_size > 0
    assert "recognised as 'star'" in out  # paper 000 end to end
    assert "Fig. 3 cylinder -> tactemes AC, PC, LC, LCM, LCMP; identified: cylinder" in out
    assert (tmp_path / "d" / "demo-smart.png").stat().st_size > 0
    solids = read_recording(tmp_path / "d" / "demo-solids.npz")
    assert solids.is_contact and solids.n_frames == 18
    # every one of the 18 presses touches the sensor
    assert np.all(solids.frames.reshape(18, -1).sum(axis=1) > 0)


def test_console_script_runs_as_a_process(good_npz: Path) -> None:
    proc = subprocess.run(
        [sys.executable, "-m", "taxelkit", "info", str(good_npz)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    bad = subprocess.run(
        [sys.executable, "-m", "taxelkit", "info", str(good_npz.with_suffix(".xyz"))],
        capture_output=True,
        text=True,
        check=False,
    )
    assert bad.returncode == 2
    assert len(bad.stderr.strip().splitlines()) == 1
