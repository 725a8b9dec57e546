"""Readers and writers of the recording formats (``.npz``, ``.h5``, ``.csv``, ``.mcap``).

One :class:`Format` per file format, keyed by suffix in :data:`FORMATS`;
:mod:`taxelkit.io.recordings` picks one, checks the file and validates what it
read. The formats are specified in ``docs/recording-format.md``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import h5py
import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import (
    CorruptRecordingError,
    FileTooLargeError,
    InvalidRecordingError,
    TaxelkitError,
)
from taxelkit.frames import CONTACT_UNITS, TactileFrames
from taxelkit.io._raw import RECORDING_FIELDS, RawRecording, describe_exception, fail
from taxelkit.io.csv_format import read_csv_recording, write_csv_recording
from taxelkit.io.limits import ReadBudget
from taxelkit.io.limits_h5 import check_h5_attribute, check_h5_dataset, h5_node
from taxelkit.io.npz_read import read_npz

__all__ = [
    "FORMATS",
    "MAGIC_LENGTH",
    "MCAP",
    "PACKED_COLS_ATTR",
    "PACKED_FRAMES",
    "SIGNATURES",
    "Format",
    "read_mcap",
    "sniff",
    "write_mcap",
]

#: File signatures that identify a format from the first bytes: a zip archive
#: (every ``.npz``), HDF5 without a user block, and a bare ``.npy`` array.
SIGNATURES = (
    (b"PK", "npz"),
    (b"\x89HDF\r\n\x1a\n", "hdf5"),
    (b"\x93NUMPY", "npy"),
    (b"\x89MCAP0\r\n", "mcap"),
)
MAGIC_LENGTH = 8

#: HDF5 dataset of contact frames packed eight taxels to a byte along each row
#: (``numpy.packbits(..., axis=2, bitorder="little")``), ``(T, rows, ceil(cols / 8))``
#: uint8, read in place of ``frames`` (written by long recordings,
#: :mod:`taxelkit.io.chunked_write`).
PACKED_FRAMES = "frames_packed"
#: Attribute of :data:`PACKED_FRAMES`: the number of columns.
PACKED_COLS_ATTR = "cols"


@dataclass(frozen=True)
class Format:
    """A recording format: its name, a reader of raw fields and a writer."""

    name: str
    read: Callable[[Path, bytes], RawRecording]
    write: Callable[[TactileFrames, Path], None]


def _raw_from_fields(fields: dict[str, object], found: tuple[str, ...]) -> RawRecording:
    return RawRecording(
        frames=fields.get("frames"),
        t_s=fields.get("t_s"),
        pitch_mm=fields.get("pitch_mm"),
        units=fields.get("units"),
        sensor=fields.get("sensor"),
        found=found,
    )


def sniff(head: bytes) -> str | None:
    """Format named by a file's first bytes, if they carry a known signature."""
    for signature, name in SIGNATURES:
        if head.startswith(signature):
            return name
    return None


# ----------------------------------------------------------------------------- npz
def _read_npz(path: Path, head: bytes) -> RawRecording:
    if sniff(head) != "npz":
        raise fail(CorruptRecordingError, path, "not an .npz file (no zip archive signature)")
    # Declared sizes are checked before allocating; object arrays are refused,
    # so no code in the file is ever run.
    contents = read_npz(path, RECORDING_FIELDS, what="recording")
    return _raw_from_fields(dict(contents.arrays), contents.names)


def _write_npz(rec: TactileFrames, path: Path) -> None:
    # An open file, not a path: numpy appends ".npz" to any name not ending in
    # lower-case ".npz", which would miss "RUN.NPZ".
    with path.open("wb") as fh:
        np.savez_compressed(
            fh,
            frames=rec.frames,
            t_s=rec.t_s,
            pitch_mm=np.float64(rec.pitch_mm),
            units=np.str_(rec.units),
            sensor=np.str_(rec.sensor),
        )


