"""The CSV recording format: one frame per line, taxels in row-major columns.

The layout is specified in ``docs/recording-format.md``::

    # pitch_mm: 1.7625
    # units: mm
    # sensor: bonneville-16x16
    # dtype: float32
    t_s,r0c0,r0c1,...,r15c15
    0.0,0.0,0.013,...

Comment lines (``#``) before the header carry the scalars as ``key: value``;
all are optional. The header is ``t_s`` followed by one ``r{i}c{j}`` name per
taxel in row-major order; the array shape is recovered from the largest indices.
"""

from __future__ import annotations

import re
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import CorruptRecordingError, EmptyRecordingError
from taxelkit.frames import CONTACT_UNITS, TactileFrames
from taxelkit.io._raw import RawRecording, describe_exception, fail
from taxelkit.io.limits import ReadBudget

__all__ = [
    "CSV_DTYPES",
    "CSV_METADATA_KEYS",
    "TIME_COLUMN",
    "read_csv_recording",
    "taxel_column_names",
    "write_csv_recording",
]

#: Name of the first CSV column: the frame timestamps, s.
TIME_COLUMN = "t_s"
#: Keys of the ``# key: value`` comment lines that taxelkit reads and writes.
CSV_METADATA_KEYS = ("pitch_mm", "units", "sensor", "dtype")
#: Values the ``# dtype:`` comment may take, and the frame dtype each selects.
CSV_DTYPES: dict[str, np.dtype[Any]] = {
    "bool": np.dtype(np.bool_),
    "float16": np.dtype(np.float16),
    "float32": np.dtype(np.float32),
    "float64": np.dtype(np.float64),
}
_COMMENT = "#"
_TAXEL_NAME = re.compile(r"r([0-9]+)c([0-9]+)")


def taxel_column_names(rows: int, cols: int) -> list[str]:
    """CSV column names of a ``rows x cols`` array in row-major order.

    Examples
    --------
    >>> taxel_column_names(2, 2)
    ['r0c0', 'r0c1', 'r1c0', 'r1c1']
    """
    return [f"r{i}c{j}" for i in range(rows) for j in range(cols)]


# ----------------------------------------------------------------------------- writing
def _parse_cells(cells: NDArray[np.str_]) -> NDArray[np.float64]:
    """Decimal strings to float64; the same conversion for reading and for write checks."""
    return cells.astype(np.float64)


def _format_cells(values: NDArray[Any]) -> NDArray[np.str_]:
    """Decimal strings that read back bit-identical through :func:`_parse_cells`.

    Bool becomes ``0``/``1``. float64 uses Python's shortest round-trip ``repr``.
    float32 and float16 first try their own shortest representation (``0.1``
    rather than ``0.10000000149011612``); any value that would not come back
    exactly through float64 parsing is written as the float64 ``repr`` of its
    exact value instead, which always does.
    """
    flat = np.ascontiguousarray(values).reshape(-1)
    if flat.dtype == np.bool_:
        return np.where(flat, "1", "0")
    if flat.dtype == np.float64:
        return np.array([repr(v) for v in flat.tolist()], dtype=np.str_)
    short = np.array([str(v) for v in flat], dtype=np.str_)
    back = _parse_cells(short).astype(flat.dtype)
    uint = np.dtype(f"u{flat.dtype.itemsize}")
    bad = np.flatnonzero(back.view(uint) != flat.view(uint))
    if bad.size:
        exact = np.array([repr(float(flat[k])) for k in bad], dtype=np.str_)
        short = short.astype(np.result_type(short.dtype, exact.dtype))
        short[bad] = exact
    return short


