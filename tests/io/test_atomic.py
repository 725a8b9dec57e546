"""Tests of taxelkit.io.atomic: temporary file, rename, never clobber without force."""

from __future__ import annotations

import os
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from taxelkit.errors import OutputExistsError, OutputWriteError, TaxelkitError
from taxelkit.io.atomic import atomic_write


def _write_text(text: str) -> Callable[[Path], None]:
    def writer(tmp: Path) -> None:
        tmp.write_text(text)

    return writer


class _Boom(RuntimeError):
    pass


def _failing_writer(tmp: Path) -> None:
    tmp.write_text("half")
    raise _Boom("writer failed")


def test_writes_new_file_and_returns_its_path(tmp_path: Path) -> None:
    out = atomic_write(tmp_path / "a.json", _write_text("{}"))
    assert out == tmp_path / "a.json"
    assert out.read_text() == "{}"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.json"]


def test_accepts_str_path(tmp_path: Path) -> None:
    out = atomic_write(str(tmp_path / "a.txt"), _write_text("x"))
    assert isinstance(out, Path)
    assert out.read_text() == "x"


def test_temp_file_is_beside_target_and_keeps_suffix(tmp_path: Path) -> None:
    seen: list[Path] = []

    def writer(tmp: Path) -> None:
        seen.append(tmp)
        assert tmp.exists() and tmp.stat().st_size == 0
        tmp.write_bytes(b"data")

    atomic_write(tmp_path / "fig.png", writer)
    (tmp,) = seen
    assert tmp.parent == tmp_path
    assert tmp.name.startswith(".fig.png.tmp-")
    assert tmp.suffix == ".png"
    assert not tmp.exists()


def test_existing_file_is_not_overwritten_without_force(tmp_path: Path) -> None:
    target = tmp_path / "out.npz"
    target.write_text("old")
    with pytest.raises(OutputExistsError) as info:
        atomic_write(target, _write_text("new"))
    message = str(info.value)
    assert "out.npz" in message and "--force" in message and "\n" not in message
    assert isinstance(info.value, TaxelkitError)
    assert isinstance(info.value, FileExistsError)
    assert target.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.npz"]


def test_force_overwrites(tmp_path: Path) -> None:
    target = tmp_path / "out.csv"
    target.write_text("old")
    atomic_write(target, _write_text("new"), force=True)
    assert target.read_text() == "new"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"]


@pytest.mark.parametrize("force", [False, True])
def test_failing_writer_leaves_old_file_and_no_temp(tmp_path: Path, force: bool) -> None:
    target = tmp_path / "out.h5"
    if force:
        target.write_text("old")
    with pytest.raises(_Boom):
        atomic_write(target, _failing_writer, force=force)
    if force:
        assert target.read_text() == "old"
        assert sorted(p.name for p in tmp_path.iterdir()) == ["out.h5"]
    else:
        assert list(tmp_path.iterdir()) == []


def test_interrupt_in_writer_cleans_up(tmp_path: Path) -> None:
    def writer(tmp: Path) -> None:
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        atomic_write(tmp_path / "x.txt", writer)
    assert list(tmp_path.iterdir()) == []


def test_oserror_in_writer_becomes_output_write_error(tmp_path: Path) -> None:
    def writer(tmp: Path) -> None:
        raise OSError(28, "No space left on device")

    with pytest.raises(OutputWriteError, match=r"x\.txt.*No space left"):
        atomic_write(tmp_path / "x.txt", writer)
    assert list(tmp_path.iterdir()) == []


def test_taxelkit_error_from_writer_passes_unchanged(tmp_path: Path) -> None:
    error = OutputExistsError("inner")

    def writer(tmp: Path) -> None:
        raise error

    with pytest.raises(OutputExistsError) as info:
        atomic_write(tmp_path / "x.txt", writer)
    assert info.value is error
    assert list(tmp_path.iterdir()) == []


def test_target_created_while_writing_is_not_clobbered(tmp_path: Path) -> None:
    target = tmp_path / "race.txt"

    def writer(tmp: Path) -> None:
        tmp.write_text("mine")
        target.write_text("theirs")

    with pytest.raises(OutputExistsError):
        atomic_write(target, writer)
    assert target.read_text() == "theirs"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["race.txt"]


def test_missing_folder(tmp_path: Path) -> None:
    with pytest.raises(OutputWriteError, match="does not exist") as info:
        atomic_write(tmp_path / "no" / "x.txt", _write_text("x"))
    assert "x.txt" in str(info.value)
    assert isinstance(info.value, OSError) and isinstance(info.value, TaxelkitError)


@pytest.mark.parametrize("force", [False, True])
def test_target_is_a_folder(tmp_path: Path, force: bool) -> None:
    folder = tmp_path / "out.png"
    folder.mkdir()
    with pytest.raises(OutputWriteError, match="folder"):
        atomic_write(folder, _write_text("x"), force=force)
    assert folder.is_dir()
    assert list(folder.iterdir()) == []


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX permission bits")
def test_new_file_gets_umask_permissions(tmp_path: Path) -> None:
    mask = os.umask(0o022)
    try:
        out = atomic_write(tmp_path / "x.txt", _write_text("x"))
    finally:
        os.umask(mask)
    assert out.stat().st_mode & 0o777 == 0o644