# ----------------------------------------------------------------------------- HDF5
def _h5_field(
    path: Path, root: Any, name: str, budget: ReadBudget, *, dataset_only: bool = False
) -> object | None:
    """A root attribute (preferred for scalars) or a root dataset, else ``None``.

    Links, external storage and virtual datasets are refused, and the declared
    size is charged to ``budget``, before any data are read.
    """
    if not dataset_only and name in root.attrs:
        check_h5_attribute(path, root.attrs, name, budget)
        return root.attrs[name]  # type: ignore[no-any-return]
    node = h5_node(path, root, name)
    if node is None:
        return None
    if not isinstance(node, h5py.Dataset):
        raise fail(CorruptRecordingError, path, f"{name!r} is an HDF5 group, expected a dataset")
    check_h5_dataset(path, name, node, budget)
    return node[()]  # type: ignore[no-any-return]


def _read_h5(path: Path, head: bytes) -> RawRecording:
    del head  # HDF5 allows a user block before the signature; h5py finds it.
    budget = ReadBudget(path)
    try:
        with h5py.File(path, "r") as root:
            found = tuple(root.keys()) + tuple(root.attrs.keys())
            fields = {
                name: _h5_field(path, root, name, budget, dataset_only=name == "frames")
                for name in RECORDING_FIELDS
            }
            if fields["frames"] is None and PACKED_FRAMES in root:
                fields["frames"] = _h5_packed(path, root, budget)
                fields["units"] = CONTACT_UNITS if fields["units"] is None else fields["units"]
    except TaxelkitError:
        raise
    except MemoryError:
        raise fail(FileTooLargeError, path, "not enough memory to read the file") from None
    except Exception as exc:
        # h5py reports damage as OSError, KeyError, RuntimeError, ValueError, ...
        raise fail(
            CorruptRecordingError, path, f"not a readable HDF5 file ({describe_exception(exc)})"
        ) from exc
    return _raw_from_fields(fields, found)


def _h5_packed(path: Path, root: Any, budget: ReadBudget) -> NDArray[np.bool_]:
    """Unpack :data:`PACKED_FRAMES`, charging the budget with the unpacked size."""
    node = h5_node(path, root, PACKED_FRAMES)
    if not isinstance(node, h5py.Dataset) or node.dtype != np.uint8 or node.ndim != 3:
        raise fail(
            CorruptRecordingError,
            path,
            f"{PACKED_FRAMES!r} must be a (T, rows, n) uint8 dataset",
        )
    cols = int(node.attrs.get(PACKED_COLS_ATTR, 8 * node.shape[2]))
    if not 8 * node.shape[2] - 8 < cols <= 8 * node.shape[2]:
        raise fail(
            InvalidRecordingError,
            path,
            f"{PACKED_FRAMES} {PACKED_COLS_ATTR} must be in ({8 * node.shape[2] - 8}, "
            f"{8 * node.shape[2]}], got {cols}",
        )
    check_h5_dataset(path, PACKED_FRAMES, node, budget)
    budget.take("unpacked frames", (*node.shape[:2], cols), np.dtype(bool))
    out: NDArray[np.bool_] = np.unpackbits(node[()], axis=2, count=cols, bitorder="little").view(
        bool
    )
    return out


def _write_h5(rec: TactileFrames, path: Path) -> None:
    with h5py.File(path, "w") as root:
        root.create_dataset("frames", data=rec.frames, compression="gzip")
        root.create_dataset("t_s", data=rec.t_s)
        root.attrs["pitch_mm"] = np.float64(rec.pitch_mm)
        root.attrs["units"] = rec.units
        root.attrs["sensor"] = rec.sensor


def _read_csv(path: Path, head: bytes) -> RawRecording:
    del head
    return read_csv_recording(path)


_NPZ = Format("npz", _read_npz, _write_npz)
_HDF5 = Format("hdf5", _read_h5, _write_h5)


def read_mcap(path: Path, head: bytes, topic: str | None = None) -> RawRecording:
    del head
    from taxelkit.io.bags import raw_from_mcap

    return raw_from_mcap(path, topic=topic)


def write_mcap(rec: TactileFrames, path: Path, topic: str | None = None) -> None:
    from taxelkit.io.bags import write_mcap_file
    from taxelkit.io.ros_messages import DEFAULT_TOPIC

    write_mcap_file(rec, path, topic=DEFAULT_TOPIC if topic is None else topic)


_CSV = Format("csv", _read_csv, write_csv_recording)
MCAP = Format("mcap", read_mcap, write_mcap)
FORMATS = {".npz": _NPZ, ".h5": _HDF5, ".hdf5": _HDF5, ".csv": _CSV, ".mcap": MCAP}
