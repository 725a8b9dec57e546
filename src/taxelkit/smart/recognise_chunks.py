"""The batch recogniser driven a chunk at a time: recordings larger than memory.

:func:`~taxelkit.smart.recogniser.recognise` holds a whole recording and its
per-frame statistics. :class:`ChunkRecogniser` takes the same frames in
consecutive chunks and carries, from chunk to chunk, only

* the cleaning state (:class:`~taxelkit.smart.cleaning_chunks.ChunkCleaner`),
* the Level 2 limits' hysteresis (:class:`~taxelkit.smart.contact_limits.LimitState`),
* the debounce: the accepted class, the frames of a candidate class not yet
  seen ``k`` times (fewer than ``k``), and the Level 1 statistics of the open
  contact segment (56 bytes per frame of that contact: a held contact of
  10 minutes at 240 frames/s is 8 MB),
* Levels 3-4 (the same object the batch path uses), which sees every accepted
  segment whole, exactly as in the batch path,
* the per-frame classes as run-length :class:`ClassSegments`.

Each accepted segment is handed to Levels 3-4 once the next one is accepted
(or the recording ends), which is when the batch path's segment is complete
too, so the events, tactemes and verdict are those of
:func:`~taxelkit.smart.recogniser.recognise` for any chunking (tested).
Memory is bounded by the chunk size plus the longest contact, not by the
recording.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive, check_shape, check_threshold
from taxelkit.frames import TactileFrames
from taxelkit.smart.class_segments import (
    ChunkRecognition,
    ClassSegments,
    class_segments,
    joined_segments,
)
from taxelkit.smart.cleaning import CleaningConfig
from taxelkit.smart.cleaning_chunks import ChunkCleaner
from taxelkit.smart.contact_classes import (
    DEFAULT_CONFIDENCE,
    HAND_SET,
    ContactClass,
    ContactNetwork,
    classify_contacts,
)
from taxelkit.smart.contact_limits import ContactLimits, LimitState, apply_limits
from taxelkit.smart.elimination import Event
from taxelkit.smart.moments import binary_images, image_stats
from taxelkit.smart.recogniser import (
    _DEFAULT_THRESHOLD_MM,
    DEFAULT_CLEANING,
    DEFAULT_LIMITS,
    _finish,
    _half_length,
    _Levels34,
)
from taxelkit.smart.tactemes import SegmentTrack, TactemeConfig, debounce_counts

__all__ = [
    "ChunkRecogniser",
    "ChunkRecognition",
    "ClassSegments",
    "class_segments",
    "recognise_chunks",
]

_NONE = int(ContactClass.NONE)
_INDET = int(ContactClass.INDETERMINATE)
#: Streaming: the open segment is looked at again when it has grown by this
#: many frames, or by 1/:data:`_REVIEW_FRACTION` of its length if that is more
#: (as ``SmartSensor(evaluate_every=16)``; each look costs time proportional
#: to the segment's length, so this keeps the cost per frame constant).
_REVIEW_FRAMES = 16
_REVIEW_FRACTION = 32
#: Streaming: events kept before those of old contacts are dropped.
_EVENTS_KEPT = 1024
#: Columns of a contact frame's Level 1 row: centre x, y (mm), orientation
#: (deg), area (mm^2), elongation, half length (mm), time (s).
_ROW_FIELDS = 7


class ChunkRecogniser:
    """:func:`~taxelkit.smart.recogniser.recognise`, fed one chunk of frames at a time.

    Parameters
    ----------
    shape : (rows, cols)
        Frame shape.
    pitch_mm : float
        Taxel pitch, mm.
    threshold, network, confidence, config, cleaning, limits
        As in :func:`~taxelkit.smart.recogniser.recognise`.
    per_frame : bool
        Also keep the per-frame classes (1 byte per frame).
    streaming : bool
        Hand the open segment to Levels 3-4 as it grows, as
        :class:`~taxelkit.smart.recogniser.SmartSensor` does (when it has
        grown by 16 frames, or by 1/32 of its length if that is more), so
        that :meth:`push` returns events as they happen rather than when
        their segment ends; the class segments are then kept for the last
        chunk only, and :meth:`result` reports the events of the last
        contacts only, so memory does not grow with the stream. The events
        and their frame numbers are the same either way (detection is causal).

    Examples
    --------
    >>> frames = np.zeros((40, 16, 16), bool); frames[5:30, 7:9, 7:9] = True
    >>> rec = ChunkRecogniser((16, 16), pitch_mm=1.7625)
    >>> for a in range(0, 40, 16):
    ...     rec.push(frames[a:a + 16], np.arange(a, min(a + 16, 40)) * 0.05)
    >>> [e.kind for e in rec.result().events][:2]
    ['contact', 'tacteme']
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
        per_frame: bool = False,
        streaming: bool = False,
    ) -> None:
        rows, cols = check_shape("shape", shape)
        self.shape = (rows, cols)
        self.pitch_mm = check_positive("pitch_mm", pitch_mm)
        self.threshold = (
            _DEFAULT_THRESHOLD_MM if threshold is None else check_threshold("threshold", threshold)
        )
        self.network = network
        self.confidence = float(confidence)
        self.config = TactemeConfig() if config is None else config
        self.limits = limits
        self.per_frame = bool(per_frame)
        self.streaming = bool(streaming)
        self.last_classes = np.empty(0, np.int8)  # Level 2 classes of the last chunk
        self._opened = False  # the accepted segment was handed to Levels 3-4 already
        self._handed = 0  # its length when it was last handed over
        self._cleaner = None if cleaning is None else ChunkCleaner(self.shape, config=cleaning)
        self._limit_state = LimitState()
        self._levels = _Levels34(self.config)
        self._n_seen = 0
        self._t0: float | None = None
        self._t_last = -np.inf
        self._dt: float | None = None
        self._segments: list[ClassSegments] = []
        self._classes: list[NDArray[np.int8]] = []
        # frames not yet debounced: global index, class, Level 1 row (until dt is known,
        # then only a candidate run shorter than its debounce count)
        self._wait_idx = np.empty(0, np.int64)
        self._wait_cls = np.empty(0, np.int8)
        self._wait_rows = np.empty((0, _ROW_FIELDS))
        self._current = _NONE
        self._accept = -1  # frame at which the current class was accepted, -1 before any
        self._open_idx: list[NDArray[np.int64]] = []  # the open contact segment's frames
        self._open_rows: list[NDArray[np.float64]] = []

    def push(self, frames: ArrayLike, t_s: ArrayLike) -> list[Event]:
        """Recognise the next chunk of frames.

        Parameters
        ----------
        frames : (n, rows, cols) bool or float
            Contact images or deflections (in the threshold's units).
        t_s : (n,) float, s
            Their timestamps, strictly increasing across chunks.

        Returns
        -------
        list of Event
            The events found (with ``streaming``, as they happen; otherwise
            those of the segments that ended).

        Raises
        ------
        InputError
            If the shape does not match or the timestamps go back.
        """
        f = np.asarray(frames)
        t = np.asarray(t_s, dtype=np.float64)
        if f.ndim != 3 or f.shape[1:] != self.shape:
            raise InputError(
                f"frames must have shape (n, {self.shape[0]}, {self.shape[1]}), got {f.shape}"
            )
        if t.shape != (f.shape[0],):
            raise InputError(f"t_s must have shape ({f.shape[0]},), got {t.shape}")
        if f.shape[0] == 0:
            return []
        before = len(self._levels.events)
        if not t[0] > self._t_last:
            raise InputError(
                f"t_s must increase across chunks, got {float(t[0])!r} after {self._t_last!r}"
            )
        if self._t0 is None:
            self._t0 = float(t[0])
        if self._dt is None and self._n_seen + t.size > 1:
            self._dt = float(t[1 - self._n_seen] - self._t0)
        self._t_last = float(t[-1])
        images = binary_images(f, None if f.dtype == bool else self.threshold)
        if self._cleaner is not None:
            images = self._cleaner.push(images, t)
        stats = image_stats(images, pitch_mm=self.pitch_mm)
        classes = classify_contacts(stats, self.network, confidence=self.confidence)
        half = _half_length(stats)
        if self.limits is not None:
            classes = apply_limits(
                classes,
                stats.n_taxels,
                2.0 * half,
                stats.elongation,
                self.limits,
                area_mm2=stats.area_mm2,
                state=self._limit_state,
            ).astype(np.int8)
        classes = np.asarray(classes, dtype=np.int8)
        self.last_classes = classes
        if self.streaming:
            self._segments = []
        self._segments.append(class_segments(classes, t, first_frame=self._n_seen))
        if self.per_frame:
            self._classes.append(classes)
        keep = np.flatnonzero(classes != _INDET)
        rows = np.empty((keep.size, _ROW_FIELDS))
        rows[:, 0:2] = stats.centre_mm[keep]
        rows[:, 2] = stats.orientation_deg[keep]
        rows[:, 3] = stats.area_mm2[keep]
        rows[:, 4] = stats.elongation[keep]
        rows[:, 5] = half[keep]
        rows[:, 6] = t[keep]
        self._wait_idx = np.concatenate([self._wait_idx, keep + self._n_seen])
        self._wait_cls = np.concatenate([self._wait_cls, classes[keep]])
        self._wait_rows = np.concatenate([self._wait_rows, rows])
        self._n_seen += f.shape[0]
        if self._dt is not None:
            self._debounce()
        if self.streaming:
            self._hand_over_open_segment()
        found = self._levels.events[before:]
        if self.streaming and len(self._levels.events) > _EVENTS_KEPT:
            self._forget_old_contacts()
        return found

    def _forget_old_contacts(self) -> None:
        """Streaming: drop the events of contacts before the last two (the verdict needs
        the last contact's, or the ongoing one's, only)."""
        events = self._levels.events
        lifts = [i for i, e in enumerate(events) if e.kind == "lifted"]
        if len(lifts) >= 2:
            del events[: lifts[-2] + 1]

    # -- the debounce of tactemes.accepted_runs, carried across chunks ---------------------
    def _debounce(self) -> None:
        k, k_none = debounce_counts(self.config, self._dt)
        idx, c, rows = self._wait_idx, self._wait_cls, self._wait_rows
        if c.size == 0:
            return
        cut = np.flatnonzero(np.diff(c)) + 1
        starts = np.concatenate([[0], cut]).tolist()
        ends = np.concatenate([cut, [c.size]]).tolist()
        carry = c.size  # where the frames still waiting begin
        for s, e in zip(starts, ends, strict=True):
            cls = int(c[s])
            if cls == self._current:
                if self._accept >= 0 and cls != _NONE:
                    self._open_idx.append(idx[s:e])
                    self._open_rows.append(rows[s:e])
                continue
            k_cls = k_none if cls == _NONE else k
            if e - s >= k_cls:
                self._close()
                self._current, self._accept = cls, int(idx[s + k_cls - 1])
                if cls != _NONE:
                    self._open_idx, self._open_rows = [idx[s:e]], [rows[s:e]]
                elif self.streaming:  # "lifted" at once
                    self._levels.open_run(cls, self._accept, None)
                    self._opened = True
            elif e == c.size:  # a candidate that may go on in the next chunk
                carry = s
        self._wait_idx = idx[carry:].copy()
        self._wait_cls = c[carry:].copy()
        self._wait_rows = rows[carry:].copy()

    def _open_track(self) -> SegmentTrack:
        """The open contact segment's frames so far (its pieces joined into one)."""
        idx = np.concatenate(self._open_idx)
        r = np.concatenate(self._open_rows)
        self._open_idx, self._open_rows = [idx], [r]
        return SegmentTrack(
            idx.astype(np.intp), r[:, 0:2], r[:, 2], r[:, 3], r[:, 4], r[:, 5], r[:, 6]
        )

    def _close(self) -> None:
        """Hand the accepted segment, now complete, to Levels 3-4."""
        if self._accept < 0:
            return
        if self._current != _NONE:
            track = self._open_track()
            if self._opened:
                self._levels.update(track)
            else:
                self._levels.open_run(self._current, self._accept, track)
        elif not self._opened:
            self._levels.open_run(self._current, self._accept, None)
        self._open_idx, self._open_rows = [], []
        self._opened = False
        self._handed = 0

    def _hand_over_open_segment(self) -> None:
        """Streaming: the open contact segment grew; Levels 3-4 look at it again."""
        if self._accept < 0 or self._current == _NONE or not self._open_idx:
            return
        n = sum(piece.size for piece in self._open_idx)
        if self._opened and n - self._handed < max(_REVIEW_FRAMES, n // _REVIEW_FRACTION):
            return
        track = self._open_track()
        if self._opened:
            self._levels.update(track)
        else:
            self._levels.open_run(self._current, self._accept, track)
            self._opened = True
        self._handed = n

    def result(self) -> ChunkRecognition:
        """The recognition of every frame pushed so far.

        Call it once, after the last chunk: it closes the open segment.
        """
        self._debounce()  # a recording of one frame: the debounce with an unknown interval
        self._close()
        self._accept = -1
        done = _finish(np.empty(0, np.int8), list(self._levels.events))
        segments = joined_segments(self._segments)
        classes = np.concatenate(self._classes) if self.per_frame and self._classes else None
        return ChunkRecognition(
            segments,
            done.tactemes,
            done.events,
            done.identified,
            done.candidates,
            done.verdict,
            classes,
        )


def recognise_chunks(
    chunks: Iterable[TactileFrames], *, pitch_mm: float | None = None, **options: Any
) -> ChunkRecognition:
    """Recognise a recording given as consecutive chunks (see :class:`ChunkRecogniser`).

    Parameters
    ----------
    chunks : iterable of TactileFrames
        Consecutive pieces of one recording (same shape, pitch and units;
        timestamps increasing across pieces).
    pitch_mm : float, optional
        Overrides the chunks' pitch.
    **options
        ``threshold``, ``network``, ``confidence``, ``config``, ``cleaning``,
        ``limits``, ``per_frame`` of :class:`ChunkRecogniser`.

    Returns
    -------
    ChunkRecognition

    Raises
    ------
    InputError
        If there are no chunks, or they differ in shape.
    """
    recogniser: ChunkRecogniser | None = None
    for chunk in chunks:
        if recogniser is None:
            pitch = chunk.pitch_mm if pitch_mm is None else pitch_mm
            recogniser = ChunkRecogniser(chunk.shape[1:], pitch_mm=pitch, **options)
        recogniser.push(chunk.frames, chunk.t_s)
    if recogniser is None:
        raise InputError("chunks must hold at least one chunk of frames")
    return recogniser.result()
