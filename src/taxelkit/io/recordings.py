"""Read and write tactile recordings as ``.npz``, ``.h5``/``.hdf5``, ``.csv`` or ROS 2 bags.

ROS 2 bags (rosbag2 folders and ``.mcap`` files) need the optional ``ros``
extra and are handled by :mod:`taxelkit.io.bags`.

The formats are specified in ``docs/recording-format.md``. Every reader returns
a validated :class:`~taxelkit.frames.TactileFrames`; every problem with a file
is a :class:`~taxelkit.errors.RecordingError` whose one-line message starts with
the file's path.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

import numpy as np

from taxelkit.errors import (
    CorruptRecordingError,
    EmptyRecordingError,
    InputError,
    InvalidRecordingError,
    RecordingAccessError,
    RecordingNotFoundError,
    UnsupportedFormatError,
    check_positive,
    check_type,
)
from taxelkit.frames import TactileFrames
from taxelkit.io._raw import describe_exception, fail
from taxelkit.io.atomic import atomic_write
from taxelkit.io.limits import ReadBudget
from taxelkit.io.recording_codecs import (
    FORMATS,
    MAGIC_LENGTH,
    MCAP,
    Format,
    read_mcap,
    sniff,
    write_mcap,
)
from taxelkit.io.recording_fields import build_frames

__all__ = [
    "BAG_SUFFIXES",
    "RECORDING_SUFFIXES",
    "WRITABLE_FRAME_DTYPES",
    "InvalidRecordingError",
    "RecordingAccessError",
    "RecordingNotFoundError",
    "read_recording",
    "recording_format",
    "write_recording",
]

#: File extensions of the recording formats (matched case-insensitively).
RECORDING_SUFFIXES = (".npz", ".h5", ".hdf5", ".csv")
#: Extensions of the ROS 2 formats (``pip install "taxelkit[ros]"``); a rosbag2
#: bag is a folder and is recognised by its ``metadata.yaml`` instead.
BAG_SUFFIXES = (".mcap",)
#: Frame dtypes every format stores exactly.
WRITABLE_FRAME_DTYPES = (
    np.dtype(np.bool_),
    np.dtype(np.float16),
    np.dtype(np.float32),
    np.dtype(np.float64),
)
_CANONICAL_SUFFIX = {"npz": ".npz", "hdf5": ".h5", "csv": ".csv", "mcap": ".mcap"}
_CONTENT_LABEL = {
    "npz": "an .npz archive",
    "hdf5": "HDF5 data",
    "csv": "CSV text",
    "npy": "a single .npy array",
    "mcap": "an MCAP file",
}


# ----------------------------------------------------------------------------- checks
def recording_format(path: str | os.PathLike[str]) -> str:
    """Name of the recording format selected by the path's extension.

    Parameters
    ----------
    path : str or os.PathLike
        A file name; only its suffix is looked at (case-insensitive).

    Returns
    -------
    str
        ``"npz"``, ``"hdf5"``, ``"csv"`` or ``"mcap"``.

    Raises
    ------
    UnsupportedFormatError
        If the suffix is not one of :data:`RECORDING_SUFFIXES` or :data:`BAG_SUFFIXES`.

    Examples
    --------
    >>> recording_format("run.H5")
    'hdf5'
    """
    return _format_for(Path(path)).name


def _format_for(path: Path) -> Format:
    fmt = FORMATS.get(path.suffix.lower())
    if fmt is None:
        got = f"extension {path.suffix!r}" if path.suffix else "no extension"
        raise fail(
            UnsupportedFormatError,
            path,
            f"unsupported recording format ({got}); expected one of "
            f"{', '.join(RECORDING_SUFFIXES + BAG_SUFFIXES)} or a rosbag2 folder",
        )
    return fmt


def _check_signature(path: Path, head: bytes, fmt: Format) -> None:
    """Refuse a file whose signature names another format than its extension."""
    found = sniff(head)
    if found is None or found == fmt.name:
        return
    if found == "npy":
        hint = "save named arrays with numpy.savez(path, frames=...)"
    else:
        hint = f"rename it to end in {_CANONICAL_SUFFIX[found]}"
    raise fail(
        CorruptRecordingError,
        path,
        f"holds {_CONTENT_LABEL[found]}, not {_CONTENT_LABEL[fmt.name]} as its extension says; "
        f"{hint}",
    )


def _reason(exc: OSError) -> str:
    return exc.strerror or describe_exception(exc)


def _probe_input(path: Path) -> tuple[int, bytes]:
    """Size and first bytes of a readable regular file, or a RecordingAccessError."""
    try:
        info = path.stat()
    except FileNotFoundError:
        raise fail(RecordingNotFoundError, path, "no such file") from None
    except (OSError, ValueError) as exc:
        reason = _reason(exc) if isinstance(exc, OSError) else describe_exception(exc)
        raise fail(RecordingAccessError, path, f"cannot access ({reason})") from None
    if stat.S_ISDIR(info.st_mode):
        raise fail(RecordingAccessError, path, "is a folder, not a recording file")
    if not stat.S_ISREG(info.st_mode):
        raise fail(RecordingAccessError, path, "is not a regular file")
    try:
        with path.open("rb") as fh:
            head = fh.read(MAGIC_LENGTH)
    except OSError as exc:
        raise fail(RecordingAccessError, path, f"cannot open ({_reason(exc)})") from None
    return info.st_size, head


def _check_text_for_file(name: str, value: str) -> None:
    """Text fields must survive every format: one line, no NUL, no outer spaces, UTF-8."""
    try:
        value.encode("utf-8")
    except UnicodeEncodeError:
        raise InputError(f"{name} must be encodable as UTF-8, got {value!r}") from None
    if "\x00" in value or len(value.splitlines()) > 1 or value != value.strip():
        raise InputError(
            f"{name} must be one line of text without NUL characters or leading/trailing "
            f"spaces to be stored in a recording file, got {value!r}"
        )


# ----------------------------------------------------------------------------- public API
def read_recording(
    path: str | os.PathLike[str], *, pitch_mm: float | None = None, topic: str | None = None
) -> TactileFrames:
    """Read a recording: ``.npz``, ``.h5``/``.hdf5``, ``.csv``, ``.mcap`` file or rosbag2 folder.

    Parameters
    ----------
    path : str or os.PathLike
        The file; its extension (case-insensitive) selects the format. A
        folder holding ``metadata.yaml`` is read as a rosbag2 bag.
    pitch_mm : float, optional
        Taxel pitch, mm, replacing (and skipping the check of) any pitch stored
        in the file. Default: the stored ``pitch_mm``, else
        :data:`~taxelkit.frames.DEFAULT_PITCH_MM`.
    topic : str, optional
        Frames topic of a bag or MCAP file (default: its only frames topic);
        refused for the other formats.

    Returns
    -------
    TactileFrames
        Frames in their stored dtype (bool stays bool, float32 stays float32;
        integers become float64), with absent ``t_s`` = ``arange(T)`` s,
        ``units`` = ``"mm"`` or ``"contact"``, ``sensor`` = ``"unknown"``.

    Raises
    ------
    InputError
        If ``pitch_mm`` is given and is not a finite number > 0.
    FileTooLargeError
        If the file, or the arrays it declares, exceed the read limit of
        :mod:`taxelkit.io.limits` (checked before they are read).
    UnsafeFileError
        If the file points outside itself: HDF5 external storage, virtual
        datasets, external or soft links; archive members with a path.
    RecordingNotFoundError
        If nothing exists at ``path``.
    RecordingAccessError
        If ``path`` is a folder or cannot be opened.
    UnsupportedFormatError
        If the extension is not one of :data:`RECORDING_SUFFIXES`.
    EmptyRecordingError
        If the file has 0 bytes or holds zero frames.
    CorruptRecordingError
        If the file is truncated or damaged, lacks ``frames``, or (CSV) has
        mismatched columns, a ragged row or a cell that is not a number.
    InvalidRecordingError
        If a field breaks the rules of :class:`TactileFrames` (dimensions,
        NaN/Inf, timestamps, pitch, text).
    BagTopicError
        If a bag's topic is missing, ambiguous or carries another message type.
    BagDependencyError
        If a bag is read without the ``ros`` extra installed.

    Examples
    --------
    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> rec = TactileFrames(np.eye(3, dtype=bool)[None], pitch_mm=2.0)
    >>> out = write_recording(rec, folder / "eye.csv")
    >>> read_recording(out).equals(rec)
    True
    """
    p = Path(path)
    override = None if pitch_mm is None else check_positive("pitch_mm", pitch_mm)
    from taxelkit.io.bags import is_rosbag2_folder, raw_from_rosbag2

    if is_rosbag2_folder(p):
        return build_frames(raw_from_rosbag2(p, topic=topic), p, override)
    size, head = _probe_input(p)
    fmt = _format_for(p)
    if size == 0:
        raise fail(EmptyRecordingError, p, "is empty (0 bytes)")
    ReadBudget(p).check_file_size(size)
    _check_signature(p, head, fmt)
    if fmt is MCAP:
        return build_frames(read_mcap(p, head, topic), p, override)
    if topic is not None:
        raise InputError(f"{p}: a topic applies only to ROS 2 bags and MCAP files")
    return build_frames(fmt.read(p, head), p, override)


def write_recording(
    rec: TactileFrames,
    path: str | os.PathLike[str],
    *,
    force: bool = False,
    topic: str | None = None,
) -> Path:
    """Write a recording atomically; the extension selects the format.

    Parameters
    ----------
    rec : TactileFrames
        The recording. Frames must be bool, float16, float32 or float64 (native
        byte order); ``units`` and ``sensor`` one line of text.
    path : str or os.PathLike
        Output file ending in ``.npz``, ``.h5``, ``.hdf5``, ``.csv`` or
        ``.mcap`` (case-insensitive). Its folder must exist. (A rosbag2
        folder is written by :func:`taxelkit.io.bags.write_rosbag2`.)
    force : bool, optional
        Replace an existing file. Default ``False``.
    topic : str, optional
        Frames topic of an ``.mcap`` file (default ``/tactile``); refused
        for the other formats.

    Returns
    -------
    pathlib.Path
        The written path. :func:`read_recording` of it ``equals`` ``rec``.

    Raises
    ------
    InputError
        If ``rec`` is not a :class:`TactileFrames` (a bare array, say).
    UnsupportedFormatError
        If the extension is not one of :data:`RECORDING_SUFFIXES`.
    EmptyRecordingError
        If ``rec`` has zero frames.
    InputError
        If the frame dtype or a text field cannot be stored exactly.
    OutputExistsError
        If ``path`` exists and ``force`` is false.
    OutputWriteError
        If the operating system refuses the write.
    """
    check_type(
        "rec", rec, TactileFrames, "a TactileFrames (wrap bare arrays: TactileFrames(frames))"
    )
    p = Path(path)
    fmt = _format_for(p)
    if rec.n_frames == 0:
        raise fail(EmptyRecordingError, p, "refusing to write a recording with zero frames")
    if rec.frames.dtype not in WRITABLE_FRAME_DTYPES:
        raise InputError(
            f"frames dtype must be one of bool, float16, float32, float64 (native byte "
            f"order) to be written, got {rec.frames.dtype.str}"
        )
    _check_text_for_file("units", rec.units)
    _check_text_for_file("sensor", rec.sensor)
    if fmt is MCAP:
        return atomic_write(p, lambda tmp: write_mcap(rec, tmp, topic), force=force)
    if topic is not None:
        raise InputError(f"{p}: a topic applies only to ROS 2 bags and MCAP files")
    return atomic_write(p, lambda tmp: fmt.write(rec, tmp), force=force)