def write_csv_recording(rec: TactileFrames, path: Path) -> None:
    """Write ``rec`` to ``path`` as CSV (the caller makes the write atomic).

    Parameters
    ----------
    rec : TactileFrames
        Frames of dtype bool, float16, float32 or float64.
    path : pathlib.Path
        Destination, overwritten.
    """
    n, rows, cols = rec.shape
    lines = [
        f"{_COMMENT} pitch_mm: {float(rec.pitch_mm)!r}",
        f"{_COMMENT} units: {rec.units}",
        f"{_COMMENT} sensor: {rec.sensor}",
    ]
    if not rec.is_contact:
        lines.append(f"{_COMMENT} dtype: {rec.frames.dtype.name}")
    lines.append(",".join([TIME_COLUMN, *taxel_column_names(rows, cols)]))
    cells = _format_cells(rec.frames).reshape(n, rows * cols)
    times = [repr(t) for t in rec.t_s.tolist()]
    with path.open("w", encoding="utf-8", newline="\n") as fh:
        fh.write("\n".join(lines) + "\n")
        for t, row in zip(times, cells.tolist(), strict=True):
            fh.write(t + "," + ",".join(row) + "\n")


# ----------------------------------------------------------------------------- reading
def _shape_from_header(path: Path, names: list[str]) -> tuple[int, int]:
    """``(rows, cols)`` from the header names, or CorruptRecordingError."""
    problem = "mismatched CSV columns"
    if names[0] != TIME_COLUMN:
        raise fail(
            CorruptRecordingError,
            path,
            f"{problem}: the first column must be {TIME_COLUMN!r}, got {names[0]!r}",
        )
    taxels = names[1:]
    if not taxels:
        raise fail(
            CorruptRecordingError, path, f"{problem}: no taxel columns after {TIME_COLUMN!r}"
        )
    rows = cols = 0
    for name in taxels:
        m = _TAXEL_NAME.fullmatch(name)
        if m is None:
            raise fail(
                CorruptRecordingError,
                path,
                f"{problem}: {name!r} is not a taxel column name r<row>c<col>",
            )
        rows, cols = max(rows, int(m[1]) + 1), max(cols, int(m[2]) + 1)
    if rows * cols != len(taxels):
        raise fail(
            CorruptRecordingError,
            path,
            f"{problem}: the largest indices imply {rows}x{cols} = {rows * cols} taxel "
            f"columns, the header has {len(taxels)}",
        )
    for k, (got, want) in enumerate(zip(taxels, taxel_column_names(rows, cols), strict=True)):
        if got != want:
            raise fail(
                CorruptRecordingError,
                path,
                f"{problem}: column {k + 2} is {got!r}, expected {want!r} "
                f"(r0c0, r0c1, ... in row-major order)",
            )
    return rows, cols


def _bad_cell(path: Path, lineno: int, cells: list[str], names: list[str]) -> CorruptRecordingError:
    """The error naming the first cell of a line that does not parse as a number."""
    for name, cell in zip(names, cells, strict=True):
        try:
            _parse_cells(np.array([cell], dtype=np.str_))
        except ValueError:
            return fail(
                CorruptRecordingError,
                path,
                f"line {lineno}, column {name}: not a number: {cell.strip()[:40]!r}",
            )
    return fail(CorruptRecordingError, path, f"line {lineno}: a cell is not a number")


def _lines(text: str, start: int = 0, lineno: int = 1) -> Iterator[tuple[int, int, str]]:
    """``(line number, end index, line)`` of ``\\n``-separated ``text`` from index ``start``.

    Slices one line at a time, so a large file is never held twice.
    """
    pos = start
    while pos < len(text):
        end = text.find("\n", pos)
        if end < 0:
            end = len(text)
        yield lineno, end, text[pos:end]
        pos = end + 1
        lineno += 1


def _data_lines(text: str, start: int, lineno: int) -> Iterator[tuple[int, str]]:
    """``(line number, stripped line)`` of the frame lines from index ``start``."""
    for number, _, line in _lines(text, start, lineno):
        stripped = line.strip()
        if stripped and not stripped.startswith(_COMMENT):
            yield number, stripped


