"""Whole contact segments as Levels 3-4 see them (the batch paths), their Level 3 at once.

:class:`TrackSegment` shows a segment's whole track through the
:class:`~taxelkit.smart.levels34.Segment` interface; :func:`track_segments`
builds many of them with their motion tactemes
(:func:`~taxelkit.smart.tactemes_batch.batch_tactemes`), slip scanners
(:func:`~taxelkit.smart.slip_batch.batch_slip_scanners`) and mean axes
computed together.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.segment_runs import Runs
from taxelkit.smart.segment_scan import mean_axis_deg, rows_from_track
from taxelkit.smart.slip import Slip
from taxelkit.smart.slip_batch import batch_slip_scanners
from taxelkit.smart.slip_scan import SlipScanner
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.tactemes import SegmentTrack, TactemeConfig, segment_tactemes
from taxelkit.smart.tactemes_batch import batch_tactemes
from taxelkit.smart.track_geometry import drawn_half_mm, grid_wobble_deg

__all__ = ["TrackSegment", "track_segments"]


class TrackSegment:
    """A whole segment's track as a :class:`Segment` (the batch path).

    Parameters
    ----------
    cls : int
    track : SegmentTrack
    config : TactemeConfig
    found : list of (Tacteme, frame), optional
        Its motion tactemes, when already computed (``segment_tactemes``, or
        :func:`~taxelkit.smart.tactemes_batch.batch_tactemes` for many segments).
    slip : SlipScanner, optional
        Its slip scanner fed the whole track, when already computed
        (:func:`~taxelkit.smart.slip_batch.batch_slip_scanners`); only read
        when ``config.slip`` is set.
    axis_sums : (n, 2) float, optional
        Running sums of the doubled-angle axis vectors ``cos 2 theta, sin 2
        theta`` (``np.cumsum`` along the track), for :meth:`mean_axis_deg`.
    """

    def __init__(
        self,
        cls: int,
        track: SegmentTrack,
        config: TactemeConfig,
        *,
        found: list[tuple[Tacteme, int]] | None = None,
        slip: SlipScanner | None = None,
        axis_sums: NDArray[np.float64] | None = None,
    ) -> None:
        self.track = track
        self._axis_sums = axis_sums
        self.size = int(track.frames.size)
        self.first_frame = int(track.frames[0])
        self.last_frame = int(track.frames[-1])
        self._found = segment_tactemes(cls, track, config) if found is None else found
        self._slip: SlipScanner | None = None
        if config.slip is not None:
            self._slip = slip
            if slip is None:
                self._slip = SlipScanner(cls, config.slip, k=int(config.debounce_frames))
                self._slip.extend(track.frames, rows_from_track(track))

    def frames_for(self, seconds: float, k: int, *, minimum: int | None = None) -> int:
        return self.track.frames_for(seconds, k, minimum=minimum)

    def frame_at(self, i: int) -> int:
        return int(self.track.frames[i])

    def mean_axis_deg(self, stop: int | None = None) -> float:
        if self._axis_sums is None:
            return mean_axis_deg(self.track.orientation_deg[:stop])
        n = len(range(self.size)[:stop])  # the frames that track.orientation_deg[:stop] holds
        if n == 0:
            return float("nan")
        sx, sy = self._axis_sums[n - 1]  # mean_axis_deg's sums: the same floats
        return float(0.5 * np.rad2deg(np.arctan2(sy, sx)))

    def mean_centre_mm(self, stop: int) -> tuple[float, float]:
        c = self.track.centre_mm[:stop].mean(axis=0)
        return float(c[0]), float(c[1])

    def grid_wobble_deg(self, stop: int) -> float:
        t = self.track
        ext = None if t.extent_mm is None else t.extent_mm[:stop]
        return grid_wobble_deg(2.0 * drawn_half_mm(t.half_length_mm[:stop], ext), t.pitch_mm)

    def tactemes(self) -> list[tuple[Tacteme, int]]:
        return self._found

    def slips(self) -> list[Slip]:
        return [] if self._slip is None else self._slip.all_slips()

    def close_slips(self) -> list[Slip]:
        return [] if self._slip is None else self._slip.close()


def track_segments(
    items: Sequence[tuple[int, SegmentTrack, NDArray[np.float64] | None]], config: TactemeConfig
) -> list[TrackSegment]:
    """:class:`TrackSegment` of many whole segments, their Level 3 computed together.

    Parameters
    ----------
    items : sequence of (int, SegmentTrack, (n, 9) float or None)
        Each segment's class, track and its per-frame rows
        (:data:`~taxelkit.smart.segment_scan.ROW_COLUMNS`; None: from the track).
    config : TactemeConfig

    Returns
    -------
    list of TrackSegment
        The same as ``TrackSegment(cls, track, config)`` of each item.
    """
    found = batch_tactemes([(cls, track) for cls, track, _ in items], config)
    slips: list[SlipScanner | None] = [None] * len(items)
    if config.slip is not None:
        slips = list(
            batch_slip_scanners(
                [
                    (cls, track.frames, rows_from_track(track) if rows is None else rows)
                    for cls, track, rows in items
                ],
                config.slip,
                k=int(config.debounce_frames),
            )
        )
    sums = _axis_sums([track for _, track, _ in items])
    return [
        TrackSegment(cls, track, config, found=f, slip=sl, axis_sums=a)
        for (cls, track, _), f, sl, a in zip(items, found, slips, sums, strict=True)
    ]


def _axis_sums(tracks: list[SegmentTrack]) -> list[NDArray[np.float64]]:
    """Running sums of each track's doubled-angle axis vectors (as ``mean_axis_deg``)."""
    if not tracks:
        return []
    runs = Runs(np.array([t.frames.size for t in tracks], dtype=np.intp))
    t = np.deg2rad(2.0 * np.concatenate([tr.orientation_deg for tr in tracks]))
    vectors = np.empty((t.size, 2))
    vectors[:, 0], vectors[:, 1] = np.cos(t), np.sin(t)
    sums = runs.cumsum(vectors)
    ends = (runs.starts + runs.lengths).tolist()
    return [sums[a:b] for a, b in zip(runs.starts.tolist(), ends, strict=True)]
