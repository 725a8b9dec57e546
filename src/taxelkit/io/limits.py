"""One reader discipline for every file taxelkit opens: limits, then allocation.

Recordings, heightmaps, memories, meshes (and any future format) come from
other people and programs. Every reader goes through the same steps, which
this module provides (and :mod:`taxelkit.io.npz_read` for ``.npz`` archives)
so that new readers can call them too:

1. **Look before allocating.** A :class:`ReadBudget` is charged with the size
   of the file on disk and with the size every array *declares* (the ``.npy``
   header of an ``.npz`` member, the shape and dtype of an HDF5 dataset or
   attribute) before the array is read. Going over the limit raises
   :class:`~taxelkit.errors.FileTooLargeError`.
2. **Stay inside the file.** Archive members whose names carry a folder path,
   HDF5 external raw storage, virtual datasets, external and soft links are
   refused with :class:`~taxelkit.errors.UnsafeFileError`; nothing they name
   is opened.
3. **One typed error, one line.** Every library exception (``BadZipFile``,
   ``zlib.error``, ``EOFError``, ``OSError``, ``ValueError``, h5py errors,
   ``MemoryError``, ...) becomes a :class:`~taxelkit.errors.RecordingError`
   whose message starts with the file's path (:func:`~taxelkit.io._raw.fail`).
   Object arrays are refused, never unpickled.

The limit
---------
:data:`DEFAULT_MAX_MB` MiB of data per file (on disk, and declared arrays in
memory). Raise it for one command with ``taxelkit --max-mb N ...``, for a
shell with the environment variable :data:`MAX_MB_ENV` (``TAXELKIT_MAX_MB``),
or in Python with ``with read_limit(N): ...``. See ``docs/security.md``.
"""

from __future__ import annotations

import contextlib
import math
import os
from collections.abc import Iterator
from contextvars import ContextVar
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from taxelkit.errors import (
    CorruptRecordingError,
    FileTooLargeError,
    InputError,
    RecordingAccessError,
    RecordingNotFoundError,
)
from taxelkit.io._raw import describe_exception, fail

__all__ = [
    "DEFAULT_MAX_MB",
    "MAX_MB_ENV",
    "MAX_NPZ_MEMBERS",
    "ReadBudget",
    "max_read_bytes",
    "open_budget",
    "read_limit",
]

#: Default read limit, MiB per file: the file on disk, and the arrays it
#: declares together. 48 MiB holds about 49,000 frames of a 16 x 16 float32
#: array (3.4 minutes at 240 Hz); reading a file at the limit (the array, the
#: validated copy, the interpreter) peaks under 200 MB.
DEFAULT_MAX_MB = 48.0
#: Bytes charged per element of an integer array: readers turn integer frames
#: into float64.
_INTEGER_CHARGE_BYTES = 8
#: Environment variable that replaces :data:`DEFAULT_MAX_MB` (a number of MiB).
MAX_MB_ENV = "TAXELKIT_MAX_MB"
#: Most members an ``.npz`` archive may hold (a recording holds 5).
MAX_NPZ_MEMBERS = 64
#: Largest ``.npy`` header read from an archive member, bytes (NumPy's own default).
MAX_NPY_HEADER_BYTES = 10_000
#: Bytes in a MiB.
_MIB = 1 << 20
#: The read limit set by :func:`read_limit`, if any (it wins over the environment).
_LIMIT_MB: ContextVar[float | None] = ContextVar("taxelkit_read_limit_mb", default=None)
#: How to raise the limit, for messages.
_HOW_TO_RAISE = f"raise the limit with --max-mb or {MAX_MB_ENV}"


def _check_mb(value: object, where: str) -> float:
    try:
        mb = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise InputError(f"{where} must be a number of MiB > 0, got {value!r}") from None
    if not (math.isfinite(mb) and mb > 0):
        raise InputError(f"{where} must be a finite number of MiB > 0, got {value!r}")
    return mb


def max_read_bytes() -> int:
    """The read limit in force, bytes.

    Returns
    -------
    int
        From :func:`read_limit` if one is active, else from the environment
        variable :data:`MAX_MB_ENV`, else :data:`DEFAULT_MAX_MB` MiB.

    Raises
    ------
    InputError
        If :data:`MAX_MB_ENV` is set to something other than a number > 0.
    """
    mb = _LIMIT_MB.get()
    if mb is None:
        env = os.environ.get(MAX_MB_ENV)
        mb = DEFAULT_MAX_MB if env is None or not env.strip() else _check_mb(env, MAX_MB_ENV)
    return int(mb * _MIB)


