"""Several objects at once: Levels 2-4 per tracked contact region, batch and streaming.

The frames are thresholded and cleaned as one image (paper 001's Level 0 and
:mod:`taxelkit.smart.cleaning`), split into contact regions
(:mod:`taxelkit.smart.regions`) and tracked (:mod:`taxelkit.smart.tracks`).
Each track then runs its own Levels 1-4 on its own masked image sequence (the
cleaned frames with every taxel of the other tracks off), through the
existing :class:`~taxelkit.smart.recognise_chunks.ChunkRecogniser` with the
cleaning switched off (it was done once, on the whole frame). A track's
recogniser is fed from the frame before the track's birth (an empty frame)
until the frame of its death, so for one object on the sensor the events and
verdict are those of :func:`~taxelkit.smart.recogniser.recognise` (on
uniformly spaced timestamps; tested), and an object lifted and put down again
gives two tracks, each with its own verdict.

:class:`ObjectRecogniser` takes frames a chunk at a time and returns the
per-track events as they are found; :func:`recognise_objects` is the batch
path (one chunk). Both give the same :class:`ObjectRecognition` (tested).

Known limits: the cleaning's stray rule drops a contact of a single taxel
while another contact is on the array (rule 4 of
:mod:`taxelkit.smart.cleaning`); two objects whose contacts touch are one
region (a merge) until they part, and the track that keeps the merged region
sees both.
"""

from __future__ import annotations

import bisect
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive, check_shape, check_threshold
from taxelkit.frames import TactileFrames
from taxelkit.smart.cleaning import CleaningConfig
from taxelkit.smart.cleaning_chunks import ChunkCleaner
from taxelkit.smart.contact_classes import DEFAULT_CONFIDENCE, HAND_SET, ContactNetwork
from taxelkit.smart.contact_limits import ContactLimits
from taxelkit.smart.elimination import Event
from taxelkit.smart.levels12 import DEFAULT_CLEANING, DEFAULT_LIMITS, DEFAULT_THRESHOLD_MM
from taxelkit.smart.object_results import (
    ObjectRecognition,
    ObjectVerdict,
    TrackedEvent,
    TrackSlip,
    interleaved,
)
from taxelkit.smart.recognise_chunks import ChunkRecogniser
from taxelkit.smart.regions import RegionConfig, segment_frames
from taxelkit.smart.slip import Slip
from taxelkit.smart.stream_state import check_chunk
from taxelkit.smart.tactemes import TactemeConfig, debounce_counts
from taxelkit.smart.tracks import RegionTracker, TrackerConfig
from taxelkit.smart.tracks_batch import track_chunk

__all__ = [
    "ObjectRecogniser",
    "ObjectRecognition",
    "ObjectVerdict",
    "TrackSlip",
    "TrackedEvent",
    "recognise_objects",
]


#: Frames of a chunk segmented, tracked and recognised together (bounds the
#: temporaries: per frame a region label map of 4 bytes a taxel and a few more).
PIECE_FRAMES = 4096


@dataclass
class _Live:
    """A track's own recogniser and where its frames start."""

    recogniser: ChunkRecogniser
    start: int  # global frame of the recogniser's frame 0
    first: int
    last: int
    events: list[TrackedEvent] = field(default_factory=list)


