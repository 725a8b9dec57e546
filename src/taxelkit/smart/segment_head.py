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
from taxelkit.smart.track_geometry import first_jump, grid_wobble_deg
from taxelkit.smart.track_stream import RunningSum, drawn_length_mm, mean_axis_deg

__all__ = ["ROW_COLUMNS", "SegmentHead", "SlipInputs", "rows_from_track", "track_from_rows"]

#: A slip scanner's features of a chunk (and the last line axis they leave) and
#: its first decisions (:meth:`~taxelkit.smart.slip_scan.SlipScanner.extend`).
SlipInputs = tuple[
    tuple[NDArray[np.float64], NDArray[np.float64] | None],
    tuple[NDArray[np.bool_], NDArray[np.bool_]],
]

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


def track_from_rows(
    frames: NDArray[np.intp], rows: NDArray[np.float64], pitch_mm: float
) -> SegmentTrack:
    """The whole segment's track of frames ``(n,)`` and their rows ``(n, 9)`` (views of them)."""
    return SegmentTrack(
        frames,
        rows[:, 0:2],
        rows[:, 2],
        rows[:, 3],
        rows[:, 4],
        rows[:, 5],
        rows[:, 8],
        rows[:, 6:8],
        pitch_mm,
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
        # the first frames kept: their numbers and rows, in pieces (joined when read)
        self._head: list[tuple[NDArray[np.intp], NDArray[np.float64]]] = []
        self._head_n = 0
        self._head_cap: int | None = None
        self._dt: dict[int, float] = {}  # frame interval of the first frames, per k
        self._axis_sum = RunningSum(2)
        # frames too sparse to follow the contact (TactemeConfig.max_motion_gap_s): the
        # first frame its centre jumped to; watched until the rate is known to be dense
        self._jump: int | None = None
        self._last_centre: NDArray[np.float64] | None = None
        self._dense = config.max_motion_gap_s <= 0.0
        self._slip = (
            None
            if config.slip is None
            else SlipScanner(
                self.cls, config.slip, k=int(config.debounce_frames), pitch_mm=self.pitch_mm
            )
        )

    @property
    def slip_scanner(self) -> SlipScanner | None:
        """The segment's slip scanner (None without slip detection)."""
        return self._slip

    # -- what Level 3's transitions need ---------------------------------------------------
    def _head_rows(self) -> tuple[NDArray[np.intp], NDArray[np.float64]]:
        """The first frames kept: numbers ``(n,)`` and rows ``(n, 9)``."""
        if len(self._head) != 1:
            if not self._head:
                return np.zeros(0, np.intp), np.zeros((0, len(ROW_COLUMNS)))
            self._head = [
                (
                    np.concatenate([f for f, _ in self._head]),
                    np.concatenate([r for _, r in self._head]),
                )
            ]
        return self._head[0]

    def _timing(self) -> SegmentTrack:
        empty = np.zeros(0)
        t = np.ascontiguousarray(self._head_rows()[1][:, 8])
        return SegmentTrack(np.zeros(0, np.intp), empty, empty, empty, empty, empty, t)

    def frames_for(self, seconds: float, k: int, *, minimum: int | None = None) -> int:
        """As :meth:`SegmentTrack.frames_for <taxelkit.smart.tactemes.SegmentTrack.frames_for>`."""
        return frames_for_interval(
            self.frame_interval_s(k), seconds, k if minimum is None else minimum
        )

    def frame_interval_s(self, k: int) -> float:
        """The segment's frame interval from its first ``k`` frames (at least 2), s."""
        if self._head_n < max(2, k):  # the rate is not yet fixed
            return self._timing().frame_interval_s(k)
        dt = self._dt.get(k)
        if dt is None:
            dt = self._dt[k] = self._timing().frame_interval_s(k)
        return dt

    def jump_frame(self) -> int | None:
        """First frame to which the contact jumped between two sparse frames (None: none).

        Watched only while the frames come more than ``max_motion_gap_s``
        apart: the centre moved more than ``motion_step_mm`` from the
        segment's frame before.
        """
        return self._jump

    def _watch(self, frames: NDArray[np.intp], rows: NDArray[np.float64]) -> None:
        """Look for a jump of the centre in new frames ``(m,)`` and rows ``(m, 9)``."""
        if self._dense or self._jump is not None or frames.size == 0:
            return
        k, gap = self.k, self.config.max_motion_gap_s
        if self._head_n >= max(2, k) and self.frame_interval_s(k) <= gap:
            self._dense = True  # fixed once the first frames are in: nothing to watch
            return
        c = rows[:, 0:2]
        self._jump = first_jump(c, frames, self.config.motion_step_mm, self._last_centre)
        self._last_centre = c[-1].copy()

    def frame_at(self, i: int) -> int:
        """Frame number of the segment's ``i``-th frame (``i`` within the first frames kept)."""
        return int(self._head_rows()[0][i])

    def mean_axis_deg(self, stop: int | None = None) -> float:
        """Mean axis of the first ``stop`` frames (kept ones), or of all of them, deg."""
        if stop is None:
            if self.size == 0:
                return float("nan")
            s = self._axis_sum.total
            return float(0.5 * np.rad2deg(np.arctan2(s[1], s[0])))
        return mean_axis_deg(np.ascontiguousarray(self._head_rows()[1][:stop, 2]))

    def mean_centre_mm(self, stop: int) -> tuple[float, float]:
        """Mean centre of the first ``stop`` frames (kept ones), mm."""
        c = np.ascontiguousarray(self._head_rows()[1][:stop, 0:2]).mean(axis=0)
        return float(c[0]), float(c[1])

    def grid_wobble_deg(self, stop: int) -> float:
        """:func:`~taxelkit.smart.track_geometry.grid_wobble_deg` of the first ``stop`` frames."""
        return grid_wobble_deg(drawn_length_mm(self._head_rows()[1][:stop]), self.pitch_mm)

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
        room = max(0, cap - self._head_n)
        if room:
            stop = offset + room
            kept = frames[offset:stop]
            if kept.size:
                self._head.append((np.array(kept, np.intp), np.array(rows[offset:stop])))
                self._head_n += int(kept.size)

    def _cut_head(self, cap: int) -> None:
        """Keep no more than the first ``cap`` frames."""
        if self._head_n > cap:
            frames, rows = self._head_rows()
            self._head, self._head_n = [(frames[:cap].copy(), rows[:cap].copy())], cap
