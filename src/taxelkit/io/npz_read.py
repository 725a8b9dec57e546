"""Reading ``.npz`` archives under the read limits: headers checked before any array.

The ``.npz`` half of :mod:`taxelkit.io.limits`: :func:`read_npz` opens an
archive, refuses members with folder paths and too many members, reads each
wanted member's ``.npy`` header (:func:`npy_header`: shape and dtype, object
arrays refused) and charges the :class:`~taxelkit.io.limits.ReadBudget` with
the declared size before it reads the array.
"""

from __future__ import annotations

import math
import zipfile
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import (
    CorruptRecordingError,
    FileTooLargeError,
    RecordingAccessError,
    TaxelkitError,
    UnsafeFileError,
)
from taxelkit.io._raw import describe_exception, fail
from taxelkit.io.limits import (
    _HOW_TO_RAISE,
    MAX_NPY_HEADER_BYTES,
    MAX_NPZ_MEMBERS,
    open_budget,
)

__all__ = ["NpzContents", "npy_header", "npz_members", "read_npz"]


@dataclass(frozen=True)
class _Member:
    info: zipfile.ZipInfo
    shape: tuple[int, ...]
    dtype: np.dtype[Any]


def npy_header(path: Path, name: str, fh: IO[bytes]) -> tuple[tuple[int, ...], np.dtype[Any]]:
    """Shape and dtype from the ``.npy`` header at ``fh``; the array itself is not read.

    Parameters
    ----------
    path : Path
        The archive, for the error messages.
    name : str
        The member's name.
    fh : binary file
        Positioned at the member's start; left after its header.

    Raises
    ------
    CorruptRecordingError
        Another format version, an object (pickled) array, a structured or
        unsupported dtype.
    """
    version = np.lib.format.read_magic(fh)
    if version == (1, 0):
        shape, _, dtype = np.lib.format.read_array_header_1_0(fh, MAX_NPY_HEADER_BYTES)
    elif version == (2, 0):
        shape, _, dtype = np.lib.format.read_array_header_2_0(fh, MAX_NPY_HEADER_BYTES)
    else:
        raise fail(
            CorruptRecordingError,
            path,
            f"array {name!r} uses .npy format version {version}; expected 1.0 or 2.0",
        )
    if dtype.hasobject:
        raise fail(
            CorruptRecordingError,
            path,
            f"array {name!r} holds Python objects (a pickle), which taxelkit never loads",
        )
    if dtype.fields is not None or dtype.kind not in "biufcUS":
        raise fail(CorruptRecordingError, path, f"array {name!r} has unsupported dtype {dtype}")
    return tuple(int(n) for n in shape), dtype


def npz_members(path: Path, archive: zipfile.ZipFile) -> dict[str, zipfile.ZipInfo]:
    """The archive's members by array name (``NAME.npy`` -> ``NAME``).

    Raises
    ------
    CorruptRecordingError
        More than :data:`~taxelkit.io.limits.MAX_NPZ_MEMBERS` members, or one name twice.
    UnsafeFileError
        A member whose name carries a folder path, a drive or a leading dot.
    """
    infos = archive.infolist()
    if len(infos) > MAX_NPZ_MEMBERS:
        raise fail(
            CorruptRecordingError,
            path,
            f"the archive holds {len(infos)} members; an .npz file taxelkit reads holds at "
            f"most {MAX_NPZ_MEMBERS}",
        )
    out: dict[str, zipfile.ZipInfo] = {}
    for info in infos:
        name = info.filename
        if "/" in name or "\\" in name or name.startswith(".") or ":" in name:
            raise fail(
                UnsafeFileError,
                path,
                f"archive member {name[:60]!r} has a path; an .npz holds only top-level "
                f"NAME.npy arrays",
            )
        key = name.removesuffix(".npy")
        if key in out:
            raise fail(CorruptRecordingError, path, f"archive holds {key!r} twice")
        out[key] = info
    return out


@dataclass(frozen=True)
class NpzContents:
    """What :func:`read_npz` read.

    Parameters
    ----------
    arrays : mapping of str to ndarray
        The requested arrays the file holds.
    names : tuple of str
        Names of every array in the archive, in stored order.
    """

    arrays: Mapping[str, NDArray[Any]]
    names: tuple[str, ...]


def read_npz(path: Path, names: Iterable[str], *, what: str) -> NpzContents:
    """Read named arrays from an ``.npz`` file under the read limit.

    The sizes that the ``.npy`` headers of the requested members declare are
    checked (against the member's stored size and the read limit) before any
    array is allocated; object arrays are refused without unpickling.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    names : iterable of str
        Arrays to read; absent ones are left out of the result.
    what : str
        What the file should be (``"recording"``, ``"heightmap"``,
        ``"memory"``), for messages.

    Returns
    -------
    NpzContents

    Raises
    ------
    RecordingNotFoundError, RecordingAccessError
        If the path is missing or not a regular file.
    FileTooLargeError
        If the file or its requested arrays exceed :func:`max_read_bytes`.
    UnsafeFileError
        If an archive member name carries a path.
    CorruptRecordingError
        If the file is empty, not a zip archive (a bare ``.npy`` included), is
        truncated or damaged, or an array is an object array, of an
        unsupported dtype, or larger than its stored bytes.
    """
    budget = open_budget(path, what=what)
    try:
        with path.open("rb") as fh:
            magic = fh.read(6)
    except OSError as exc:
        raise fail(RecordingAccessError, path, f"cannot open ({describe_exception(exc)})") from None
    if magic.startswith(b"\x93NUMPY"):
        raise fail(
            CorruptRecordingError,
            path,
            f"holds a single .npy array, not an .npz archive of named arrays as a {what} "
            f"file must; save it with numpy.savez(path, name=array, ...)",
        )
    if not magic.startswith(b"PK"):
        raise fail(CorruptRecordingError, path, f"not an .npz {what} file (no zip signature)")
    try:
        with zipfile.ZipFile(path) as archive:
            members = npz_members(path, archive)
            wanted = [n for n in dict.fromkeys(names) if n in members]
            headers: dict[str, _Member] = {}
            for name in wanted:
                info = members[name]
                with archive.open(info) as fh:
                    shape, dtype = npy_header(path, name, fh)
                    stored = info.file_size - fh.tell()
                declared = math.prod(shape) * dtype.itemsize
                if declared > stored:
                    raise fail(
                        CorruptRecordingError,
                        path,
                        f"array {name!r} declares shape {shape} of {dtype} "
                        f"({declared} bytes) but stores {max(stored, 0)} bytes",
                    )
                budget.take(name, shape, dtype)
                headers[name] = _Member(info, shape, dtype)
            arrays: dict[str, NDArray[Any]] = {}
            for name, member in headers.items():
                with archive.open(member.info) as fh:
                    arrays[name] = np.lib.format.read_array(
                        fh, allow_pickle=False, max_header_size=MAX_NPY_HEADER_BYTES
                    )
    except TaxelkitError:
        raise
    except MemoryError:
        raise fail(
            FileTooLargeError, path, f"not enough memory to read the file; {_HOW_TO_RAISE}"
        ) from None
    except Exception as exc:  # zipfile, zlib and numpy report damage in many ways
        raise fail(
            CorruptRecordingError,
            path,
            f"unreadable .npz {what} file ({describe_exception(exc)})",
        ) from None
    return NpzContents(arrays, tuple(members))