class ObjectRecogniser:
    """Levels 1-4 per tracked contact region, fed one chunk of frames at a time.

    Parameters
    ----------
    shape : (rows, cols)
    pitch_mm : float
    threshold, network, confidence, config, cleaning, limits
        As in :func:`~taxelkit.smart.recogniser.recognise`.
    regions : RegionConfig, optional
        Segmentation.
    tracker : TrackerConfig, optional
        Tracking.
    keep_map : bool
        Keep every frame's track map (``int16`` per taxel, -1 off contact)
        for :attr:`ObjectRecognition.track_map` (experiments score tracks
        with it); memory then grows with the stream.

    Notes
    -----
    A chunk is processed :data:`PIECE_FRAMES` frames at a time, cleaning
    included (the same events as in one piece), so its temporaries stay
    bounded whatever the chunk's length. The timestamps are kept from the first frame of the
    oldest live track on (8 bytes a frame), to give each event its time;
    every track's verdict is kept for :meth:`result`.
    """

    def __init__(
        self,
        shape: tuple[int, int],
        *,
        pitch_mm: float,
        threshold: float | None = None,
        network: ContactNetwork = HAND_SET,
        confidence: float = DEFAULT_CONFIDENCE,
        config: TactemeConfig | None = None,
        cleaning: CleaningConfig | None = DEFAULT_CLEANING,
        limits: ContactLimits | None = DEFAULT_LIMITS,
        regions: RegionConfig | None = None,
        tracker: TrackerConfig | None = None,
        keep_map: bool = False,
    ) -> None:
        rows, cols = check_shape("shape", shape)
        self.shape = (rows, cols)
        self.pitch_mm = check_positive("pitch_mm", pitch_mm)
        self.threshold = (
            DEFAULT_THRESHOLD_MM if threshold is None else check_threshold("threshold", threshold)
        )
        self.config = TactemeConfig() if config is None else config
        self.regions = RegionConfig() if regions is None else regions
        self.tracker_config = TrackerConfig() if tracker is None else tracker
        self._options: dict[str, Any] = {
            "network": network,
            "confidence": confidence,
            "config": self.config,
            "limits": limits,
        }
        self._cleaner = None if cleaning is None else ChunkCleaner(1, self.shape, config=cleaning)
        self._tracker: RegionTracker | None = None
        self._pending: list[tuple[NDArray[np.bool_], NDArray[np.float64]]] = []
        self._t: list[NDArray[np.float64]] = []  # timestamps of each chunk processed
        self._offsets: list[int] = []  # first frame of each chunk processed
        self._track_log: list[TrackedEvent] = []
        self._n = 0
        self._live: dict[int, _Live] = {}
        self._done: list[ObjectVerdict] = []
        self._done_events: list[TrackedEvent] = []
        self._t_last = -np.inf
        self.keep_map = bool(keep_map)
        self._maps: list[NDArray[np.int16]] = []

    def _t_of(self, frame: int) -> float:
        k = bisect.bisect_right(self._offsets, frame) - 1
        return float(self._t[k][frame - self._offsets[k]])

    def push(self, frames: ArrayLike, t_s: ArrayLike) -> list[TrackedEvent]:
        """Track and recognise the next chunk of frames.

        Parameters
        ----------
        frames : (n, rows, cols) bool or float
        t_s : (n,) float, s
            Strictly increasing across chunks.

        Returns
        -------
        list of TrackedEvent
            The events found in this chunk, in order.
        """
        f, t = check_chunk(frames, t_s, self.shape, self._t_last)
        if f.shape[0] == 0:
            return []
        if f.shape[0] > PIECE_FRAMES:  # a piece at a time, cleaning included: the same events
            found: list[TrackedEvent] = []
            for a in range(0, f.shape[0], PIECE_FRAMES):
                found.extend(self.push(f[a : a + PIECE_FRAMES], t[a : a + PIECE_FRAMES]))
            return found
        self._t_last = float(t[-1])
        images = f.astype(bool) if f.dtype == bool else f.astype(np.float64) > self.threshold
        if self._cleaner is not None:
            images = self._cleaner.push(images[None], t[None])[0]
        self._pending.append((images, t))
        if self._tracker is None:
            if sum(p[1].size for p in self._pending) < 2:
                return []  # the frame interval (and so the track's lifetime) is not known yet
            first = np.concatenate([p[1] for p in self._pending])
            _, k_none = debounce_counts(self.config, float(first[1] - first[0]))
            self._tracker = RegionTracker(
                pitch_mm=self.pitch_mm, lost_frames=k_none, config=self.tracker_config
            )
        pending, self._pending = self._pending, []
        images = np.concatenate([p[0] for p in pending]) if len(pending) > 1 else pending[0][0]
        t = np.concatenate([p[1] for p in pending]) if len(pending) > 1 else pending[0][1]
        return self._process(images, t)

    def _process(self, images: NDArray[np.bool_], t: NDArray[np.float64]) -> list[TrackedEvent]:
        assert self._tracker is not None
        n0 = self._n
        self._t.append(t)
        self._offsets.append(n0)
        self._n += t.size
        reg = segment_frames(images, pitch_mm=self.pitch_mm, config=self.regions)
        lut = np.full(reg.n_regions + 1, -1, np.int32)
        track_of, events = track_chunk(self._tracker, reg, t, first_frame=n0)
        lut[1:] = track_of
        starts: dict[int, int] = {}  # track -> first chunk frame (tracks new here)
        ids, first = np.unique(track_of, return_index=True)
        for tid, r in zip(ids.tolist(), first.tolist(), strict=True):
            if tid not in self._live:
                starts[tid] = int(reg.frame[r])
        found: list[TrackedEvent] = []
        ends: dict[int, int] = {}  # track -> last chunk frame to feed (its death)
        for e in events:
            tracked = TrackedEvent(e.track, e.kind, e.frame, e.t_s, e.other)
            found.append(tracked)
            self._track_log.append(tracked)
            if e.kind == "death":
                ends[e.track] = e.frame - n0
        pix = lut[reg.labels]
        if self.keep_map:
            self._maps.append(pix.astype(np.int16))
        tracks_here = sorted(set(self._live) | set(starts))
        for tid in tracks_here:
            if tid in starts:
                self._start_track(tid, n0 + starts[tid], images, t, starts[tid])
            live = self._live[tid]
            a = starts.get(tid, 0)
            b = ends.get(tid, t.size - 1)
            mine = pix[a : b + 1] == tid
            seen = np.flatnonzero(mine.reshape(b + 1 - a, -1).any(axis=1))
            if seen.size:
                live.last = n0 + a + int(seen[-1])
            emitted = live.recogniser.push(mine, t[a : b + 1])
            new = [self._tracked(tid, live, e) for e in emitted]
            live.events.extend(new)
            found.extend(new)
            if tid in ends:
                self._finish(tid)
        self._forget_times()
        return found

    def _forget_times(self) -> None:
        """Drop the timestamps of pieces before every live track's first frame.

        The last piece stays (a track born on the next piece's first frame
        starts from the frame before); a track held on the array keeps those
        since its start.
        """
        oldest = min((live.start for live in self._live.values()), default=self._n)
        drop = 0
        while drop + 1 < len(self._offsets) and self._offsets[drop + 1] <= oldest:
            drop += 1
        if drop:
            del self._t[:drop], self._offsets[:drop]

    def _start_track(
        self, tid: int, birth: int, images: NDArray[np.bool_], t: NDArray[np.float64], i: int
    ) -> None:
        rec = ChunkRecogniser(self.shape, pitch_mm=self.pitch_mm, cleaning=None, **self._options)
        start = birth
        if birth > 0:  # an empty frame before the birth, as the whole recording would have
            t_before = float(t[i - 1]) if i > 0 else self._t_of(birth - 1)
            rec.push(np.zeros((1, *self.shape), bool), np.array([t_before]))
            start = birth - 1
        self._live[tid] = _Live(rec, start, birth, birth)

    def _tracked(self, tid: int, live: _Live, e: Event) -> TrackedEvent:
        frame = live.start + e.frame
        return TrackedEvent(tid, e.kind, frame, self._t_of(frame), e.value)

    def _finish(self, tid: int) -> None:
        live = self._live.pop(tid)
        res = live.recogniser.result()
        self._done.append(
            ObjectVerdict(
                track=tid,
                first_frame=live.first,
                last_frame=live.last,
                first_t_s=self._t_of(live.first),
                last_t_s=self._t_of(live.last),
                identified=res.identified,
                candidates=res.candidates,
                verdict=res.verdict,
                tactemes=tuple(
                    (n, live.start + f, self._t_of(live.start + f)) for n, f in res.tactemes
                ),
                accepted=any(e.kind == "contact" for e in res.events),
                slips=tuple(self._track_slip(live.start, sl) for sl in res.slips),
            )
        )
        self._done_events.extend(live.events)

    def _track_slip(self, start: int, sl: Slip) -> TrackSlip:
        last = None if sl.last_frame is None else start + sl.last_frame
        return TrackSlip(
            kind=sl.kind,
            first_frame=start + sl.first_frame,
            detected_frame=start + sl.detected_frame,
            last_frame=last,
            t_start_s=self._t_of(start + sl.first_frame),
            t_detected_s=self._t_of(start + sl.detected_frame),
            t_end_s=None if last is None else self._t_of(last),
        )

    def result(self) -> ObjectRecognition:
        """Every track's verdict so far (live tracks: their verdict up to now)."""
        if self._pending and self._tracker is None:  # a single frame: track it with k frames
            self._tracker = RegionTracker(
                pitch_mm=self.pitch_mm,
                lost_frames=debounce_counts(self.config, None)[1],
                config=self.tracker_config,
            )
            pending, self._pending = self._pending, []
            self._process(np.concatenate([p[0] for p in pending]), pending[0][1])
        done, done_events = list(self._done), list(self._done_events)
        live_ids = list(self._live)
        for tid in live_ids:  # finish copies: the live recognisers go on
            keep = self._live[tid]
            self._finish(tid)
            self._live[tid] = keep
        objects = sorted(self._done, key=lambda o: o.track)
        events = interleaved(self._done_events, self._track_log)
        self._done, self._done_events = done, done_events
        track_map = None
        if self.keep_map:
            track_map = (
                np.concatenate(self._maps) if self._maps else np.empty((0, *self.shape), np.int16)
            )
        return ObjectRecognition(tuple(objects), tuple(events), self._n, track_map)


