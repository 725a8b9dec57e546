"""Typed exceptions and boundary validators.

Every error a user can cause is a :class:`TaxelkitError`. The CLI turns these
into one line on stderr and exit code 2; anything else is a bug.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "CorruptRecordingError",
    "EmptyRecordingError",
    "FileTooLargeError",
    "InputError",
    "InvalidRecordingError",
    "OutputExistsError",
    "OutputWriteError",
    "RecordingAccessError",
    "RecordingError",
    "RecordingNotFoundError",
    "TaxelkitError",
    "UnsafeFileError",
    "UnsupportedFormatError",
    "check_finite_array",
    "check_in_range",
    "check_ndim",
    "check_positive",
    "check_shape",
    "check_threshold",
    "check_type",
]


class TaxelkitError(Exception):
    """Base class of every error taxelkit raises on purpose."""


class InputError(TaxelkitError, ValueError):
    """A parameter or array has the wrong shape, type, range or value."""


class RecordingError(TaxelkitError):
    """A recording cannot be read or written."""


class UnsupportedFormatError(RecordingError):
    """The file extension names no recording format taxelkit knows."""


class CorruptRecordingError(RecordingError):
    """The file is truncated, damaged, or does not hold the documented arrays."""


class EmptyRecordingError(RecordingError):
    """The file holds no frames."""


class InvalidRecordingError(RecordingError, InputError):
    """The file is readable but a field breaks the rules of :class:`~taxelkit.frames.TactileFrames`.

    Wrong number of dimensions, NaN or Inf, non-increasing or mismatched
    timestamps, a pitch that is not a positive number, text fields that are not
    text. Both a :class:`RecordingError` and an :class:`InputError`.
    """


class FileTooLargeError(RecordingError):
    """The file, or the arrays it declares, exceed the read limit.

    The limit is checked against the sizes a file declares (array headers, HDF5
    dataset shapes) before anything is allocated; see :mod:`taxelkit.io.limits`
    for its default and how to raise it.
    """


class UnsafeFileError(RecordingError):
    """The file points outside itself, which taxelkit never follows.

    HDF5 external raw storage, virtual datasets, external and soft links, and
    archive members whose names carry a folder path.
    """


class RecordingAccessError(RecordingError, OSError):
    """The path cannot be read as a file: a folder, no permission, not a regular file."""


class RecordingNotFoundError(RecordingAccessError, FileNotFoundError):
    """No file exists at the path."""


class OutputExistsError(TaxelkitError, FileExistsError):
    """An output file exists and overwriting it was not asked for."""


class OutputWriteError(TaxelkitError, OSError):
    """An output file cannot be written: missing folder, no permission, disk full, ..."""


def check_positive(name: str, value: float, *, allow_zero: bool = False) -> float:
    """Return ``value`` as float if it is finite and > 0 (or >= 0).

    Raises
    ------
    InputError
        Naming ``name``, the expectation and the value received.
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    ok = v >= 0 if allow_zero else v > 0
    if not math.isfinite(v) or not ok:
        bound = ">= 0" if allow_zero else "> 0"
        raise InputError(f"{name} must be finite and {bound}, got {value!r}")
    return v


def check_in_range(name: str, value: float, low: float, high: float) -> float:
    """Return ``value`` as float if ``low <= value <= high``.

    Raises
    ------
    InputError
        If the value is not a finite number inside the closed interval.
    """
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    if not (math.isfinite(v) and low <= v <= high):
        raise InputError(f"{name} must be in [{low}, {high}], got {value!r}")
    return v


def check_shape(name: str, value: object, ndim: int = 2) -> tuple[int, ...]:
    """Return ``value`` as a tuple of ``ndim`` positive ints, else raise.

    A string, a float, a bool or anything but a tuple, list or 1-D integer
    array is refused, never reinterpreted (``"16x16"`` is not a shape).

    Raises
    ------
    InputError
        Naming ``name``, the expectation and the value received.

    Examples
    --------
    >>> check_shape("shape", (16, 16))
    (16, 16)
    """
    expected = f"{ndim} positive integers"
    if isinstance(value, np.ndarray):
        if value.ndim != 1 or value.dtype.kind not in "iu":
            raise InputError(f"{name} must be {expected}, got {value!r}")
        items: list[object] = list(value.tolist())
    elif isinstance(value, tuple | list):
        items = list(value)
    else:
        raise InputError(f"{name} must be a tuple of {expected}, got {value!r}")
    ok = all(isinstance(v, int | np.integer) and not isinstance(v, bool) for v in items)
    if len(items) != ndim or not ok or any(int(v) < 1 for v in items):  # type: ignore[call-overload]
        raise InputError(f"{name} must be {expected}, got {value!r}")
    return tuple(int(v) for v in items)  # type: ignore[call-overload]


def check_threshold(name: str, value: object) -> float:
    """Return a contact threshold as float if it is a finite real number, else raise.

    Raises
    ------
    InputError
        If ``value`` is not a real number (a string, a bool) or is NaN/Inf.
    """
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise InputError(f"{name} must be a finite number, got {value!r}")
    v = float(value)
    if not math.isfinite(v):
        raise InputError(f"{name} must be a finite number, got {value!r}")
    return v


def check_type(name: str, value: object, cls: type, expected: str) -> None:
    """Raise :class:`InputError` unless ``value`` is an instance of ``cls``.

    Parameters
    ----------
    name : str
        Parameter name used in the message.
    value : object
        Value to check.
    cls : type
        Required type.
    expected : str
        The type in words, e.g. ``"a TactileFrames"``.
    """
    if not isinstance(value, cls):
        raise InputError(f"{name} must be {expected}, got {type(value).__name__}")


def check_ndim(name: str, array: ArrayLike, ndim: int, shape_doc: str) -> NDArray[Any]:
    """Return ``np.asarray(array)`` if it has ``ndim`` dimensions.

    Parameters
    ----------
    name : str
        Parameter name used in the message.
    array : array_like
        Value to check.
    ndim : int
        Required number of dimensions.
    shape_doc : str
        Expected shape in words, e.g. ``"(T, rows, cols)"``.

    Raises
    ------
    InputError
        If the number of dimensions differs.
    """
    arr = np.asarray(array)
    if arr.ndim != ndim:
        raise InputError(
            f"{name} must have shape {shape_doc} ({ndim} dimensions), got shape {arr.shape}"
        )
    return arr


def check_finite_array(name: str, array: NDArray[Any]) -> None:
    """Raise :class:`InputError` if a numeric array holds NaN or Inf.

    Boolean and integer arrays are always finite and pass.
    """
    if array.dtype.kind in "fc" and not np.all(np.isfinite(array)):
        n_bad = int(np.count_nonzero(~np.isfinite(array)))
        raise InputError(f"{name} must be finite, got {n_bad} NaN/Inf value(s)")
