"""HDF5 side of the reader discipline of :mod:`taxelkit.io.limits`.

Hard links inside the file only (no external, soft or virtual storage), each
dataset's and attribute's declared size charged to the :class:`ReadBudget`
before it is read, and one typed one-line error for every h5py failure.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from taxelkit.errors import CorruptRecordingError, UnsafeFileError
from taxelkit.io._raw import fail
from taxelkit.io.limits import ReadBudget

__all__ = ["check_h5_attribute", "check_h5_dataset", "h5_node"]


def h5_node(path: Path, group: Any, name: str) -> Any | None:
    """The object ``group[name]`` if it is a hard link inside the file, else ``None`` if absent.

    Parameters
    ----------
    path : pathlib.Path
        The file, for messages.
    group : h5py.Group
        An open group (or file).
    name : str
        A member name.

    Raises
    ------
    UnsafeFileError
        If ``name`` is an external link or a soft link: neither is followed,
        so no other file (or other part of this one) is opened through it.
    """
    import h5py

    link = group.get(name, getlink=True)
    if link is None:
        return None
    if isinstance(link, h5py.ExternalLink):
        raise fail(
            UnsafeFileError,
            path,
            f"{name!r} is an external link to {link.filename!r}; taxelkit reads no other file",
        )
    if isinstance(link, h5py.SoftLink):
        raise fail(
            UnsafeFileError,
            path,
            f"{name!r} is a soft link to {link.path!r}; links are not followed",
        )
    return group[name]


def check_h5_dataset(path: Path, name: str, dataset: Any, budget: ReadBudget) -> None:
    """Refuse a dataset stored outside the file or too large, before reading it.

    Parameters
    ----------
    path : pathlib.Path
        The file, for messages.
    name : str
        The dataset's name.
    dataset : h5py.Dataset
        The open dataset; its data are not read.
    budget : ReadBudget
        Charged with the declared size.

    Raises
    ------
    UnsafeFileError
        If the raw data live in external files or the dataset is virtual.
    CorruptRecordingError
        If the dtype is variable-length (other than one text value) or compound.
    FileTooLargeError
        If the declared size exceeds the budget.
    """
    import h5py

    if dataset.external:
        files = ", ".join(repr(str(e[0])) for e in dataset.external[:3])
        raise fail(
            UnsafeFileError,
            path,
            f"dataset {name!r} keeps its data in external file(s) {files}; "
            f"taxelkit reads no other file",
        )
    if dataset.is_virtual:
        raise fail(
            UnsafeFileError,
            path,
            f"dataset {name!r} is a virtual dataset (data mapped from other files); "
            f"taxelkit reads no other file",
        )
    _check_h5_type(path, f"dataset {name!r}", dataset.dtype, dataset.shape, h5py)
    budget.take(name, dataset.shape or (), dataset.dtype)


def check_h5_attribute(path: Path, attrs: Any, name: str, budget: ReadBudget) -> None:
    """Refuse an attribute of unsupported type or too large, before reading it.

    Parameters
    ----------
    path : pathlib.Path
        The file, for messages.
    attrs : h5py.AttributeManager
        The attributes of a group or dataset.
    name : str
        The attribute's name.
    budget : ReadBudget
        Charged with the declared size.
    """
    import h5py

    aid = attrs.get_id(name)
    dtype = aid.dtype
    shape = aid.shape or ()
    _check_h5_type(path, f"attribute {name!r}", dtype, shape, h5py)
    budget.take(name, shape, dtype)


def _check_h5_type(
    path: Path, what: str, dtype: np.dtype[Any], shape: tuple[int, ...] | None, h5py: Any
) -> None:
    size = 0 if shape is None else math.prod(shape)
    if h5py.check_string_dtype(dtype) is not None and dtype.kind == "O":
        if size > 1:
            raise fail(
                CorruptRecordingError,
                path,
                f"{what} holds {size} variable-length strings; expected one text value",
            )
        return
    if dtype.hasobject or dtype.fields is not None or dtype.kind not in "biufcSU":
        raise fail(CorruptRecordingError, path, f"{what} has unsupported HDF5 type {dtype}")
