"""The recogniser driven a chunk at a time: recordings larger than memory.

:func:`~taxelkit.smart.recogniser.recognise` holds a whole recording and its
per-frame statistics. :class:`ChunkRecogniser` takes the same frames in
consecutive chunks through the vectorised Levels 1-2 with carried state
(:class:`~taxelkit.smart.levels12.ChunkLevels12`: cleaning, the limits'
hysteresis) and the incremental Levels 3-4 of the streaming sensor
(:class:`~taxelkit.smart.stream_state.ArrayStream`), whose cost per frame does
not grow with a contact's length. The per-frame classes are kept as
run-length :class:`ClassSegments`. The events, tactemes and verdict are those
of :func:`~taxelkit.smart.recogniser.recognise` for any chunking (tested);
memory is bounded by the chunk size, not by the recording.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive, check_shape, check_threshold
from taxelkit.smart.class_history import check_chunk_times
from taxelkit.smart.class_segments import (
    ChunkRecognition,
    ClassSegments,
    class_segments,
    joined_segments,
)
from taxelkit.smart.cleaning import CleaningConfig
from taxelkit.smart.contact_classes import DEFAULT_CONFIDENCE, HAND_SET, ContactNetwork
from taxelkit.smart.contact_limits import ContactLimits
from taxelkit.smart.elimination import Event
from taxelkit.smart.levels12 import (
    DEFAULT_CLEANING,
    DEFAULT_LIMITS,
    DEFAULT_THRESHOLD_MM,
    ChunkLevels12,
)
from taxelkit.smart.stream_state import ArrayStream, ClassHistory, check_chunk
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.tactemes import TactemeConfig

__all__ = [
    "ChunkRecogniser",
    "ChunkRecognition",
    "ClassSegments",
    "class_segments",
    "levels12_of",
    "push_chunk",
    "recognise_chunks",
]

#: Streaming: events kept before those of old contacts are dropped.
_EVENTS_KEPT = 1024


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
        For endless streams: the class segments are kept for the last chunk
        only, and the events of contacts before the last two are forgotten
        once more than 1024 have gathered (the verdict needs the last
        contact's only), so memory does not grow with the stream. Events are
        returned by :meth:`push` as they are detected either way.

    Examples
    --------
    >>> frames = np.zeros((40, 16, 16), bool); frames[5:30, 7:9, 7:9] = True
    >>> rec = ChunkRecogniser((16, 16), pitch_mm=1.7625)
    >>> for a in range(0, 40, 16):
    ...     _ = rec.push(frames[a:a + 16], np.arange(a, min(a + 16, 40)) * 0.05)
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
        thr = DEFAULT_THRESHOLD_MM if threshold is None else check_threshold("threshold", threshold)
        self.threshold = thr
        self.config = TactemeConfig() if config is None else config
        self.per_frame = bool(per_frame)
        self.streaming = bool(streaming)
        self.last_classes = np.empty(0, np.int8)  # Level 2 classes of the last chunk
        self._levels12 = ChunkLevels12(
            1,
            self.shape,
            pitch_mm=self.pitch_mm,
            threshold=thr,
            network=network,
            confidence=float(confidence),
            cleaning=cleaning,
            limits=limits,
        )
        self._stream = ArrayStream(self.config, pitch_mm=self.pitch_mm)
        self._n_seen = 0
        self._t_last = -np.inf
        self._segments: list[ClassSegments] = []
        self._classes: list[NDArray[np.int8]] = []

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
            The events detected in this chunk.

        Raises
        ------
        InputError
            If the shape does not match or the timestamps go back.
        """
        f, t = check_chunk(frames, t_s, self.shape, self._t_last)
        if f.shape[0] == 0:
            return []
        self._t_last = float(t[-1])
        return self._next("frames", f, t)

    def push_packed(self, rows: ArrayLike, t_s: ArrayLike) -> list[Event]:
        """As :meth:`push`, the contact frames packed 8 taxels to a byte along each row.

        The image cleaning works on packed rows: rows of 8, 16, 32 or 64
        taxels go to it as given (no unpacking and packing again), others are
        unpacked first. The events are those of :meth:`push` of the frames
        unpacked (tested).

        Parameters
        ----------
        rows : (n, rows, ceil(cols / 8)) uint8
            Bit ``c % 8`` (least significant first) of byte ``c // 8`` is
            column ``c`` (:class:`~taxelkit.io.packed_chunk.PackedChunk`); bits
            past ``cols`` are ignored.
        t_s : (n,) float, s
            Their timestamps, strictly increasing across chunks.

        Returns
        -------
        list of Event
            The events detected in this chunk.

        Raises
        ------
        InputError
            If the shape or dtype does not match or the timestamps go back.
        """
        p = np.asarray(rows)
        r, c = self.shape
        if p.dtype != np.uint8 or p.ndim != 3 or p.shape[1:] != (r, -(-c // 8)):
            raise InputError(
                f"rows must be uint8 of shape (n, {r}, {-(-c // 8)}), got {p.dtype} {p.shape}"
            )
        ops = self._levels12.ops
        if not (self._levels12.packs and c == 8 * ops.bytes):
            return self.push(np.unpackbits(p, axis=2, count=c, bitorder="little").view(bool), t_s)
        t = check_chunk_times(t_s, p.shape[0], self._t_last)
        if p.shape[0] == 0:
            return []
        self._t_last = float(t[-1])
        words = np.ascontiguousarray(p).view(ops.dtype).reshape(p.shape[0], 1, r)
        return self._next("packed", words, t)

    def push_levels12(
        self,
        classes: NDArray[np.int8],
        rows: NDArray[np.float64],
        t_s: NDArray[np.float64],
        *,
        precomputed: dict[tuple[int, bytes], list[tuple[Tacteme, int]]] | None = None,
    ) -> list[Event]:
        """Levels 3-4 of a chunk whose Levels 1-2 ran elsewhere; its events.

        Parameters
        ----------
        classes : (1, n) int8
            Level 2 classes (:func:`levels12_of`), of the chunk after the last one pushed.
        rows : (1, n, 9) float
            Their statistics.
        t_s : (n,) float, s
            Their timestamps, checked already.
        precomputed : dict, optional
            The motion tactemes of segments the chunk ends, computed elsewhere
            (:meth:`~taxelkit.smart.whole_segments.WholeSegments.tactemes`);
            those not asked for are dropped.
        """
        self._t_last = float(t_s[-1])
        self._stream.precomputed = {} if precomputed is None else precomputed
        try:
            return self._levels34(classes, rows, t_s)
        finally:
            self._stream.precomputed = {}

    def _next(self, kind: str, data: NDArray[Any], t: NDArray[np.float64]) -> list[Event]:
        """Levels 1-4 of a checked chunk (:func:`levels12_of`); its events.

        The worker of :func:`~taxelkit.smart.recognise_pipeline.recognise_pipelined`
        sends them to another process instead (:meth:`push_levels12` there).
        """
        return self._levels34(*levels12_of(self._levels12, kind, data, t), t)

    def _levels34(
        self, classes_nt: NDArray[np.int8], rows: NDArray[np.float64], t: NDArray[np.float64]
    ) -> list[Event]:
        """Levels 3-4 of a chunk's classes ``(1, n)`` and rows ``(1, n, 9)`` at times ``t``."""
        classes = classes_nt[0]
        self.last_classes = classes
        if self.streaming:
            self._segments = []
            self._stream.classes = ClassHistory()  # the history is the segments, kept above
        self._segments.append(class_segments(classes, t, first_frame=self._n_seen))
        if self.per_frame:
            self._classes.append(classes)
        self._n_seen += classes.size
        found = self._stream.push_chunk(classes, rows[0], t)
        events = self._stream.state.events
        if self.streaming and len(events) > _EVENTS_KEPT:
            lifts = [i for i, e in enumerate(events) if e.kind == "lifted"]
            if len(lifts) >= 2:
                del events[: lifts[-2] + 1]
        return found

    def result(self) -> ChunkRecognition:
        """The recognition of every frame pushed so far."""
        done = self._stream.result()
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
            done.slips,
        )


def levels12_of(
    levels12: ChunkLevels12, kind: str, data: NDArray[Any], t_s: NDArray[np.float64]
) -> tuple[NDArray[np.int8], NDArray[np.float64]]:
    """Classes ``(1, n)`` and rows ``(1, n, 9)`` of one array's chunk.

    Parameters
    ----------
    levels12 : ChunkLevels12
        One array's Levels 1-2, state carried from chunk to chunk.
    kind : {"frames", "packed"}
        ``data`` is frames ``(n, rows, cols)`` (bool, or float in the
        threshold's units), or rows packed one word each ``(n, 1, rows)``
        (:attr:`ChunkLevels12.ops`).
    data : ndarray
    t_s : (n,) float, s
    """
    if kind == "packed":
        return levels12.process_packed_time_major(data, t_s[None])
    return levels12.process(data[None], t_s[None])


def push_chunk(recogniser: ChunkRecogniser, chunk: Any) -> list[Event]:
    """Push a chunk: frames (:meth:`ChunkRecogniser.push`) or packed rows (``push_packed``).

    Parameters
    ----------
    recogniser : ChunkRecogniser
    chunk : TactileFrames or PackedChunk
        A chunk with ``frames`` and ``t_s``, or with packed ``rows`` and
        ``t_s`` (:class:`~taxelkit.io.packed_chunk.PackedChunk`).

    Returns
    -------
    list of Event
        The events it caused.
    """
    if hasattr(chunk, "rows"):
        return recogniser.push_packed(chunk.rows, chunk.t_s)
    return recogniser.push(chunk.frames, chunk.t_s)


def recognise_chunks(
    chunks: Iterable[Any], *, pitch_mm: float | None = None, **options: Any
) -> ChunkRecognition:
    """Recognise a recording given as consecutive chunks (see :class:`ChunkRecogniser`).

    Parameters
    ----------
    chunks : iterable of TactileFrames or packed chunks
        Consecutive pieces of one recording (same shape, pitch and units;
        timestamps increasing across pieces); see :func:`push_chunk`.
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
        push_chunk(recogniser, chunk)
    if recogniser is None:
        raise InputError("chunks must hold at least one chunk of frames")
    return recogniser.result()
