"""The shared reader discipline of :mod:`taxelkit.io.limits`."""

from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np
import pytest

from taxelkit.errors import (
    CorruptRecordingError,
    FileTooLargeError,
    InputError,
    RecordingError,
    UnsafeFileError,
)
from taxelkit.io.limits import (
    DEFAULT_MAX_MB,
    MAX_MB_ENV,
    ReadBudget,
    max_read_bytes,
    read_limit,
)
from taxelkit.io.limits_h5 import check_h5_dataset, h5_node
from taxelkit.io.npz_read import read_npz
from taxelkit.io.recordings import read_recording
from tests.fuzz.corpus import npy_bytes, zip_of

MIB = 2**20


def test_default_environment_and_context_limits(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.delenv(MAX_MB_ENV, raising=False)
    assert max_read_bytes() == int(DEFAULT_MAX_MB * MIB)
    monkeypatch.setenv(MAX_MB_ENV, "2.5")
    assert max_read_bytes() == int(2.5 * MIB)
    with read_limit(1):  # the context wins over the environment
        assert max_read_bytes() == MIB
    assert max_read_bytes() == int(2.5 * MIB)
    for bad in ("zero", "0", "-3", "nan", "inf"):
        monkeypatch.setenv(MAX_MB_ENV, bad)
        with pytest.raises(InputError, match=MAX_MB_ENV):
            max_read_bytes()
    with pytest.raises(InputError, match="max_mb"):
        read_limit(float("nan")).__enter__()


def test_budget_charges_declared_sizes_and_integers_as_float64() -> None:
    budget = ReadBudget(Path("x.npz"), limit=1000)
    budget.take("a", (10, 10), np.dtype(np.float32))
    assert budget.used == 400
    with pytest.raises(FileTooLargeError, match=r"x.npz: b declares shape \(100,\) of int8"):
        budget.take("b", (100,), np.dtype(np.int8))  # 800 bytes as float64
    with pytest.raises(FileTooLargeError, match="the file has"):
        ReadBudget(Path("x.npz"), limit=10).check_file_size(11)


def test_read_npz_checks_headers_before_reading(tmp_path: Path) -> None:
    path = tmp_path / "a.npz"
    members = {"a.npy": npy_bytes(np.zeros(1000)), "b.npy": npy_bytes(np.ones(2))}
    path.write_bytes(zip_of(members, compress=True))  # ~0.5 KiB on disk
    got = read_npz(path, ["b", "missing"], what="test")
    assert set(got.arrays) == {"b"} and got.names == ("a", "b")
    with read_limit(0.004):  # 4 KiB: "a" (8000 bytes) is over it, "b" alone is not
        with pytest.raises(FileTooLargeError, match=r"a declares shape \(1000,\)"):
            read_npz(path, ["a"], what="test")
        assert read_npz(path, ["b"], what="test").arrays["b"].shape == (2,)


@pytest.mark.parametrize("name", ["../frames.npy", "sub/frames.npy", "/abs/frames.npy", "c:x.npy"])
def test_archive_members_with_paths_are_unsafe(tmp_path: Path, name: str) -> None:
    path = tmp_path / "r.npz"
    path.write_bytes(zip_of({name: npy_bytes(np.zeros((1, 2, 2)))}))
    with pytest.raises(UnsafeFileError, match="has a path"):
        read_recording(path)


def test_object_arrays_are_refused_without_unpickling(tmp_path: Path) -> None:
    path = tmp_path / "r.npz"
    member = npy_bytes(np.array([object()], dtype=object), allow_pickle=True)
    path.write_bytes(zip_of({"frames.npy": member}))
    with pytest.raises(CorruptRecordingError, match="never loads"):
        read_recording(path)


def test_hdf5_links_and_external_data_are_unsafe(tmp_path: Path) -> None:
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as root:
        root.create_dataset("x", data=np.zeros(3))
    path = tmp_path / "links.h5"
    with h5py.File(path, "w") as root:
        root.create_dataset("data", data=np.zeros(3))
        root["soft"] = h5py.SoftLink("/data")
        root["ext"] = h5py.ExternalLink(str(other), "/x")
        root.create_dataset("raw", shape=(3,), dtype="f8", external=[(str(other), 0, 24)])
    with h5py.File(path, "r") as root:
        assert h5_node(path, root, "absent") is None
        assert isinstance(h5_node(path, root, "data"), h5py.Dataset)
        with pytest.raises(UnsafeFileError, match="soft link"):
            h5_node(path, root, "soft")
        with pytest.raises(UnsafeFileError, match="external link"):
            h5_node(path, root, "ext")
        with pytest.raises(UnsafeFileError, match="external file"):
            check_h5_dataset(path, "raw", root["raw"], ReadBudget(path))


def test_new_errors_belong_to_the_recording_family() -> None:
    assert issubclass(FileTooLargeError, RecordingError)
    assert issubclass(UnsafeFileError, RecordingError)


def test_max_mb_option_and_environment_raise_the_cli_limit(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    from taxelkit.cli import run
    from taxelkit.frames import TactileFrames
    from taxelkit.io.recordings import write_recording

    big = tmp_path / "r.npz"
    np.savez(big, frames=np.zeros((300, 32, 32)))  # 2.3 MiB, read a chunk at a time
    monkeypatch.setenv(MAX_MB_ENV, "1")
    assert run(["info", str(big)]) == 0
    capsys.readouterr()
    path = write_recording(TactileFrames(np.zeros((700, 32, 32), bool)), tmp_path / "r.csv")
    assert path.stat().st_size > 2**20  # CSV files are read whole, under the limit
    assert run(["info", str(path)]) == 2
    assert "over the read limit of 1 MiB" in capsys.readouterr().err
    assert run(["--max-mb", "16", "info", str(path)]) == 0  # 11 MiB of parsed table
    monkeypatch.setenv(MAX_MB_ENV, "16")
    assert run(["info", str(path)]) == 0
    capsys.readouterr()
    assert run(["--max-mb", "nan", "info", str(path)]) == 2
    assert "--max-mb" in capsys.readouterr().err