def recognise_objects(
    recording: TactileFrames | ArrayLike,
    *,
    pitch_mm: float | None = None,
    **options: Any,
) -> ObjectRecognition:
    """Recognise every object on the sensor in a recording (batch: one chunk).

    Parameters
    ----------
    recording : TactileFrames or (T, rows, cols) array
    pitch_mm : float, optional
        Overrides the recording's pitch (required for a bare array).
    **options
        Of :class:`ObjectRecogniser`.

    Returns
    -------
    ObjectRecognition
    """
    if isinstance(recording, TactileFrames):
        frames = recording.frames
        t_s = np.asarray(recording.t_s, dtype=np.float64)
        pitch = recording.pitch_mm if pitch_mm is None else pitch_mm
    else:
        frames = np.asarray(recording)
        if frames.ndim != 3:
            raise InputError(f"recording must have shape (T, rows, cols), got {frames.shape}")
        if pitch_mm is None:
            raise InputError("pitch_mm is required when recording is a bare array")
        from taxelkit.frames import DEFAULT_FRAME_INTERVAL_S

        t_s = np.arange(frames.shape[0], dtype=np.float64) * DEFAULT_FRAME_INTERVAL_S
        pitch = pitch_mm
    rec = ObjectRecogniser((frames.shape[1], frames.shape[2]), pitch_mm=pitch, **options)
    rec.push(frames, t_s)
    return rec.result()
