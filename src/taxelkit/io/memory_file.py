"""Read an associative memory saved by ``taxelkit memorise`` (an ``.npz`` file).

The arrays are those of :meth:`~taxelkit.memory.associatron.AssociativeMemory.to_arrays`.
Reading follows :mod:`taxelkit.io.limits`: the declared array sizes, and the
size of the recall operator the memory implies (an ``N x N`` float64 matrix for
codes of ``N = m * l`` elements), are checked against the read limit before
anything is allocated.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from taxelkit.errors import CorruptRecordingError, InputError
from taxelkit.io.limits import ReadBudget
from taxelkit.io.npz_read import read_npz
from taxelkit.memory.associatron import AssociativeMemory

__all__ = ["MEMORY_ARRAYS", "read_memory"]

#: Arrays a memory file holds.
MEMORY_ARRAYS = ("format_version", "names", "patterns", "m", "l", "thresholds", "rule")


def _count(arrays: dict[str, np.ndarray], key: str) -> int | None:
    value = arrays.get(key)
    if value is None or value.shape != () or value.dtype.kind not in "iu":
        return None  # left to AssociativeMemory.from_arrays to describe
    return int(value)


def read_memory(path: str | os.PathLike[str]) -> AssociativeMemory:
    """Read a memory file written by ``taxelkit memorise``.

    Parameters
    ----------
    path : str or os.PathLike
        An ``.npz`` file holding :data:`MEMORY_ARRAYS`.

    Returns
    -------
    AssociativeMemory

    Raises
    ------
    RecordingNotFoundError, RecordingAccessError
        If the path is missing or not a regular file.
    FileTooLargeError
        If the file, its arrays or the recall operator its code length
        implies exceed the read limit (checked before allocating).
    UnsafeFileError
        If an archive member name carries a path.
    CorruptRecordingError
        If the file is not a readable ``.npz`` archive or lacks an array.
    InputError
        If an array has the wrong type, shape or content.
    """
    p = Path(path)
    contents = read_npz(p, MEMORY_ARRAYS, what="memory")
    arrays = dict(contents.arrays)
    missing = [key for key in MEMORY_ARRAYS if key not in arrays]
    if missing:
        raise CorruptRecordingError(
            f"{p}: not a taxelkit memory file: missing array(s) {', '.join(missing)}"
        )
    m, l_ = _count(arrays, "m"), _count(arrays, "l")
    if m is not None and l_ is not None and m > 0 and l_ > 0:
        n = m * l_
        ReadBudget(p).take(
            f"the recall operator of its m*l = {n}-element codes", (n, n), np.dtype(np.float64)
        )
    try:
        return AssociativeMemory.from_arrays(arrays)
    except InputError as exc:
        raise InputError(f"{p}: {exc}") from None
