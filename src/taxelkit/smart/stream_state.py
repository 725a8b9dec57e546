"""Levels 3-4 of one array's stream: debounce, the open segment's scanner, elimination.

Shared by :class:`~taxelkit.smart.streaming.SmartSensor` (one array) and
:class:`~taxelkit.smart.bank.SensorBank` (many). Frames come one at a time
(:meth:`ArrayStream.push_one`) or as a chunk of Level 2 classes and Level 1
rows (:meth:`ArrayStream.push_chunk`, one Python step per run of equal
classes); either way the debounce is that of
:func:`~taxelkit.smart.tactemes.accepted_runs`, the open segment goes to a
:class:`~taxelkit.smart.segment_scan.SegmentScanner` and the events are those
of :func:`~taxelkit.smart.recogniser.recognise`. A bank splits a chunk in two
(:meth:`ArrayStream.begin_chunk`, :meth:`ArrayStream.end_chunk`: the open
segment's last feed) to compute the slip scanners' part of that feed for all
its arrays at once. Memory: the class history is
kept as runs (one entry per change of class), the open segment as the
scanner's bounded state.
"""

from __future__ import annotations

import copy
import itertools

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.class_history import ClassHistory, check_chunk
from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.elimination import Event
from taxelkit.smart.levels34 import Levels34, Recognition, TrackSegment, finish, track_segments
from taxelkit.smart.segment_head import SlipInputs, track_from_rows
from taxelkit.smart.segment_scan import SegmentScanner
from taxelkit.smart.slip_scan import SlipScanner
from taxelkit.smart.stream_calls import DeferredSegment, LevelsCall
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.tactemes import SegmentTrack, TactemeConfig, debounce_counts

__all__ = ["ArrayStream", "ClassHistory", "WholeItem", "check_chunk"]

#: A segment that began and ended within a chunk: class, track, rows (as fed).
WholeItem = tuple[int, SegmentTrack, NDArray[np.float64] | None]

_NONE = int(ContactClass.NONE)
_INDET = int(ContactClass.INDETERMINATE)