@contextlib.contextmanager
def read_limit(max_mb: float) -> Iterator[None]:
    """Set the read limit for the readers called inside the ``with`` block.

    Parameters
    ----------
    max_mb : float
        MiB per file, > 0.

    Raises
    ------
    InputError
        If ``max_mb`` is not a finite number > 0.

    Examples
    --------
    >>> with read_limit(1024):
    ...     max_read_bytes() == 1024 * 2**20
    True
    """
    token = _LIMIT_MB.set(_check_mb(max_mb, "max_mb"))
    try:
        yield
    finally:
        _LIMIT_MB.reset(token)


def _mb(nbytes: int) -> str:
    return f"{nbytes / _MIB:.4g} MiB"


@dataclass
class ReadBudget:
    """Bytes a reader may still take from one file.

    Parameters
    ----------
    path : pathlib.Path
        The file, named in every message.
    limit : int, optional
        Bytes; default :func:`max_read_bytes`.

    Examples
    --------
    >>> budget = ReadBudget(Path("run.npz"), limit=1000)
    >>> budget.take("frames", (10, 10), np.dtype(np.float64))
    >>> budget.used
    800
    """

    path: Path
    limit: int = field(default_factory=max_read_bytes)
    used: int = 0

    def check_file_size(self, size: int) -> None:
        """Refuse a file larger on disk than the limit."""
        if size > self.limit:
            raise fail(
                FileTooLargeError,
                self.path,
                f"the file has {_mb(size)}, over the read limit of {_mb(self.limit)}; "
                f"{_HOW_TO_RAISE}",
            )

    def check_block(self, what: str, nbytes: int) -> None:
        """Refuse one block (a compressed chunk, a buffer) that alone exceeds the limit.

        Unlike :meth:`take`, nothing is charged: the block is freed once decoded.

        Raises
        ------
        FileTooLargeError
            If ``nbytes`` exceeds the limit.
        """
        if nbytes > self.limit:
            raise fail(
                FileTooLargeError,
                self.path,
                f"{what} declares {_mb(nbytes)}, over the read limit of {_mb(self.limit)}; "
                f"{_HOW_TO_RAISE}",
            )

    def take(self, what: str, shape: tuple[int, ...], dtype: np.dtype[Any]) -> None:
        """Charge an array's declared size before it is read.

        Parameters
        ----------
        what : str
            The array's name, for the message.
        shape : tuple of int
            Declared shape.
        dtype : numpy.dtype
            Declared dtype. Integer elements count as 8 bytes, the float64
            they become.

        Raises
        ------
        FileTooLargeError
            If the arrays charged so far exceed the limit.
        """
        itemsize = _INTEGER_CHARGE_BYTES if dtype.kind in "iu" else int(dtype.itemsize)
        nbytes = math.prod(int(n) for n in shape) * max(itemsize, 1)
        self.used += nbytes
        if self.used > self.limit:
            total = "" if nbytes == self.used else f" ({_mb(self.used)} with the arrays before)"
            raise fail(
                FileTooLargeError,
                self.path,
                f"{what} declares shape {tuple(shape)} of {dtype} ({_mb(nbytes)}){total}, "
                f"over the read limit of {_mb(self.limit)}; {_HOW_TO_RAISE}",
            )


def open_budget(path: Path, *, what: str) -> ReadBudget:
    """Check that ``path`` is a non-empty regular file within the limit; its budget.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    what : str
        What the file should be (``"heightmap"``, ``"memory"``), for messages.

    Raises
    ------
    RecordingNotFoundError, RecordingAccessError, FileTooLargeError
    CorruptRecordingError
        If the file has 0 bytes.
    """
    try:
        info = path.stat()
    except FileNotFoundError:
        raise fail(RecordingNotFoundError, path, f"no such {what} file") from None
    except (OSError, ValueError) as exc:
        raise fail(
            RecordingAccessError, path, f"cannot access ({describe_exception(exc)})"
        ) from None
    if not path.is_file():
        raise fail(RecordingAccessError, path, f"is not a regular file; expected a {what} file")
    if info.st_size == 0:
        raise fail(CorruptRecordingError, path, f"is empty (0 bytes); expected a {what} file")
    budget = ReadBudget(path)
    budget.check_file_size(info.st_size)
    return budget
