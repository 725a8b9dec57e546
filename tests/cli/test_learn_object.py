"""``taxelkit learn-object`` and ``recognize --objects``: tables written safely, one-line errors."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
import trimesh

from taxelkit.cli import run

ROOT = Path(__file__).resolve().parents[2]
HEX = ROOT / "examples" / "objects" / "hex-prism.stl"


def _run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = run(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


def _error(err: str) -> str:
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("taxelkit: error:"), err
    return lines[0]


def test_learn_adds_objects_and_replaces_only_with_force(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    table = tmp_path / "objects.json"
    code, out, _ = _run(capsys, "learn-object", str(HEX), "--name", "nut", "--out", str(table),
                        "--checks", "2")  # fmt: skip
    assert code == 0 and "LC -> AC -> LC (60 or 120 deg)" in out
    assert "cannot tell apart: cube is never identified beside nut" in out
    code, out, _ = _run(capsys, "learn-object", str(HEX), "--name", "bolt", "--out", str(table),
                        "--checks", "0")  # fmt: skip
    assert code == 0
    doc = json.loads(table.read_text())
    assert doc["format"] == "taxelkit-object-table" and doc["version"] == 1
    assert [o["name"] for o in doc["objects"]] == ["nut", "bolt"]
    before = table.read_text()
    code, _, err = _run(capsys, "learn-object", str(HEX), "--name", "nut", "--out", str(table))
    assert code == 2 and "--force" in _error(err) and table.read_text() == before
    code, _, _ = _run(capsys, "learn-object", str(HEX), "--name", "nut", "--out", str(table),
                      "--checks", "0", "--force")  # fmt: skip
    assert code == 0 and [o["name"] for o in json.loads(table.read_text())["objects"]] == [
        "nut", "bolt"]  # fmt: skip


def test_bad_meshes_and_names_end_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = str(tmp_path / "t.json")
    trimesh.creation.annulus(r_min=4.0, r_max=8.0, height=4.0).export(tmp_path / "ring.stl")
    (tmp_path / "junk.stl").write_bytes(b"solid x\nfacet nonsense\n")
    (tmp_path / "notes.txt").write_text("hello")
    cases = [
        (["learn-object", str(tmp_path / "ring.stl"), "--name", "ring"], "not convex"),
        (["learn-object", str(tmp_path / "junk.stl"), "--name", "junk"], "junk.stl"),
        (["learn-object", str(tmp_path / "notes.txt"), "--name", "n"], "suffix"),
        (["learn-object", str(tmp_path / "missing.stl"), "--name", "m"], "missing.stl"),
        (["learn-object", str(HEX), "--name", "Bad Name"], "--name"),
        (["learn-object", str(HEX), "--name", "cube"], "six objects"),
    ]
    for argv, needle in cases:
        code, _, err = _run(capsys, *argv, "--out", out, "--checks", "0")
        assert code == 2, argv
        assert needle in _error(err), (argv, err)
    assert not Path(out).exists()
    code, _, _ = _run(capsys, "learn-object", str(tmp_path / "ring.stl"), "--name", "ring",
                      "--hull", "--out", out, "--checks", "0")  # fmt: skip
    assert code == 0  # the convex hull of a ring is a disc


def test_recognize_with_a_bad_table_ends_in_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    rec = tmp_path / "roll.npz"
    assert _run(capsys, "simulate", "roll", "--object", "cube", "--out", str(rec))[0] == 0
    bad = tmp_path / "bad.json"
    bad.write_text('{"format": "taxelkit-object-table", "version": 7, "objects": []}')
    code, _, err = _run(capsys, "recognize", str(rec), "--objects", str(bad))
    assert code == 2 and "version" in _error(err)
    code, _, err = _run(capsys, "recognize", str(rec), "--objects", str(tmp_path / "none.json"))
    assert code == 2 and "none.json" in _error(err)
    shutil.copy(HEX, tmp_path / "x.stl")
    code, _, err = _run(capsys, "simulate", "roll", "--mesh", str(tmp_path / "x.stl"),
                        "--object", "cube", "--out", str(tmp_path / "y.npz"))  # fmt: skip
    assert code == 2 and "exactly one" in _error(err)
