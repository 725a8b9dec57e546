"""Recordings on disk (``.npz``, ``.h5``, ``.csv``) and atomic output files."""

from taxelkit.io.atomic import atomic_write
from taxelkit.io.recordings import (
    RECORDING_SUFFIXES,
    read_recording,
    recording_format,
    write_recording,
)

__all__ = [
    "RECORDING_SUFFIXES",
    "atomic_write",
    "read_recording",
    "recording_format",
    "write_recording",
]