class ArrayStream:
    """Debounce and Levels 3-4 of one array's stream.

    Parameters
    ----------
    config : TactemeConfig
    evaluate_every : int
        With frames one at a time, the open segment's scanner is fed every
        this many frames (and when the segment ends).
    chunk_every : int
        With chunks, the scanner is fed once this many frames of the open
        segment have come (and when it ends): 1, after every chunk.
    pitch_mm : float
        Taxel pitch, mm, for the grid's share of a line's turn (0: unknown).
    """

    def __init__(
        self,
        config: TactemeConfig,
        evaluate_every: int = 16,
        chunk_every: int = 1,
        pitch_mm: float = 0.0,
    ) -> None:
        self.config = config
        self.pitch_mm = float(pitch_mm)
        self.every = int(evaluate_every)
        self.chunk_every = int(chunk_every)
        self.classes = ClassHistory()
        self.state = Levels34(config)
        self.frame_index = 0
        self._accepted = _NONE
        self._cand: int | None = None
        self._cand_j: list[NDArray[np.intp]] = []
        self._cand_rows: list[NDArray[np.float64]] = []
        self._cand_n = 0
        self._seg: SegmentScanner | None = None
        self._pend_j: list[int] = []
        self._pend_rows: list[tuple[float, ...]] = []
        self._pend_chunks: list[tuple[NDArray[np.intp], NDArray[np.float64]]] = []
        self._t_first: float | None = None
        self._dt: float | None = None
        # within push_chunk: a segment accepted in this chunk, not yet shown to Levels 3-4
        self._defer = False
        self._deferred: DeferredSegment | None = None
        # within push_chunk: the calls to Levels 3-4, replayed in order at the chunk's end
        # (the segments that ended within it computed together, by batch_tactemes)
        self._queue: list[LevelsCall] | None = None
        # between begin_chunk and end_chunk: the feed that ends the chunk (scanner, frames,
        # rows, and the class and accepting frame of a segment opened by it)
        self._tail: (
            tuple[SegmentScanner, NDArray[np.intp], NDArray[np.float64], tuple[int, int] | None]
            | None
        ) = None
        self._before = 0  # events before the chunk (debounce_chunk to settle_chunk)
        self._settling = False
        #: Tactemes of segments ending in the next chunk, by (class, frames.tobytes()), computed
        self.precomputed: dict[tuple[int, bytes], list[tuple[Tacteme, int]]] = {}  # elsewhere

    @property
    def idle(self) -> bool:
        """No contact accepted or pending: a chunk of "none" frames changes nothing but counts."""
        return self._accepted == _NONE and self._cand is None

    def _timing(self, t0: float, t1: float | None) -> None:
        if self._t_first is None:
            self._t_first = t0
            if t1 is not None:
                self._dt = t1 - t0
        elif self._dt is None:
            self._dt = t0 - self._t_first
        self.state.frame_interval_s = self._dt  # as recognise's: the first interval

    # -- one frame --------------------------------------------------------------------------
    def push_one(self, cls: int, row: tuple[float, ...], t_s: float) -> list[Event]:
        """One frame's class and row (empty for no contact); the events it caused."""
        j = self.frame_index
        self.frame_index += 1
        self.classes.append(cls)
        self._timing(t_s, None)
        if cls == _INDET:
            return []
        before = len(self.state.events)
        if cls == self._accepted:
            self._drop_candidate()
            if cls != _NONE:
                self._pend_j.append(j)
                self._pend_rows.append(row)
                if len(self._pend_j) >= self.every:
                    self._feed(final=False)
            return self.state.events[before:]
        if cls != self._cand:
            self._drop_candidate()
            self._cand = cls
        self._cand_j.append(np.array([j], dtype=np.intp))
        self._cand_rows.append(np.array([row]) if row else np.zeros((1, 9)))
        self._cand_n += 1
        k_contact, k_none = debounce_counts(self.config, self._dt)
        if self._cand_n >= (k_none if cls == _NONE else k_contact):
            self._accept(cls, j)
        return self.state.events[before:]

    # -- a chunk --------------------------------------------------------------------------------
    def push_chunk(
        self, classes: NDArray[np.int8], rows: NDArray[np.float64], t_s: NDArray[np.float64]
    ) -> list[Event]:
        """A chunk's classes ``(m,)``, rows ``(m, 9)`` and times ``(m,)``; the events caused."""
        return self.begin_chunk(classes, rows, t_s) + self.end_chunk()

    def begin_chunk(
        self, classes: NDArray[np.int8], rows: NDArray[np.float64], t_s: NDArray[np.float64]
    ) -> list[Event]:
        """:meth:`push_chunk` up to the open segment's last feed; the events caused so far.

        The feed that ends the chunk (its frames to the open segment's
        scanner) waits in :attr:`tail_feed` for :meth:`end_chunk`, which must
        come next: a bank computes the slip scanners' part of those feeds for
        all its arrays at once in between. It is :meth:`debounce_chunk` and
        :meth:`settle_chunk` with this array's whole segments computed between.
        """
        items = self.debounce_chunk(classes, rows, t_s)
        segs = track_segments(items, self.config, known=self.precomputed) if items else []
        return self.settle_chunk(segs)

    def debounce_chunk(
        self, classes: NDArray[np.int8], rows: NDArray[np.float64], t_s: NDArray[np.float64]
    ) -> list[WholeItem]:
        """:meth:`begin_chunk`'s debounce: the segments that began and ended within the chunk.

        Returns each such segment's ``(class, track, rows)``, in order, for
        :func:`~taxelkit.smart.levels34.track_segments`; its result goes to
        :meth:`settle_chunk`, which must come next. A bank computes those of
        all its arrays in one call (:attr:`precomputed` must then be empty).
        """
        assert self._tail is None, "end_chunk must follow begin_chunk"
        self._before = len(self.state.events)
        self._settling = False
        m = int(classes.size)
        if m == 0:
            return []
        if self.frame_index == 0 and m > 1:  # the first frame is debounced before dt is known
            self.push_chunk(classes[:1], rows[:1], t_s[:1])
            classes, rows, t_s = classes[1:], rows[1:], t_s[1:]
            m -= 1
        j0 = self.frame_index
        self.frame_index += m
        self.classes.extend_array(classes)
        self._timing(float(t_s[0]), float(t_s[1]) if m > 1 else None)
        idx = np.flatnonzero(classes != _INDET)
        if idx.size == 0:
            return []
        c = classes[idx]
        cut = np.flatnonzero(np.diff(c)) + 1
        bounds = np.concatenate([[0], cut, [c.size]]).tolist()
        k_contact, k_none = debounce_counts(self.config, self._dt)
        self._defer = True
        self._queue = []
        try:
            self._runs(c, idx, bounds, rows, j0, k_contact, k_none)
        except BaseException:
            self._defer = False
            self._replay()
            self._undefer(hold=True)
            raise
        self._defer = False
        self._settling = True
        return [(q.cls, q.track, q.rows) for q in self._queue if q.track is not None]

    def settle_chunk(self, segs: list[TrackSegment]) -> list[Event]:
        """The rest of :meth:`begin_chunk`: ``segs``, those of :meth:`debounce_chunk`'s segments."""
        if self._settling:
            self._settling = False
            self._replay(segs=segs)
            self._undefer(hold=True)
            if sum(j.size for j, _ in self._pend_chunks) >= self.chunk_every:
                self._feed(final=False, hold=True)
        return self.state.events[self._before :]

    @property
    def tail_feed(self) -> tuple[SlipScanner | None, NDArray[np.float64]] | None:
        """The feed :meth:`end_chunk` makes: the segment's slip scanner and the rows ``(m, 9)``."""
        if self._tail is None:
            return None
        return self._tail[0].slip_scanner, self._tail[2]

    def end_chunk(self, slip: SlipInputs | None = None) -> list[Event]:
        """Make the feed that ends a chunk (:meth:`begin_chunk`); the events it caused.

        ``slip``: the slip scanner's inputs for it, computed already.
        """
        tail, self._tail = self._tail, None
        if tail is None:
            return []
        seg, frames, rows, opened = tail
        before = len(self.state.events)
        seg.extend(frames, rows, slip=slip)
        if opened is None:
            self._call(LevelsCall(0, 0, seg, update=True))
        else:  # a segment accepted in this chunk, shown to Levels 3-4 with its first frames
            self.state.open_run(opened[0], opened[1], seg)
        return self.state.events[before:]

    def _runs(
        self,
        c: NDArray[np.int8],
        idx: NDArray[np.intp],
        bounds: list[int],
        rows: NDArray[np.float64],
        j0: int,
        k_contact: int,
        k_none: int,
    ) -> None:
        """The debounce over a chunk's runs of equal classes ``c`` (frames ``idx``)."""
        for s, e in itertools.pairwise(bounds):  # one step per run
            cls = int(c[s])
            sel = idx[s:e]
            if cls == self._accepted:
                self._drop_candidate()
                if cls != _NONE:
                    self._pend(j0 + sel, rows[sel])
                continue
            if cls != self._cand:
                self._drop_candidate()
                self._cand = cls
            need = (k_none if cls == _NONE else k_contact) - self._cand_n
            take = sel[:need]
            rest = sel[need:]
            if take.size == need and rest.size and cls != _NONE and self.chunk_every == 1:
                take = sel  # the run's later frames go to the new segment at once
            self._cand_j.append(j0 + take)
            self._cand_rows.append(rows[take])
            self._cand_n += int(take.size)
            if take.size < need:
                continue
            self._accept(cls, j0 + int(sel[need - 1]))
            if take.size == need and rest.size and cls != _NONE:
                self._pend(j0 + rest, rows[rest])

    def _pend(self, j: NDArray[np.intp], rows: NDArray[np.float64]) -> None:
        """Frames of the open segment, waiting for its scanner (or, deferred, for its end)."""
        if self._deferred is not None:
            self._deferred.later.append((j, rows))
        else:
            self._pend_chunks.append((j, rows))

    def look(self) -> list[Event]:
        """Feed the open segment what it has waiting; the events caused."""
        if not (self._pend_j or self._pend_chunks):
            return []
        before = len(self.state.events)
        self._feed(final=False)
        return self.state.events[before:]

    def push_quiet(self, t_s: NDArray[np.float64]) -> None:
        """A chunk of "no contact" frames at times ``t_s`` ``(m,)`` while :attr:`idle`."""
        m = int(t_s.size)
        if m:
            self._timing(float(t_s[0]), float(t_s[1]) if m > 1 else None)
            self.classes.extend_constant(_NONE, m)
            self.frame_index += m

    # -- shared -----------------------------------------------------------------------------
    def _drop_candidate(self) -> None:
        self._cand = None
        self._cand_j, self._cand_rows, self._cand_n = [], [], 0

    def _accept(self, cls: int, j: int) -> None:
        self._feed(final=True)  # the open segment ends: its last motion tactemes first
        self._close_deferred()
        self._accepted = cls
        if cls != _NONE and self._defer:  # it may end within this chunk: wait and see
            self._deferred = DeferredSegment(cls, j, self._cand_j, self._cand_rows)
            self._seg = None
            self._drop_candidate()
            return
        seg = None
        if cls != _NONE:
            seg = SegmentScanner(cls, self.config, self.pitch_mm)
            seg.extend(np.concatenate(self._cand_j), np.concatenate(self._cand_rows))
        self._seg = seg
        self._drop_candidate()
        self._call(LevelsCall(cls, j, seg))

    def _close_deferred(self) -> None:
        """A segment accepted and ended within one chunk: Levels 3-4 on it whole (batch).

        The events are those of the scanner fed the same frames in any pieces
        (both give those of :func:`~taxelkit.smart.recogniser.recognise`), at
        a fraction of the scanner's fixed cost per segment.
        """
        d, self._deferred = self._deferred, None
        if d is None:
            return
        pieces = [*zip(d.first_j, d.first_rows, strict=True), *d.later]
        frames = np.concatenate([p[0] for p in pieces])
        rows = np.concatenate([p[1] for p in pieces])
        track = track_from_rows(frames, rows, self.pitch_mm)
        self._call(LevelsCall(d.cls, d.accept, None, track, rows))

    def _call(self, call: LevelsCall) -> None:
        """A call to Levels 3-4: now, or queued while a chunk is debounced."""
        if self._queue is None:
            self._replay([call])
        else:
            self._queue.append(call)

    def _replay(
        self, calls: list[LevelsCall] | None = None, segs: list[TrackSegment] | None = None
    ) -> None:
        """Make the queued calls to Levels 3-4 in order (the whole segments' tactemes at once).

        ``segs``: the whole segments' :class:`TrackSegment`, computed already.
        """
        if calls is None:
            calls, self._queue = self._queue or [], None
        whole = [c for c in calls if c.track is not None]
        if whole:
            if segs is None:
                items = [(c.cls, c.track, c.rows) for c in whole]
                segs = track_segments(items, self.config, known=self.precomputed)  # type: ignore[arg-type]
            for c, seg in zip(whole, segs, strict=True):
                c.seg = seg
        for c in calls:
            if c.update:
                assert c.seg is not None
                self.state.update(c.seg)
            else:
                self.state.open_run(c.cls, c.accept, c.seg)

    def _undefer(self, *, hold: bool = False) -> None:
        """The chunk ended with a deferred segment open: it goes to a scanner after all.

        ``hold``: its first feed waits for :meth:`end_chunk` when nothing else
        would follow it in the chunk.
        """
        d, self._deferred = self._deferred, None
        if d is None:
            return
        seg = SegmentScanner(d.cls, self.config, self.pitch_mm)
        first_j, first_rows = d.first_j, d.first_rows
        if self.chunk_every == 1:  # the chunk's later frames too: one feed, not two
            first_j = [*first_j, *(j for j, _ in d.later)]
            first_rows = [*first_rows, *(r for _, r in d.later)]
            d.later = []
        self._seg = seg
        self._pend_chunks = d.later
        frames, rows = np.concatenate(first_j), np.concatenate(first_rows)
        if hold and not d.later:
            self._tail = (seg, frames, rows, (d.cls, d.accept))
            return
        seg.extend(frames, rows)
        self.state.open_run(d.cls, d.accept, seg)

    def _feed(self, *, final: bool, hold: bool = False) -> None:
        seg = self._seg
        if self._pend_j:
            self._pend_chunks.append(
                (np.asarray(self._pend_j, dtype=np.intp), np.asarray(self._pend_rows))
            )
            self._pend_j, self._pend_rows = [], []
        if seg is None:
            self._pend_chunks = []
            return
        grew = bool(self._pend_chunks)
        if len(self._pend_chunks) == 1:
            frames, rows = self._pend_chunks[0]
        elif self._pend_chunks:
            frames = np.concatenate([j for j, _ in self._pend_chunks])
            rows = np.concatenate([r for _, r in self._pend_chunks])
        self._pend_chunks = []
        if hold and grew and not final:  # the chunk's last feed: end_chunk makes it
            self._tail = (seg, frames, rows, None)
            return
        if grew:
            seg.extend(frames, rows)
        if final:
            grew |= bool(seg.close())
        if grew or final:
            self._call(LevelsCall(0, 0, seg, update=True))

    def result(self) -> Recognition:
        """Everything so far (detections waiting for later frames decided as if none came)."""
        self._feed(final=False)
        state = self.state
        if self._seg is not None and self._seg.waiting:
            state, seg = copy.deepcopy((self.state, self._seg))
            if seg.close():
                state.update(seg)
        return finish(
            self.classes.to_array(),
            list(state.events),
            list(state.slips.values()),
            objects=self.config.objects,
            unread_gap_s=state.unread_gap_s,
            blip_s=self.config.blip_s,
            frame_interval_s=self._dt,
            last_frame=self.frame_index - 1,
        )
