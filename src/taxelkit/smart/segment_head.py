"""What an open segment keeps of its first frames, and its rows (for :mod:`segment_scan`).

Level 3's transitions (:mod:`taxelkit.smart.transitions`) ask a segment for
its frame rate, its first frames' numbers, mean axis, mean centre and the
grid's share of its axis; a streamed segment keeps only the first
``max(k, edge_hold)`` frames for them, a running sum of its axis vectors,
and its slip scanner. :class:`SegmentHead` holds that part of
:class:`~taxelkit.smart.segment_scan.SegmentScanner`.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.slip import Slip
from taxelkit.smart.slip_scan import SlipScanner
from taxelkit.smart.tacteme_config import TactemeConfig
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.tactemes import SegmentTrack, frames_for_interval
from taxelkit.smart.track_geometry import grid_wobble_deg
from taxelkit.smart.track_stream import RunningSum, drawn_length_mm, mean_axis_deg

__all__ = ["ROW_COLUMNS", "SegmentHead", "rows_from_track"]

#: Columns of the per-frame rows fed to :meth:`SegmentScanner.extend`:
#: centre x, y (mm), orientation (deg), area (mm^2), elongation, half-length
#: (mm), line extent low, high (mm from the centre, NaN if not measured), time (s).
ROW_COLUMNS = ("cx", "cy", "theta", "area", "elong", "half", "lo", "hi", "t")


def rows_from_track(track: SegmentTrack) -> NDArray[np.float64]:
    """The per-frame rows ``(n, 9)`` (:data:`ROW_COLUMNS`) of a whole segment's track."""
    ext = np.full((track.frames.size, 2), np.nan) if track.extent_mm is None else track.extent_mm
    return np.column_stack(
        [
            track.centre_mm,
            track.orientation_deg,
            track.area_mm2,
            track.elongation,
            track.half_length_mm,
            ext,
            track.t_s,
        ]
    )


class SegmentHead:
    """The first frames, the axis sum and the slip scanner of one streamed segment.

    Parameters
    ----------
    cls : int
        The segment's :class:`~taxelkit.smart.contact_classes.ContactClass`.
    config : TactemeConfig
    pitch_mm : float
        Taxel pitch, mm (0: unknown), as :attr:`SegmentTrack.pitch_mm`.
    """

    def __init__(self, cls: int, config: TactemeConfig, pitch_mm: float = 0.0) -> None:
        self.cls = int(cls)
        self.config = config
        self.pitch_mm = float(pitch_mm)
        self.k = int(config.debounce_frames)
        self.size = 0
        self.first_frame = -1
        self.last_frame = -1
        self.found: list[tuple[Tacteme, int]] = []
        self._head_frames: list[int] = []
        self._head_t: list[float] = []
        self._head_theta: list[float] = []
        self._head_xy: list[list[float]] = []
        self._head_len: list[float] = []
        self._head_cap: int | None = None
        self._dt: dict[int, float] = {}  # frame interval of the first frames, per k
        self._axis_sum = RunningSum(2)
        self._slip = (
            None
            if config.slip is None
            else SlipScanner(self.cls, config.slip, k=int(config.debounce_frames))
        )

    # -- what Level 3's transitions need ---------------------------------------------------
    def _timing(self) -> SegmentTrack:
        empty = np.zeros(0)
        t = np.asarray(self._head_t, dtype=np.float64)
        return SegmentTrack(np.zeros(0, np.intp), empty, empty, empty, empty, empty, t)

    def frames_for(self, seconds: float, k: int, *, minimum: int | None = None) -> int:
        """As :meth:`SegmentTrack.frames_for <taxelkit.smart.tactemes.SegmentTrack.frames_for>`."""
        if len(self._head_t) < max(2, k):  # the rate is not yet fixed
            return self._timing().frames_for(seconds, k, minimum=minimum)
        dt = self._dt.get(k)
        if dt is None:
            dt = self._dt[k] = self._timing().frame_interval_s(k)
        return frames_for_interval(dt, seconds, k if minimum is None else minimum)

    def frame_at(self, i: int) -> int:
        """Frame number of the segment's ``i``-th frame (``i`` within the first frames kept)."""
        return self._head_frames[i]

    def mean_axis_deg(self, stop: int | None = None) -> float:
        """Mean axis of the first ``stop`` frames (kept ones), or of all of them, deg."""
        if stop is None:
            if self.size == 0:
                return float("nan")
            s = self._axis_sum.total
            return float(0.5 * np.rad2deg(np.arctan2(s[1], s[0])))
        return mean_axis_deg(np.asarray(self._head_theta[:stop], dtype=np.float64))

    def mean_centre_mm(self, stop: int) -> tuple[float, float]:
        """Mean centre of the first ``stop`` frames (kept ones), mm."""
        c = np.asarray(self._head_xy[:stop], dtype=np.float64).mean(axis=0)
        return float(c[0]), float(c[1])

    def grid_wobble_deg(self, stop: int) -> float:
        """:func:`~taxelkit.smart.track_geometry.grid_wobble_deg` of the first ``stop`` frames."""
        return grid_wobble_deg(np.asarray(self._head_len[:stop], dtype=np.float64), self.pitch_mm)

    def tactemes(self) -> list[tuple[Tacteme, int]]:
        """The tactemes decided so far, in the order decided."""
        return self.found

    def slips(self) -> list[Slip]:
        """Slip phases so far (:class:`~taxelkit.smart.slip.SlipScanner`)."""
        return [] if self._slip is None else self._slip.all_slips()

    def close_slips(self) -> list[Slip]:
        """The segment ended: a slip going on ends at its last frame."""
        return [] if self._slip is None else self._slip.close()

    def _keep_head(
        self, frames: NDArray[np.intp], rows: NDArray[np.float64], cap: int, offset: int
    ) -> None:
        """Keep the segment's first ``cap`` frames: ``frames[offset:]`` come next."""
        room = max(0, cap - len(self._head_frames))
        if room:
            stop = offset + room
            self._head_frames += frames[offset:stop].tolist()
            self._head_t += rows[offset:stop, 8].tolist()
            self._head_theta += rows[offset:stop, 2].tolist()
            self._head_xy += rows[offset:stop, 0:2].tolist()
            self._head_len += drawn_length_mm(rows[offset:stop]).tolist()
