"""Tracking contact regions over time: one track per object on the sensor.

:func:`~taxelkit.smart.regions.segment_frames` splits each frame into contact
regions; :class:`RegionTracker` links them from frame to frame. It sees only
the regions (their centroids, areas and taxels), never who made them.

Rules (:class:`TrackerConfig` holds the numbers)
    1. **Assignment.** The live tracks and the regions of a frame are paired
       by :func:`scipy.optimize.linear_sum_assignment` on the cost
       ``d + area_weight * |sqrt(A_track) - sqrt(A_region)|`` (mm), where ``d``
       is the distance from the track's last centroid to the region's
       centroid and ``A`` the areas in mm^2. A pair is never made when the
       region's nearest taxel is more than ``gate_pitches`` pitches from the
       nearest of the track's last taxels. The gate is on the taxels, not the centroids, because a
       contact moves continuously while its centroid can jump: a cube tipping
       from a face onto an edge, a cone laid down from its rim onto its side
       (the line starts where the point was).
    2. **Loss and death.** A track that gets no region stays alive, unseen,
       for up to ``lost_frames - 1`` frames and may be picked up again; on
       its ``lost_frames``-th unseen frame it **dies**. The recogniser sets
       ``lost_frames`` to the frames "no contact" must hold to be accepted
       (:func:`~taxelkit.smart.tactemes.debounce_counts`), so a track dies
       exactly when paper 001's pipeline would report "lifted": an object
       lifted off and put down again is a **new** track.
    3. **Birth.** A region that no track takes starts a new track.
    4. **Merge.** A track seen in the previous frame that gets no region,
       while a region taken by another track comes within ``touch_pitches``
       of its last taxels (default 1.5: the eight neighbours), has **merged**
       into that track. It stays alive, unseen, as rule 2 says.
    5. **Split.** A region that no track takes, within ``touch_pitches`` of
       the last taxels of a track that took another region, has **split**
       from it; a merged track that takes a region again has split from its
       host.

Every birth, death, merge and split is a :class:`TrackEvent` with its frame
and time. :func:`step` is the pure step of one frame; :class:`RegionTracker`
is a thin stateful wrapper that numbers the tracks.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError, check_positive

__all__ = [
    "TRACK_EVENT_KINDS",
    "LiveTrack",
    "RegionTracker",
    "TrackEvent",
    "TrackerConfig",
    "step",
]

#: Kinds of :class:`TrackEvent`.
TRACK_EVENT_KINDS = ("birth", "death", "merge", "split")
#: Default gate, pitches: a contact's taxels move less than this between sightings.
GATE_PITCHES = 3.0
#: Default distance at which two regions touch (merge, split), pitches: the eight neighbours.
TOUCH_PITCHES = 1.5
#: Default weight of the change of sqrt(area), mm per mm.
AREA_WEIGHT = 0.5
#: Cost of a forbidden pair (beyond the gate).
_FORBIDDEN = 1e12


def _region_taxels(
    labels: NDArray[np.int32], region_ids: NDArray[np.intp]
) -> list[NDArray[np.float64]]:
    """(row, column) of the taxels of each region, in the order of ``region_ids``."""
    on = np.flatnonzero(labels)
    if on.size == 0:
        return [np.empty((0, 2)) for _ in region_ids]
    lab = labels.reshape(-1)[on]
    order = np.argsort(lab, kind="stable")
    rc = np.column_stack(np.unravel_index(on[order], labels.shape)).astype(np.float64)
    ids, starts = np.unique(lab[order], return_index=True)
    groups = np.split(rc, starts[1:])
    where = np.searchsorted(ids, region_ids)
    return [groups[k] for k in where.tolist()]


def _nearest(tracks: list[LiveTrack], taxels: list[NDArray[np.float64]]) -> NDArray[np.float64]:
    """``(n, m)``: distance from each track's last taxels to each region's nearest, pitches."""
    mine = np.concatenate([tr.taxels for tr in tracks])
    every = np.concatenate(taxels)
    d2 = ((mine[:, None, :] - every[None, :, :]) ** 2).sum(axis=2)
    t_starts = np.cumsum([0] + [tr.taxels.shape[0] for tr in tracks[:-1]])
    r_starts = np.cumsum([0] + [t.shape[0] for t in taxels[:-1]])
    per_track = np.minimum.reduceat(d2, t_starts, axis=0)
    out: NDArray[np.float64] = np.sqrt(np.minimum.reduceat(per_track, r_starts, axis=1))
    return out


def _near_enough(
    tracks: list[LiveTrack],
    taxels: list[NDArray[np.float64]],
    labels: NDArray[np.int32],
    region_ids: NDArray[np.intp],
    beyond: float,
) -> NDArray[np.float64]:
    """:func:`_nearest` where it matters: exact up to ``beyond`` pitches, a bound above it.

    A track whose last taxels share one with a region is 0 from it; a pair
    whose bounding boxes lie more than ``beyond`` apart gets the boxes'
    distance (a lower bound, so every comparison with a distance up to
    ``beyond`` comes out as with the exact one); only the pairs left are
    measured taxel by taxel.
    """
    n = len(tracks)
    mine = np.concatenate([tr.taxels for tr in tracks])
    every = np.concatenate(taxels)
    t_starts = np.cumsum([0] + [tr.taxels.shape[0] for tr in tracks[:-1]])
    r_starts = np.cumsum([0] + [t.shape[0] for t in taxels[:-1]])
    lo_t, hi_t = np.minimum.reduceat(mine, t_starts), np.maximum.reduceat(mine, t_starts)
    lo_r, hi_r = np.minimum.reduceat(every, r_starts), np.maximum.reduceat(every, r_starts)
    gap = np.maximum(lo_r[None, :, :] - hi_t[:, None, :], lo_t[:, None, :] - hi_r[None, :, :])
    bound = np.hypot(*np.maximum(gap, 0.0).transpose(2, 0, 1))  # (n, m)
    on = labels[mine[:, 0].astype(np.intp), mine[:, 1].astype(np.intp)]
    order = np.argsort(region_ids)
    at = np.searchsorted(region_ids, on, sorter=order).clip(0, region_ids.size - 1)
    hit = region_ids[order[at]] == on
    owner = np.repeat(np.arange(n), np.diff(np.append(t_starts, mine.shape[0])))
    shared = np.zeros(bound.shape, bool)
    shared[owner[hit], order[at[hit]]] = True
    near: NDArray[np.float64] = np.where(shared, 0.0, bound)
    if np.any(~shared & (bound <= beyond)):
        near = np.where(shared | (bound > beyond), near, _nearest(tracks, taxels))
    return near


@dataclass(frozen=True)
class TrackerConfig:
    """Numbers of the tracker.

    Parameters
    ----------
    gate_pitches : float
        Largest distance from a track's last taxels to the nearest taxel of
        the region it takes, pitches.
    touch_pitches : float
        Distance within which a region touches a track's last taxels
        (merges and splits), pitches.
    area_weight : float
        Weight of the change of ``sqrt(area)`` in the assignment cost (mm per mm).
    """

    gate_pitches: float = GATE_PITCHES
    touch_pitches: float = TOUCH_PITCHES
    area_weight: float = AREA_WEIGHT

    def __post_init__(self) -> None:
        check_positive("gate_pitches", self.gate_pitches)
        check_positive("touch_pitches", self.touch_pitches)
        if not (math.isfinite(self.area_weight) and self.area_weight >= 0.0):
            raise InputError(f"area_weight must be >= 0, got {self.area_weight!r}")

    def gate_mm(self, pitch_mm: float) -> float:
        """The gate in mm on an array of pitch ``pitch_mm``."""
        return float(self.gate_pitches) * check_positive("pitch_mm", pitch_mm)


@dataclass(frozen=True)
class TrackEvent:
    """A birth, death, merge or split of a track.

    Attributes
    ----------
    kind : str
        One of :data:`TRACK_EVENT_KINDS`.
    track : int
        The track born, dead, merged (into ``other``) or split (from ``other``).
    frame : int
    t_s : float, s
    other : int or None
        The track merged into or split from.
    """

    kind: str
    track: int
    frame: int
    t_s: float
    other: int | None = None


@dataclass
class LiveTrack:
    """Mutable state of one live track."""

    track: int
    centre_mm: NDArray[np.float64]
    area_mm2: float
    taxels: NDArray[np.float64]  # (k, 2) row, column of its last region's taxels
    last_frame: int
    unseen: int = 0
    merged_into: int | None = None
    frames_seen: int = 1


def step(
    tracks: list[LiveTrack],
    labels: NDArray[np.int32],
    region_ids: NDArray[np.intp],
    centre_mm: NDArray[np.float64],
    area_mm2: NDArray[np.float64],
    *,
    frame: int,
    t_s: float,
    gate_pitches: float,
    touch_pitches: float,
    area_weight: float,
    lost_frames: int,
    next_id: int,
    taxels: list[NDArray[np.float64]] | None = None,
) -> tuple[list[LiveTrack], NDArray[np.intp], list[TrackEvent], int]:
    """Link the regions of one frame to the live tracks (rules in the module docstring).

    Parameters
    ----------
    tracks : list of LiveTrack
        Live tracks before this frame (updated in place and returned).
    labels : (rows, cols) int32
        The frame's region labels (0 off contact).
    region_ids : (m,) int
        The label of each region of the frame.
    centre_mm : (m, 2) float, mm
    area_mm2 : (m,) float, mm^2
    frame : int
    t_s : float, s
    gate_pitches, touch_pitches, area_weight : float
        As in :class:`TrackerConfig`.
    lost_frames : int
        Unseen frames at which a track dies.
    next_id : int
        Number of the next new track.
    taxels : list of (k, 2) float, optional
        (row, column) of each region's taxels, if known
        (:meth:`~taxelkit.smart.regions.Regions.taxels_of`); else read off ``labels``.

    Returns
    -------
    tracks : list of LiveTrack
        Live tracks after this frame.
    track_of_region : (m,) int
        The track of each region.
    events : list of TrackEvent
    next_id : int
    """
    m, n = int(region_ids.size), len(tracks)
    if m == 0 and n == 0:  # nothing on the array, nothing tracked
        return tracks, np.empty(0, np.intp), [], next_id
    track_of = np.full(m, -1, np.intp)
    got = np.full(n, -1, np.intp)  # region taken by each track
    if taxels is None:
        taxels = _region_taxels(labels, region_ids) if m else []
    near = np.full((n, m), np.inf)  # region's nearest taxel to each track's last taxels, pitches
    if m and n:
        near = _near_enough(tracks, taxels, labels, region_ids, max(gate_pitches, touch_pitches))
        prev = np.array([tr.centre_mm for tr in tracks])
        d = np.hypot(*(prev[:, None, :] - centre_mm[None, :, :]).transpose(2, 0, 1))
        root = np.sqrt(np.array([tr.area_mm2 for tr in tracks]))
        cost = d + area_weight * np.abs(root[:, None] - np.sqrt(area_mm2)[None, :])
        cost[near > gate_pitches] = _FORBIDDEN
        if m == 1 and n == 1:  # the usual case: one contact, one track
            rows, cols = np.zeros(1, np.intp), np.zeros(1, np.intp)
        else:  # imported here: scipy.optimize holds ~35 MB that one object never needs
            from scipy.optimize import linear_sum_assignment

            rows, cols = linear_sum_assignment(cost)
        ok = cost[rows, cols] < _FORBIDDEN
        got[rows[ok]] = cols[ok]
        track_of[cols[ok]] = rows[ok]
    touch = near <= touch_pitches
    events: list[TrackEvent] = []
    # rule 5 (a merged track seen again) and the update of the tracks that took a region
    for i, tr in enumerate(tracks):
        j = int(got[i])
        if j < 0:
            continue
        if tr.merged_into is not None:
            events.append(TrackEvent("split", tr.track, frame, t_s, tr.merged_into))
            tr.merged_into = None
        tr.centre_mm = centre_mm[j].copy()
        tr.area_mm2 = float(area_mm2[j])
        tr.taxels = taxels[j]
        tr.last_frame = frame
        tr.unseen = 0
        tr.frames_seen += 1
    # rules 3 and 5: regions nobody took
    new: list[LiveTrack] = []
    for j in np.flatnonzero(track_of < 0).tolist():
        parent = next((i for i in range(n) if got[i] >= 0 and touch[i, j]), None)
        tid = next_id
        next_id += 1
        if parent is None:
            events.append(TrackEvent("birth", tid, frame, t_s))
        else:
            events.append(TrackEvent("split", tid, frame, t_s, tracks[parent].track))
        track_of[j] = n + len(new)
        new.append(
            LiveTrack(
                tid,
                centre_mm[j].copy(),
                float(area_mm2[j]),
                taxels[j],
                frame,
            )
        )
    # rules 4 and 2: tracks that took nothing
    kept: list[LiveTrack] = []
    for i, tr in enumerate(tracks):
        if got[i] < 0:
            if tr.unseen == 0 and tr.merged_into is None:
                host = next(
                    (tracks[k].track for k in range(n) if got[k] >= 0 and touch[i, int(got[k])]),
                    None,
                )
                if host is not None:
                    tr.merged_into = host
                    events.append(TrackEvent("merge", tr.track, frame, t_s, host))
            tr.unseen += 1
            if tr.unseen >= lost_frames:
                events.append(TrackEvent("death", tr.track, frame, t_s))
                continue
        kept.append(tr)
    all_tracks = tracks + new
    ids = np.array([all_tracks[int(k)].track for k in track_of], dtype=np.intp)
    return kept + new, ids, events, next_id


class RegionTracker:
    """Tracks of the regions of a stream of frames (a thin wrapper around :func:`step`).

    Parameters
    ----------
    pitch_mm : float
    lost_frames : int
        Unseen frames at which a track dies (>= 1).
    config : TrackerConfig, optional
    """

    def __init__(
        self, *, pitch_mm: float, lost_frames: int, config: TrackerConfig | None = None
    ) -> None:
        self.config = TrackerConfig() if config is None else config
        self.pitch_mm = check_positive("pitch_mm", pitch_mm)
        if int(lost_frames) < 1:
            raise InputError(f"lost_frames must be >= 1, got {lost_frames!r}")
        self.lost_frames = int(lost_frames)
        self.tracks: list[LiveTrack] = []
        self.next_id = 0

    def push(
        self,
        frame: int,
        t_s: float,
        labels: NDArray[np.int32],
        region_ids: NDArray[np.intp],
        centre_mm: NDArray[np.float64],
        area_mm2: NDArray[np.float64],
        taxels: list[NDArray[np.float64]] | None = None,
    ) -> tuple[NDArray[np.intp], list[TrackEvent]]:
        """Link one frame's regions; return the track of each region and the events."""
        self.tracks, ids, events, self.next_id = step(
            self.tracks,
            labels,
            region_ids,
            centre_mm,
            area_mm2,
            frame=frame,
            t_s=t_s,
            gate_pitches=self.config.gate_pitches,
            touch_pitches=self.config.touch_pitches,
            area_weight=self.config.area_weight,
            lost_frames=self.lost_frames,
            next_id=self.next_id,
            taxels=taxels,
        )
        return ids, events

    def alive(self) -> list[int]:
        """Numbers of the live tracks."""
        return [tr.track for tr in self.tracks]
