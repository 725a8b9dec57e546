"""The HDF5 side of :func:`~taxelkit.io.chunked_read.open_chunks`.

The recording's fields are read and checked at once; ``frames`` (or the
packed ``frames_packed``, see ``docs/recording-format.md``) and ``t_s`` stay
HDF5 datasets, sliced a chunk at a time by
:class:`~taxelkit.io.chunked_read.ChunkedRecording`.
"""

from __future__ import annotations

import sys
from typing import TYPE_CHECKING

import h5py
import numpy as np

from taxelkit.errors import CorruptRecordingError, InvalidRecordingError, TaxelkitError
from taxelkit.io._raw import describe_exception, fail
from taxelkit.io.chunked_npz import SCALARS, Layout, item_bytes
from taxelkit.io.limits import ReadBudget
from taxelkit.io.limits_h5 import check_h5_attribute, check_h5_dataset, h5_node
from taxelkit.io.recording_codecs import PACKED_COLS_ATTR, PACKED_FRAMES

if TYPE_CHECKING:
    from taxelkit.io.chunked_read import ChunkedRecording

__all__ = ["open_h5"]

_UNLIMITED = sys.maxsize


def open_h5(rec: ChunkedRecording) -> None:
    """Open ``rec.path`` as HDF5 into ``rec``: its fields read, its frame datasets checked.

    The frames (``frames``, or the packed ``frames_packed``) and ``t_s`` are
    kept as datasets, sliced chunk by chunk; their sizes are checked per chunk.

    Raises
    ------
    RecordingError
        If the file is not a readable HDF5 recording.
    """
    path = rec.path
    try:
        root = rec._stack.enter_context(h5py.File(path, "r"))
        budget = ReadBudget(path)
        for name in SCALARS:
            if name in root.attrs:
                check_h5_attribute(path, root.attrs, name, budget)
                rec._scalars[name] = root.attrs[name]
            elif (node := h5_node(path, root, name)) is not None:
                check_h5_dataset(path, name, node, budget)
                rec._scalars[name] = node[()]
        structure = ReadBudget(path, limit=_UNLIMITED)  # sizes are checked per chunk
        frames = h5_node(path, root, "frames")
        packed = frames is None and (frames := h5_node(path, root, PACKED_FRAMES)) is not None
        if frames is None:
            found = ", ".join(root.keys()) or "nothing"
            raise fail(CorruptRecordingError, path, f"no 'frames' array (the file holds: {found})")
        name = PACKED_FRAMES if packed else "frames"
        if not isinstance(frames, h5py.Dataset):
            raise fail(
                CorruptRecordingError, path, f"{name!r} is an HDF5 group, expected a dataset"
            )
        check_h5_dataset(path, name, frames, structure)
        t_s = h5_node(path, root, "t_s")
        if t_s is not None:
            if not isinstance(t_s, h5py.Dataset):
                raise fail(CorruptRecordingError, path, "'t_s' is an HDF5 group, not a dataset")
            check_h5_dataset(path, "t_s", t_s, structure)
        shape = tuple(frames.shape)
        if len(shape) != 3:
            raise fail(InvalidRecordingError, path, f"frames must be (T, rows, cols), got {shape}")
        cols = shape[2]
        if packed:
            cols = int(frames.attrs.get(PACKED_COLS_ATTR, 8 * shape[2]))
            if frames.dtype != np.uint8 or not 8 * shape[2] - 8 < cols <= 8 * shape[2]:
                raise fail(
                    InvalidRecordingError,
                    path,
                    f"{PACKED_FRAMES} must be uint8 with {PACKED_COLS_ATTR} in "
                    f"({8 * shape[2] - 8}, {8 * shape[2]}], got {frames.dtype} and {cols}",
                )
            rec._scalars.setdefault("units", "contact")
        if t_s is not None and tuple(t_s.shape) != (shape[0],):
            raise fail(
                InvalidRecordingError,
                path,
                f"t_s must have {shape[0]} entries (one per frame), got shape {t_s.shape}",
            )
    except TaxelkitError:
        raise
    except Exception as exc:
        raise fail(
            CorruptRecordingError, path, f"not a readable HDF5 file ({describe_exception(exc)})"
        ) from exc
    rec._frames, rec._t_s = frames, t_s
    item = 1 if packed else item_bytes(frames.dtype)
    rec.layout = Layout(int(shape[0]), (int(shape[1]), int(cols)), packed, shape[1] * cols * item)