def read_csv_recording(path: Path, budget: ReadBudget | None = None) -> RawRecording:
    """Read the fields of a CSV recording, unchecked.

    Parameters
    ----------
    path : pathlib.Path
        An existing, non-empty file.
    budget : ReadBudget, optional
        Charged with the size of the parsed table before it is allocated;
        default a fresh budget at :func:`~taxelkit.io.limits.max_read_bytes`.

    Returns
    -------
    RawRecording
        ``frames`` (T, rows, cols) in the ``# dtype:`` of the file (float64 if
        absent), ``t_s`` (T,) float64, and the ``# pitch_mm:``, ``# units:`` and
        ``# sensor:`` values as strings where present.

    Raises
    ------
    CorruptRecordingError
        On bytes that are not UTF-8, no header, mismatched CSV columns, a ragged
        row, a cell that is not a number, or an unknown ``# dtype:``.
    EmptyRecordingError
        If the file has a header but no frame lines.
    FileTooLargeError
        If the table would exceed the read limit.
    """
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise fail(CorruptRecordingError, path, f"cannot read ({describe_exception(exc)})") from exc
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise fail(
            CorruptRecordingError, path, f"not UTF-8 text (bad byte at offset {exc.start})"
        ) from None
    del data
    text = text.replace("\r\n", "\n").replace("\r", "\n")
    meta: dict[str, str] = {}
    header: str | None = None
    start = header_lineno = 0
    for lineno, end, line in _lines(text):
        stripped = line.strip()
        if not stripped:
            continue
        if stripped.startswith(_COMMENT):
            key, colon, value = stripped[1:].partition(":")
            if colon:
                meta[key.strip()] = value.strip()
            continue
        header, start, header_lineno = stripped, end + 1, lineno
        break
    if header is None:
        raise fail(
            CorruptRecordingError,
            path,
            f"no CSV header line (expected '{TIME_COLUMN},r0c0,r0c1,...')",
        )
    names = [n.strip().strip('"') for n in header.split(",")]
    rows, cols = _shape_from_header(path, names)
    n_frames = sum(1 for _ in _data_lines(text, start, header_lineno + 1))
    if n_frames == 0:
        raise fail(EmptyRecordingError, path, "holds zero frames (a CSV header and no data lines)")
    # Charged before the values are allocated: the parsed table and its copy
    # into a TactileFrames.
    (budget or ReadBudget(path)).take(
        "the CSV table", (2, n_frames, len(names)), np.dtype(np.float64)
    )
    values = np.empty((n_frames, len(names)), dtype=np.float64)
    for k, (lineno, stripped) in enumerate(_data_lines(text, start, header_lineno + 1)):
        cells = stripped.split(",")
        if len(cells) != len(names):
            raise fail(
                CorruptRecordingError,
                path,
                f"line {lineno} has {len(cells)} cells, expected {len(names)} "
                f"({TIME_COLUMN} and {rows}x{cols} taxels)",
            )
        try:
            values[k] = _parse_cells(np.array(cells, dtype=np.str_))
        except ValueError:
            raise _bad_cell(path, lineno, cells, names) from None
    del text

    dtype_name = meta.get("dtype")
    if dtype_name is not None and dtype_name not in CSV_DTYPES:
        raise fail(
            CorruptRecordingError,
            path,
            f"unsupported '# dtype: {dtype_name}' comment; expected one of {', '.join(CSV_DTYPES)}",
        )
    contact = dtype_name == "bool" or meta.get("units") == CONTACT_UNITS
    frames: NDArray[Any] = values[:, 1:].reshape(n_frames, rows, cols)
    if dtype_name is not None and not contact:
        with np.errstate(over="ignore"):  # an overflow becomes Inf, rejected later
            frames = frames.astype(CSV_DTYPES[dtype_name])
    return RawRecording(
        frames=frames,
        t_s=values[:, 0],
        pitch_mm=meta.get("pitch_mm"),
        units=meta.get("units"),
        sensor=meta.get("sensor"),
        contact=contact,
    )
