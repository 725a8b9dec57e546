"""What one array's stream holds back for Levels 3-4 within a chunk.

:class:`~taxelkit.smart.stream_state.ArrayStream` defers a segment accepted
within a chunk until it knows whether the segment also ends there (then the
batch functions take it whole), and queues its calls to Levels 3-4 to replay
them in order at the chunk's end: :class:`DeferredSegment` and
:class:`LevelsCall`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.levels34 import Segment
from taxelkit.smart.tactemes import SegmentTrack

__all__ = ["DeferredSegment", "LevelsCall"]


@dataclass
class DeferredSegment:
    """A segment accepted within a chunk: its class, accepting frame and frames so far."""

    cls: int
    accept: int
    first_j: list[NDArray[np.intp]]  # the candidate's frames (a scanner's first feed)
    first_rows: list[NDArray[np.float64]]
    later: list[tuple[NDArray[np.intp], NDArray[np.float64]]] = field(default_factory=list)


@dataclass
class LevelsCall:
    """A call to Levels 3-4: a run opened (a whole segment's track, or a segment), or updated."""

    cls: int
    accept: int
    seg: Segment | None
    track: SegmentTrack | None = None
    rows: NDArray[np.float64] | None = None  # the track's, as fed (ROW_COLUMNS)
    update: bool = False
