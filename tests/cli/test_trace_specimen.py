"""``taxelkit trace --specimen`` with the shape options: applied to the heightmap, not ignored."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from taxelkit.cli import run
from taxelkit.world.relief import heightmap_from_relief, relief_shape


def _run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = run(list(argv))
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.fixture(scope="module")
def square_npz(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A heightmap of the 90 mm, 200 um square, axis-aligned and centred."""
    path = tmp_path_factory.mktemp("spec") / "square.npz"
    hm = heightmap_from_relief(relief_shape("square"), pixel_mm=0.5, extent_mm=(-50, 50, -50, 50))
    np.savez(path, **hm.to_arrays())
    return path


def test_shape_options_move_turn_resize_the_heightmap(
    square_npz: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The trace follows the square where the options put it: 63 mm, turned 30 deg, at (8, -5)."""
    code, out, err = _run(
        capsys, "trace", "--specimen", str(square_npz), "--diameter-mm", "63",
        "--rotate-deg", "30", "--offset-mm", "8,-5", "--step-height-um", "100", "--json",
    )  # fmt: skip
    assert code == 0, err
    doc = json.loads(out)
    assert doc["closed"] and doc["recognised"] == "square"
    truth = relief_shape("square", diameter_mm=63.0, rotation_deg=30.0, offset_mm=(8.0, -5.0))
    d = truth.distance_to_edge_mm(np.asarray(doc["trajectory_mm"]))
    assert float(d.mean()) < 0.5  # on the placed square's outline, not the file's


def test_without_options_the_heightmap_is_traced_as_stored(
    square_npz: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    code, out, err = _run(capsys, "trace", "--specimen", str(square_npz), "--json")
    assert code == 0, err
    d = relief_shape("square").distance_to_edge_mm(np.asarray(json.loads(out)["trajectory_mm"]))
    assert float(d.mean()) < 0.5


def test_a_flat_heightmap_cannot_be_sized(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    flat = tmp_path / "flat.npz"
    np.savez(flat, height_mm=np.zeros((20, 20)), pixel_mm=np.array(1.0))
    code, out, err = _run(capsys, "trace", "--specimen", str(flat), "--diameter-mm", "50")
    assert code == 2 and out == ""
    assert len(err.strip().splitlines()) == 1 and "no raised relief" in err
