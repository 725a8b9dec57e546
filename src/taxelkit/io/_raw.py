"""What a format reader found in a file, before it is validated as a recording."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import TypeVar

from taxelkit.errors import TaxelkitError

_E = TypeVar("_E", bound=TaxelkitError)

__all__ = ["RECORDING_FIELDS", "RawRecording", "describe_exception", "fail", "one_line"]

#: Names of the arrays and scalars a recording file may hold, in documented order.
RECORDING_FIELDS = ("frames", "t_s", "pitch_mm", "units", "sensor")


@dataclass(frozen=True)
class RawRecording:
    """Fields read from a file, unchecked; ``None`` where a field is absent.

    Parameters
    ----------
    frames, t_s, pitch_mm, units, sensor : object or None
        The values as the file format returned them (arrays, NumPy scalars,
        ``str`` or ``bytes``).
    found : tuple of str
        Names of everything the file holds, for error messages.
    contact : bool
        True if the format itself marks the frames as 0/1 contact values that
        must become bool (the CSV ``# dtype: bool`` comment).
    """

    frames: object | None
    t_s: object | None = None
    pitch_mm: object | None = None
    units: object | None = None
    sensor: object | None = None
    found: tuple[str, ...] = ()
    contact: bool = False


def one_line(text: str) -> str:
    """Collapse all whitespace runs, line breaks included, to single spaces."""
    return " ".join(text.split())


def describe_exception(exc: BaseException) -> str:
    """``"TypeName: message"`` on one line, for wrapping a third-party failure."""
    message = one_line(str(exc))
    return f"{type(exc).__name__}: {message}" if message else type(exc).__name__


def fail(cls: type[_E], path: Path, problem: str) -> _E:
    """Build ``cls("<path>: <problem>")`` with the message forced onto one line."""
    return cls(one_line(f"{path}: {problem}"))
