"""The fields of a recording read from a file, checked and turned into frames.

Every reader of :mod:`taxelkit.io.recordings` and :mod:`taxelkit.io.chunked_read`
ends in :func:`build_frames`: text and number fields are taken from whatever
the format stored (``str``, ``bytes``, numbers, one-element arrays), contact
frames are checked to hold only 0 and 1, and any problem is a
:class:`~taxelkit.errors.RecordingError` that names the file.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import (
    CorruptRecordingError,
    EmptyRecordingError,
    InputError,
    InvalidRecordingError,
)
from taxelkit.frames import CONTACT_UNITS, DEFAULT_PITCH_MM, TactileFrames
from taxelkit.io._raw import RawRecording, fail

__all__ = ["DEFAULT_SENSOR", "build_frames"]

#: Default sensor name, as in :class:`~taxelkit.frames.TactileFrames`.
DEFAULT_SENSOR = "unknown"


def _show(value: object) -> str:
    if isinstance(value, np.ndarray):
        return f"an array of shape {value.shape} and dtype {value.dtype}"
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."


def _text_field(path: Path, name: str, value: object | None) -> str | None:
    """A text scalar from ``str``, ``bytes`` or a one-element string array."""
    if value is None:
        return None
    item = value
    if isinstance(item, np.ndarray) and item.size == 1 and item.dtype.kind in "US":
        item = item.reshape(()).item()
    if isinstance(item, bytes):
        try:
            item = item.decode("utf-8")
        except UnicodeDecodeError:
            raise fail(InvalidRecordingError, path, f"{name} is not UTF-8 text") from None
    if isinstance(item, str):
        return str(item)
    raise fail(InvalidRecordingError, path, f"{name} must be text, got {_show(value)}")


def _number_field(path: Path, name: str, value: object | None) -> float | None:
    """A real scalar from a number, a numeric string or a one-element array of either."""
    if value is None:
        return None
    item = value
    if isinstance(item, np.ndarray) and item.size == 1:
        item = item.reshape(()).item()
    if isinstance(item, bytes):
        item = item.decode("utf-8", "replace")
    if isinstance(item, str):
        try:
            return float(item)
        except ValueError:
            pass
    elif isinstance(item, int | float | np.integer | np.floating) and not isinstance(
        item, bool | np.bool_
    ):
        return float(item)
    raise fail(InvalidRecordingError, path, f"{name} must be a single number, got {_show(value)}")


def build_frames(
    raw: RawRecording, path: Path, pitch_override: float | None, *, owned: bool = False
) -> TactileFrames:
    """Validate raw fields into a :class:`TactileFrames`, naming the file on failure.

    Parameters
    ----------
    raw : RawRecording
        The fields as the format stored them.
    path : Path
        The file, named in every error.
    pitch_override : float or None
        Taxel pitch, mm, replacing the stored one (None: the stored one, or
        the default).
    owned : bool
        The frames and times were just read into arrays that nothing else
        holds: they are kept rather than copied (:meth:`TactileFrames.adopt`).

    Returns
    -------
    TactileFrames
    """
    if raw.frames is None:
        found = ", ".join(raw.found) if raw.found else "nothing"
        raise fail(CorruptRecordingError, path, f"no 'frames' array (the file holds: {found})")
    frames: NDArray[Any] = np.asarray(raw.frames)
    if frames.ndim == 3 and frames.shape[0] == 0:
        raise fail(EmptyRecordingError, path, f"holds zero frames (frames shape {frames.shape})")
    if frames.ndim == 3 and 0 in frames.shape[1:]:
        raise fail(
            InvalidRecordingError,
            path,
            f"frames must have at least one row and one column, got shape {frames.shape}",
        )
    if frames.dtype.byteorder not in "=|":
        frames = frames.astype(frames.dtype.newbyteorder("="))
    units = _text_field(path, "units", raw.units)
    sensor = _text_field(path, "sensor", raw.sensor)
    if (raw.contact or units == CONTACT_UNITS) and frames.dtype.kind in "iuf":
        if not np.all((frames == 0) | (frames == 1)):
            raise fail(
                InvalidRecordingError,
                path,
                f"frames must hold only 0 and 1 for units {CONTACT_UNITS!r}",
            )
        frames = frames != 0
    if pitch_override is not None:
        pitch = pitch_override
    else:
        stored = _number_field(path, "pitch_mm", raw.pitch_mm)
        pitch = DEFAULT_PITCH_MM if stored is None else stored
    t_s: NDArray[Any] | None = None
    if raw.t_s is not None:
        t_s = np.asarray(raw.t_s)
        if t_s.dtype.kind not in "iuf":
            raise fail(InvalidRecordingError, path, f"t_s must be numeric, got dtype {t_s.dtype}")
    try:
        return (TactileFrames.adopt if owned else TactileFrames)(
            frames,
            t_s,
            pitch_mm=pitch,
            units=units,
            sensor=DEFAULT_SENSOR if sensor is None else sensor,
        )
    except InputError as exc:
        raise fail(InvalidRecordingError, path, str(exc)) from exc
