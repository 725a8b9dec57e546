"""Every command that reads a file, fed every crafted file of the corpus.

Each case must end in exit code 2, exactly one line on stderr naming the
file, no traceback, and no output file left behind.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import pytest

from tests.fuzz._harness import assert_refused, files_under, invoke
from tests.fuzz.corpus import (
    CSV_CASES,
    H5_CASES,
    HEIGHTMAP_CASES,
    MCAP_CASES,
    MEMORY_CASES,
    MESH_CASES,
    NPZ_CASES,
    RECORDING_NPZ_CASES,
)

Command = Callable[[Path, Path], list[str | Path]]

#: Commands reading a recording FILE: (input, output folder) -> argv.
RECORDING_COMMANDS: dict[str, Command] = {
    "info": lambda f, out: ["info", f],
    "info-json": lambda f, out: ["info", f, "--json"],
    "show": lambda f, out: ["show", f, "--out", out / "strip.png"],
    "recognize": lambda f, out: ["recognize", f],
    "convert": lambda f, out: ["convert", f, out / "c.h5"],
}
#: Commands reading a heightmap.
HEIGHTMAP_COMMANDS: dict[str, Command] = {
    "trace": lambda f, out: ["trace", "--specimen", f, "--plot", out / "t.png"],
    "memorise": lambda f, out: ["memorise", "--specimen", f, "--name", "x", "--out", out / "m.npz"],
    "simulate-press": lambda f, out: ["simulate", "press", "--specimen", f, "--out", out / "p.npz"],
}
#: Commands reading a memory file.
MEMORY_COMMANDS: dict[str, Command] = {
    "trace": lambda f, out: ["trace", "--shape", "circle", "--memory", f],
    "memorise": lambda f, out: ["memorise", "--base", f, "--out", out / "m.npz"],
}
#: Commands reading a mesh.
MESH_COMMANDS: dict[str, Command] = {
    "simulate-solid": lambda f, out: ["simulate", "solid", "--mesh", f, "--out", out / "s.npz"],
}


def _check(tmp_path: Path, name: str, write: Callable[[Path], None], command: Command) -> None:
    folder = tmp_path / "in"
    folder.mkdir()
    out = tmp_path / "out"
    out.mkdir()
    path = folder / name
    write(path)
    before = files_under(tmp_path)
    line = assert_refused(invoke(command(path, out)))
    assert path.name in line, line
    assert files_under(tmp_path) == before, "a file was left behind"


def _cases(corpus: dict[str, Callable[[Path], None]], commands: dict[str, Command]) -> list:
    return [
        pytest.param(case, corpus[case], commands[cmd], id=f"{case}-{cmd}")
        for case in corpus
        for cmd in commands
    ]


@pytest.mark.parametrize(
    ("case", "write", "command"), _cases(NPZ_CASES["recording"], RECORDING_COMMANDS)
)
def test_damaged_npz_recording(tmp_path: Path, case: str, write, command: Command) -> None:
    _check(tmp_path, f"{case}.npz", write, command)


@pytest.mark.parametrize(
    ("case", "write", "command"), _cases(RECORDING_NPZ_CASES, RECORDING_COMMANDS)
)
def test_bad_npz_recording(tmp_path: Path, case: str, write, command: Command) -> None:
    _check(tmp_path, f"{case}.npz", write, command)


@pytest.mark.parametrize(("case", "write", "command"), _cases(H5_CASES, RECORDING_COMMANDS))
def test_bad_hdf5_recording(tmp_path: Path, case: str, write, command: Command) -> None:
    _check(tmp_path, f"{case}.h5", write, command)


@pytest.mark.parametrize(("case", "write", "command"), _cases(CSV_CASES, RECORDING_COMMANDS))
def test_bad_csv_recording(tmp_path: Path, case: str, write, command: Command) -> None:
    _check(tmp_path, f"{case}.csv", write, command)


@pytest.mark.parametrize(
    ("case", "write", "command"), _cases(NPZ_CASES["heightmap"], HEIGHTMAP_COMMANDS)
)
def test_damaged_heightmap(tmp_path: Path, case: str, write, command: Command) -> None:
    _check(tmp_path, f"{case}.npz", write, command)


@pytest.mark.parametrize(("case", "write", "command"), _cases(HEIGHTMAP_CASES, HEIGHTMAP_COMMANDS))
def test_bad_heightmap(tmp_path: Path, case: str, write, command: Command) -> None:
    _check(tmp_path, f"{case}.npz", write, command)


@pytest.mark.parametrize(("case", "write", "command"), _cases(NPZ_CASES["memory"], MEMORY_COMMANDS))
def test_damaged_memory(tmp_path: Path, case: str, write, command: Command) -> None:
    _check(tmp_path, f"{case}.npz", write, command)


@pytest.mark.parametrize(("case", "write", "command"), _cases(MEMORY_CASES, MEMORY_COMMANDS))
def test_bad_memory(tmp_path: Path, case: str, write, command: Command) -> None:
    _check(tmp_path, f"{case}.npz", write, command)


@pytest.mark.parametrize(
    ("case", "suffix", "write"),
    [pytest.param(case, suffix, write, id=case) for case, (suffix, write) in MESH_CASES.items()],
)
def test_bad_mesh(tmp_path: Path, case: str, suffix: str, write) -> None:
    _check(tmp_path, f"{case}{suffix}", write, MESH_COMMANDS["simulate-solid"])


@pytest.mark.parametrize(("case", "write", "command"), _cases(MCAP_CASES, RECORDING_COMMANDS))
def test_bad_mcap_recording(tmp_path: Path, case: str, write, command: Command) -> None:
    pytest.importorskip("mcap")
    pytest.importorskip("rosbags")
    _check(tmp_path, f"{case}.mcap", write, command)


def test_rosbag2_folder_with_a_symbolic_link_is_refused(tmp_path: Path) -> None:
    pytest.importorskip("rosbags")
    secret = tmp_path / "secret.db3"
    secret.write_bytes(b"private")
    bag = tmp_path / "bag"
    bag.mkdir()
    (bag / "metadata.yaml").write_text("rosbag2_bagfile_information: {}\n")
    (bag / "bag_0.db3").symlink_to(secret)
    for argv in (["info", bag], ["recognize", bag], ["convert", bag, tmp_path / "c.npz"]):
        line = assert_refused(invoke(argv), contains="symbolic link")
        assert "bag" in line
    assert not (tmp_path / "c.npz").exists()
