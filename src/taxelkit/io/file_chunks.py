"""A recording's chunks as a picklable source: opened where it is iterated.

:func:`~taxelkit.io.chunked_read.open_chunks` opens a file in the process
that calls it. :class:`FileChunks` names the file and how to cut it, and opens
it only when called, so that another process (the Levels 1-2 worker of
:func:`~taxelkit.smart.recognise_pipeline.recognise_pipelined`) can read it
itself: the frames then never pass through the caller's process.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from taxelkit.frames import TactileFrames
from taxelkit.io.chunked_read import open_chunks
from taxelkit.io.packed_chunk import PackedChunk

__all__ = ["FileChunks"]


@dataclass(frozen=True)
class FileChunks:
    """The chunks of a recording file, read when called.

    Parameters
    ----------
    path : str or os.PathLike
        A recording (any format :func:`~taxelkit.io.chunked_read.open_chunks` opens).
    pitch_mm : float, optional
        Taxel pitch, mm, replacing the stored one.
    chunk_frames : int, optional
        Frames per chunk (the default of :meth:`~taxelkit.io.chunked_read.ChunkedRecording.chunks`).

    Examples
    --------
    >>> import tempfile
    >>> import numpy as np
    >>> from taxelkit.io.recordings import write_recording
    >>> out = write_recording(
    ...     TactileFrames(np.zeros((5, 4, 4), bool)), Path(tempfile.mkdtemp()) / "r.h5")
    >>> [c.n_frames for c in FileChunks(out, chunk_frames=2)()]
    [2, 2, 1]
    """

    path: str | os.PathLike[str]
    pitch_mm: float | None = None
    chunk_frames: int | None = None

    def __call__(self) -> Iterator[TactileFrames | PackedChunk]:
        """Open the file and yield its chunks: packed as stored where it is, else frames.

        Raises
        ------
        RecordingError
            As :func:`~taxelkit.io.chunked_read.open_chunks`, when the file or a chunk is bad.
        """
        with open_chunks(Path(self.path), pitch_mm=self.pitch_mm) as rec:
            if rec.packed:
                yield from rec.packed_chunks(self.chunk_frames)
            else:
                yield from rec.chunks(self.chunk_frames)
