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
from taxelkit.smart.tactemes import (
    SegmentTrack,
    TactemeConfig,
    frames_for_interval,
    segment_tactemes,
)
from taxelkit.smart.tactemes_batch import batch_tactemes
from taxelkit.smart.track_geometry import drawn_half_mm, first_jump, grid_wobble_deg

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
    axis_sums : (n, 2) or (n, 4) float, optional
        Running sums of the doubled-angle axis vectors ``cos 2 theta, sin 2
        theta`` (``np.cumsum`` along the track), for :meth:`mean_axis_deg`;
        with four columns, then those of the centre ``x, y`` (mm), for
        :meth:`mean_centre_mm`.
    line_mm : (n,) float, optional
        Drawn length of each frame's line, mm (``2 drawn_half_mm``), for
        :meth:`grid_wobble_deg`.
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
        line_mm: NDArray[np.float64] | None = None,
    ) -> None:
        self.track = track
        self._config = config
        self._jump: int | None = None  # jump_frame(), once computed
        self._jump_known = False
        self._axis_sums = axis_sums
        self._line_mm = line_mm
        self._dt: dict[int, float] = {}  # frame interval by k, s (fixed once accepted)
        self.size = int(track.frames.size)
        self.first_frame = int(track.frames[0])
        self.last_frame = int(track.frames[-1])
        self._found = segment_tactemes(cls, track, config) if found is None else found
        self._slip: SlipScanner | None = None
        if config.slip is not None:
            self._slip = slip
            if slip is None:
                self._slip = SlipScanner(
                    cls, config.slip, k=int(config.debounce_frames), pitch_mm=track.pitch_mm
                )
                self._slip.extend(track.frames, rows_from_track(track))

    def frames_for(self, seconds: float, k: int, *, minimum: int | None = None) -> int:
        return frames_for_interval(
            self.frame_interval_s(k), seconds, k if minimum is None else minimum
        )

    def frame_interval_s(self, k: int) -> float:
        dt = self._dt.get(k)
        if dt is None:
            dt = self._dt[k] = self.track.frame_interval_s(k)
        return dt

    def jump_frame(self) -> int | None:
        """First frame the contact jumped to between sparse frames (``SegmentHead.jump_frame``)."""
        if not self._jump_known:  # computed once: the whole track is known
            self._jump_known = True
            cfg = self._config
            gap = cfg.max_motion_gap_s
            sparse = gap > 0.0 and self.frame_interval_s(cfg.debounce_frames) > gap
            t = self.track
            self._jump = first_jump(t.centre_mm, t.frames, cfg.motion_step_mm) if sparse else None
        return self._jump

    @property
    def pitch_mm(self) -> float:
        """The track's taxel pitch, mm (0: unknown)."""
        return float(self.track.pitch_mm)

    def frame_at(self, i: int) -> int:
        return int(self.track.frames[i])

    def mean_axis_deg(self, stop: int | None = None) -> float:
        if self._axis_sums is None:
            return mean_axis_deg(self.track.orientation_deg[:stop])
        n = len(range(self.size)[:stop])  # the frames that track.orientation_deg[:stop] holds
        if n == 0:
            return float("nan")
        sx, sy = self._axis_sums[n - 1, :2]  # mean_axis_deg's sums: the same floats
        return float(0.5 * np.rad2deg(np.arctan2(sy, sx)))

    def mean_centre_mm(self, stop: int) -> tuple[float, float]:
        n = len(range(self.size)[:stop])
        if self._axis_sums is None or self._axis_sums.shape[1] < 4 or n == 0:
            c = self.track.centre_mm[:stop].mean(axis=0)
            return float(c[0]), float(c[1])
        sums = self._axis_sums[n - 1]  # the sums of the mean along axis 0: the same floats
        return float(sums[2] / n), float(sums[3] / n)

    def grid_wobble_deg(self, stop: int) -> float:
        t = self.track
        if self._line_mm is not None:
            return grid_wobble_deg(self._line_mm[:stop], t.pitch_mm)
        ext = None if t.extent_mm is None else t.extent_mm[:stop]
        return grid_wobble_deg(2.0 * drawn_half_mm(t.half_length_mm[:stop], ext), t.pitch_mm)

    def tactemes(self) -> list[tuple[Tacteme, int]]:
        return self._found

    def slips(self) -> list[Slip]:
        return [] if self._slip is None else self._slip.all_slips()

    def close_slips(self) -> list[Slip]:
        return [] if self._slip is None else self._slip.close()


