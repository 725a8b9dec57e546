"""``recognize --live --record FILE.h5``: the received frames appended to a long recording."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from taxelkit.io.datagram_batch import FrameBatch
from taxelkit.io.frame_protocol import PayloadType

__all__ = ["RECORD_CHUNK_FRAMES", "Recorder"]

#: Frames per chunk of a ``--record`` file: a crash loses at most these
#: (17 s at 240 frames/s).
RECORD_CHUNK_FRAMES = 4096


class Recorder:
    """``--record FILE.h5``: the received frames appended as they come."""

    def __init__(self, path: Path, pitch_mm: float, force: bool) -> None:
        self.path = path
        self.pitch_mm = pitch_mm
        self.force = force
        self.out: Any = None  # a RecordingAppender, once the first frame gives the shape
        self.skipped = 0  # frames whose time did not increase
        self._t_last = -math.inf

    def append(self, batch: FrameBatch) -> None:
        from taxelkit.io.chunked_write import RecordingAppender

        values, t = batch.values, batch.t_s
        if self.out is None:
            bool_frames = batch.payload_type == PayloadType.BOOL
            self.out = RecordingAppender(
                self.path,
                shape=batch.shape,
                pitch_mm=self.pitch_mm,
                dtype=bool if bool_frames else np.float32,
                units=None if bool_frames else _UNITS[batch.payload_type],
                chunk_frames=RECORD_CHUNK_FRAMES,
                force=self.force,
            )
        if values.shape[1:] != self.out.shape:
            self.skipped += batch.n_frames
            return
        before = np.maximum.accumulate(np.concatenate([[self._t_last], t[:-1]]))
        keep = t > before  # a sender restart sends times again: not recorded
        self.skipped += int(np.count_nonzero(~keep))
        if np.any(keep):
            frames = values[keep]
            self.out.append(frames if frames.dtype == bool else frames.astype(np.float32), t[keep])
            self._t_last = float(t[keep][-1])

    def close(self) -> str:
        """Close the file; a few words for the summary."""
        if self.out is None:
            return f"nothing recorded to {self.path}"
        n = self.out.n_frames
        self.out.close()
        skipped = f" ({self.skipped} not recorded)" if self.skipped else ""
        return f"{n} frames recorded to {self.path}{skipped}"


_UNITS = {PayloadType.UINT16: "counts", PayloadType.FLOAT32: "mm"}
