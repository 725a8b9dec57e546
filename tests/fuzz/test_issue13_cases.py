"""One test per case listed in issue 13 ("Hostile files and options").

Each ends in one line on stderr, exit code 2 and no traceback; the HDF5
external-storage case also proves that the named file is never opened.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import threading
import time
import zipfile
from pathlib import Path

import h5py
import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.experiments.paper000_common import FAITHFUL, reference_memory
from taxelkit.frames import TactileFrames
from taxelkit.io.recordings import write_recording
from taxelkit.smart.recogniser import SmartSensor
from tests.fuzz._harness import assert_refused, files_under, invoke
from tests.fuzz.corpus import BOMB_SHAPE, MEMORY_CASES, NPZ_CASES, npy_bytes, zip_of


# ----------------------------------------------------------------------------- memories
def _memory_file(tmp_path: Path, case: str) -> Path:
    path = tmp_path / f"{case}.npz"
    if case == "truncated":
        np.savez(path, **reference_memory(FAITHFUL).to_arrays())
        path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    elif case == "m-200000":
        MEMORY_CASES["m-200000"](path)
    else:
        NPZ_CASES["memory"][case](path)
    return path


@pytest.mark.parametrize(
    ("case", "expected"),
    [
        ("truncated", "unreadable .npz memory file"),
        ("text", "no zip signature"),
        ("empty", "is empty (0 bytes)"),
        ("bare-npy", "single .npy array"),
        ("m-200000", "over the read limit"),
    ],
)
@pytest.mark.parametrize("reader", ["trace --memory", "memorise --base"])
def test_hostile_memory_file(tmp_path: Path, case: str, expected: str, reader: str) -> None:
    path = _memory_file(tmp_path, case)
    out = tmp_path / "out.npz"
    if reader == "trace --memory":
        argv: list[str | Path] = ["trace", "--shape", "circle", "--memory", path]
    else:
        argv = ["memorise", "--base", path, "--out", out]
    assert_refused(invoke(argv), contains=expected)
    assert not out.exists()


# ----------------------------------------------------------------------------- heightmaps
@pytest.mark.parametrize(
    "argv",
    [
        ["trace", "--specimen", "{f}"],
        ["memorise", "--specimen", "{f}", "--name", "x", "--out", "{d}/m.npz"],
        ["simulate", "press", "--specimen", "{f}", "--out", "{d}/p.npz"],
    ],
)
@pytest.mark.parametrize("shape", [(100_000, 100_000), (2**31, 2**31)])
def test_heightmap_declaring_a_huge_shape(tmp_path: Path, argv: list[str], shape: tuple) -> None:
    path = tmp_path / "huge.npz"
    header = np.lib.format.header_data_from_array_1_0(np.zeros((1, 1)))
    header["shape"] = shape
    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, header)
    member = buf.getvalue() + b"\0" * 800
    path.write_bytes(zip_of({"height_mm.npy": member, "pixel_mm.npy": npy_bytes(np.array(1.0))}))
    filled = [a.format(f=path, d=tmp_path) for a in argv]
    assert_refused(invoke(filled), contains="height_mm")
    assert files_under(tmp_path) == {path}


def test_heightmap_with_heights_of_1e300_is_one_line(tmp_path: Path) -> None:
    path = tmp_path / "tall.npz"
    np.savez(path, height_mm=np.full((9, 9), 1e300), pixel_mm=1.0)
    assert_refused(invoke(["trace", "--specimen", path]), contains="within +-1000 mm")


# ----------------------------------------------------------------------------- HDF5
def test_hdf5_external_storage_is_refused_without_opening_the_named_file(
    tmp_path: Path,
) -> None:
    # The named file lies outside the recording's folder and is a FIFO: opening
    # it for reading is what releases the writer thread, so `opened` records
    # whether anything opened it at all (read or not).
    elsewhere = tmp_path / "home" / "user"
    elsewhere.mkdir(parents=True)
    secret = elsewhere / "secret.bin"
    os.mkfifo(secret)
    downloads = tmp_path / "downloads"
    downloads.mkdir()
    recording = downloads / "run.h5"
    with h5py.File(recording, "w") as root:
        root.create_dataset("frames", shape=(2, 2, 2), dtype="f8", external=[(str(secret), 0, 64)])
    opened = threading.Event()

    def writer() -> None:
        fd = os.open(secret, os.O_WRONLY)  # blocks until a reader opens the FIFO
        opened.set()
        with contextlib.suppress(OSError):
            os.write(fd, np.arange(8, dtype=np.float64).tobytes())
        os.close(fd)

    thread = threading.Thread(target=writer, daemon=True)
    thread.start()
    try:
        for argv in (
            ["info", recording],
            ["info", recording, "--json"],
            ["show", recording, "--out", downloads / "s.png"],
            ["recognize", recording],
        ):
            result = invoke(argv)
            assert_refused(result, contains="external file")
            assert "secret.bin" in result.err
        time.sleep(0.2)
        assert not opened.is_set(), "taxelkit opened the file named by the external storage"
        # Control: reading the dataset with h5py directly does open it, so the
        # check above can fail.
        with h5py.File(recording, "r") as root, contextlib.suppress(Exception):
            root["frames"][()]
        assert opened.wait(10)
    finally:
        with contextlib.suppress(OSError):  # release the writer if nothing opened the FIFO
            os.close(os.open(secret, os.O_RDONLY | os.O_NONBLOCK))
        thread.join(10)


def test_mesh_side_files_are_never_opened(tmp_path: Path) -> None:
    # An OBJ naming a material library elsewhere (a FIFO, as above): the mesh
    # itself is read, the library never opened.
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    library = elsewhere / "private.mtl"
    os.mkfifo(library)
    mesh = tmp_path / "tetra.obj"
    mesh.write_text(
        f"mtllib {library}\nusemtl x\nv 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 10\n"
        "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
    )
    opened = threading.Event()

    def writer() -> None:
        fd = os.open(library, os.O_WRONLY)  # blocks until a reader opens the FIFO
        opened.set()
        with contextlib.suppress(OSError):
            os.write(fd, b"newmtl x\nKd 1 0 0\n")
        os.close(fd)

    thread = threading.Thread(target=writer, daemon=True)
    thread.start()
    try:
        out = tmp_path / "s.npz"
        result = invoke(["simulate", "solid", "--mesh", mesh, "--no-noise", "--out", out])
        assert result.code == 0, result.err
        assert out.exists()
        time.sleep(0.2)
        assert not opened.is_set(), "the material library named by the OBJ was opened"
    finally:
        with contextlib.suppress(OSError):
            os.close(os.open(library, os.O_RDONLY | os.O_NONBLOCK))
        thread.join(10)


# ----------------------------------------------------------------------------- options
@pytest.mark.parametrize(
    "argv",
    [
        ["simulate", "press", "--shape", "circle", "--seed", "-1", "--out", "{d}/p.npz"],
        ["simulate", "solid", "--object", "cube", "--seed", "-1", "--out", "{d}/s.npz"],
        ["simulate", "roll", "--object", "cube", "--seed", "-1", "--out", "{d}/r.npz"],
        ["trace", "--shape", "circle", "--seed", "-1"],
        ["memorise", "--seed", "-1", "--out", "{d}/m.npz"],
        ["reproduce", "fig7", "--seed", "-1", "--out", "{d}/r"],
        ["demo", "--seed", "-1", "--out", "{d}/demo"],
        ["reproduce", "fig7", "--seed", str(2**63), "--out", "{d}/r"],
    ],
)
def test_seed_out_of_range(tmp_path: Path, argv: list[str]) -> None:
    assert_refused(invoke([a.format(d=tmp_path) for a in argv]), contains="--seed")
    assert files_under(tmp_path) == set()


@pytest.mark.parametrize("command", ["show", "recognize"])
@pytest.mark.parametrize("value", ["nan", "inf", "-1"])
def test_threshold_has_one_rule_in_show_and_recognize(
    tmp_path: Path, command: str, value: str
) -> None:
    rec = tmp_path / "r.npz"
    write_recording(TactileFrames(np.zeros((2, 3, 3))), rec)
    argv: list[str | Path] = [command, rec, f"--threshold={value}"]
    if command == "show":
        argv += ["--out", tmp_path / "s.png"]
    assert_refused(invoke(argv), contains="--threshold")
    assert files_under(tmp_path) == {rec}


@pytest.mark.parametrize(
    "argv",
    [
        ["simulate", "solid", "--object", "cube", "--euler-deg", "inf,0,0", "--out", "{d}/s.npz"],
        ["simulate", "solid", "--object", "cube", "--euler-deg", "1e300,0,0", "--out", "{d}/s.npz"],
        ["simulate", "press", "--shape", "circle", "--step-height-um", "1e300", "--out", "{d}/p"],
        ["simulate", "press", "--shape", "circle", "--at", "1e300,0", "--out", "{d}/p.npz"],
        ["trace", "--shape", "circle", "--diameter-mm", "1e300"],
        ["trace", "--shape", "circle", "--start-mm", "nan,0"],
    ],
)
def test_extreme_numbers_give_one_line_and_no_numpy_warning(
    tmp_path: Path, argv: list[str]
) -> None:
    result = invoke([a.format(d=tmp_path) for a in argv])
    assert_refused(result)
    assert "RuntimeWarning" not in result.err
    assert files_under(tmp_path) == set()


def test_numpy_floating_point_trouble_is_one_line(monkeypatch: pytest.MonkeyPatch) -> None:
    # A computation that overflows despite the option checks ends as one line.
    import taxelkit.cli as cli_module

    def overflow(*args: object, **kwargs: object) -> None:
        np.float64(1e300) * np.float64(1e300)

    monkeypatch.setattr(cli_module.cli, "main", overflow)
    assert_refused(invoke(["sensors"]), contains="numerical overflow")


# ----------------------------------------------------------------------------- reproduce
def test_reproduce_fig7_twice_gives_byte_identical_json(tmp_path: Path) -> None:
    for run in ("a", "b"):
        result = invoke(["reproduce", "fig7", "--seed", "3", "--out", tmp_path / run])
        assert result.code == 0, result.err
    first = (tmp_path / "a" / "fig7.json").read_bytes()
    assert first == (tmp_path / "b" / "fig7.json").read_bytes()
    assert b"seconds" not in first
    assert json.loads(first)["seed"] == 3
    timing = json.loads((tmp_path / "a" / "fig7.timing.json").read_text())
    assert timing["experiment"] == "fig7" and timing["seconds"] >= 0


# ----------------------------------------------------------------------------- Python API
def test_write_recording_refuses_a_bare_array(tmp_path: Path) -> None:
    with pytest.raises(InputError, match=r"rec must be a TactileFrames.*got ndarray"):
        write_recording(np.zeros((2, 3, 3)), tmp_path / "r.npz")  # type: ignore[arg-type]
    assert files_under(tmp_path) == set()


@pytest.mark.parametrize("shape", ["16x16", "16", 16, (16.0, 16.0), (16,), (16, 16, 1), (0, 4)])
def test_smart_sensor_refuses_what_is_not_a_shape(shape: object) -> None:
    with pytest.raises(InputError, match="shape must be"):
        SmartSensor(shape, pitch_mm=1.0)  # type: ignore[arg-type]


def test_smart_sensor_accepts_shapes_as_tuples_lists_and_arrays() -> None:
    for shape in ((4, 5), [4, 5], np.array([4, 5])):
        assert SmartSensor(shape, pitch_mm=1.0).shape == (4, 5)  # type: ignore[arg-type]


@pytest.mark.parametrize("threshold", [float("nan"), float("inf"), "0.1", True])
def test_thresholds_are_checked_in_the_api(threshold: object) -> None:
    with pytest.raises(InputError, match="threshold"):
        SmartSensor((4, 4), pitch_mm=1.0, threshold=threshold)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="threshold"):
        TactileFrames(np.zeros((1, 2, 2))).contact(threshold)  # type: ignore[arg-type]


# ----------------------------------------------------------------------------- no cap
def test_small_compressed_npz_holding_256_mib_is_refused_before_reading(tmp_path: Path) -> None:
    path = tmp_path / "bomb.npz"
    path.write_bytes(
        zip_of({"frames.npy": npy_bytes(np.zeros(BOMB_SHAPE, np.float32))}, compress=True)
    )
    assert path.stat().st_size < 300_000
    with zipfile.ZipFile(path) as zf:
        assert zf.infolist()[0].file_size > 256 * 2**20
    assert_refused(invoke(["info", path]), contains="over the read limit of 48 MiB")
    # The limit is the user's to raise: the same file reads with --max-mb 300.
    result = invoke(["--max-mb", "300", "info", path, "--json"])
    assert result.code == 0, result.err
    assert json.loads(result.out)["frames"] == BOMB_SHAPE[0]