def track_segments(
    items: Sequence[tuple[int, SegmentTrack, NDArray[np.float64] | None]],
    config: TactemeConfig,
    *,
    known: dict[tuple[int, bytes], list[tuple[Tacteme, int]]] | None = None,
) -> list[TrackSegment]:
    """:class:`TrackSegment` of many whole segments, their Level 3 computed together.

    Parameters
    ----------
    items : sequence of (int, SegmentTrack, (n, 9) float or None)
        Each segment's class, track and its per-frame rows
        (:data:`~taxelkit.smart.segment_scan.ROW_COLUMNS`; None: from the track).
    config : TactemeConfig
    known : dict, optional
        Motion tactemes computed already (elsewhere, by
        :func:`~taxelkit.smart.tactemes_batch.batch_tactemes` of the same
        class, frames, rows and configuration), by ``(class,
        track.frames.tobytes())``: an item's are taken (popped) from it, the
        others computed here.

    Returns
    -------
    list of TrackSegment
        The same as ``TrackSegment(cls, track, config)`` of each item.
    """
    found: list[list[tuple[Tacteme, int]] | None] = [None] * len(items)
    if known:
        found = [known.pop((cls, track.frames.tobytes()), None) for cls, track, _ in items]
    todo = [i for i, f in enumerate(found) if f is None]
    for i, f in zip(todo, batch_tactemes([items[i][:2] for i in todo], config), strict=True):
        found[i] = f
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
                pitch_mm=[float(track.pitch_mm) for _, track, _ in items],
            )
        )
    tracks = [track for _, track, _ in items]
    sums, lines = _axis_sums(tracks), _line_lengths(tracks)
    return [
        TrackSegment(cls, track, config, found=f, slip=sl, axis_sums=a, line_mm=m)
        for (cls, track, _), f, sl, a, m in zip(items, found, slips, sums, lines, strict=True)
    ]


def _axis_sums(tracks: list[SegmentTrack]) -> list[NDArray[np.float64]]:
    """Running sums of each track's doubled-angle axis vectors and centres ``(n, 4)``.

    Columns ``cos 2 theta, sin 2 theta`` (as ``mean_axis_deg``), then the
    centre ``x, y`` in mm (as the mean of the centres along axis 0).
    """
    if not tracks:
        return []
    runs = Runs(np.array([t.frames.size for t in tracks], dtype=np.intp))
    t = np.deg2rad(2.0 * np.concatenate([tr.orientation_deg for tr in tracks]))
    vectors = np.empty((t.size, 4))
    vectors[:, 0], vectors[:, 1] = np.cos(t), np.sin(t)
    vectors[:, 2:4] = np.concatenate([tr.centre_mm for tr in tracks])
    sums = runs.cumsum(vectors)
    ends = (runs.starts + runs.lengths).tolist()
    return [sums[a:b] for a, b in zip(runs.starts.tolist(), ends, strict=True)]


def _line_lengths(tracks: list[SegmentTrack]) -> list[NDArray[np.float64] | None]:
    """Each track's drawn line lengths ``2 drawn_half_mm`` ``(n,)``, mm, element-wise at once.

    Tracks that measure no extents (None) are left to compute their own (None).
    """
    out: list[NDArray[np.float64] | None] = [None] * len(tracks)
    measured = [i for i, t in enumerate(tracks) if t.extent_mm is not None]
    if not measured:
        return out
    half = np.concatenate([tracks[i].half_length_mm for i in measured])
    ext = np.concatenate([tracks[i].extent_mm for i in measured])
    line = 2.0 * drawn_half_mm(half, ext)
    a = 0
    for i in measured:
        b = a + tracks[i].frames.size
        out[i] = line[a:b]
        a = b
    return out
