"""The streaming smart sensor fed batches of frames: what a live source delivers at once.

A live source hands over, each time it is read, every frame that arrived
since the last read: one frame at 240 frames/s, hundreds at 50,000 frames/s.
:class:`BatchSmartSensor` takes such a batch in one call:

* Levels 1-2 run vectorised over the batch (the cleaning, statistics,
  network and limits of :func:`~taxelkit.smart.recogniser.recognise`, with
  their state carried from batch to batch);
* the debounce and Levels 3-4 of :class:`~taxelkit.smart.recogniser.SmartSensor`
  then step through the batch's frames, and the open segment's motion
  tactemes are looked for once per batch (and whenever a segment ends)
  instead of every 16 frames.

Detection is causal, so the events and their frame numbers are those of
:func:`~taxelkit.smart.recogniser.recognise` for any batching (tested); only
their emission waits for the end of the batch. The per-frame class list of
:class:`SmartSensor` is kept for the last batch only, so memory does not grow
with the stream (the open contact segment's statistics still do, 56 bytes a
frame, until it ends).
"""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError
from taxelkit.smart.cleaning import CleaningConfig
from taxelkit.smart.cleaning_chunks import ChunkCleaner
from taxelkit.smart.contact_classes import (
    DEFAULT_CONFIDENCE,
    HAND_SET,
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
    SmartSensor,
    _half_length,
)
from taxelkit.smart.tactemes import TactemeConfig

__all__ = ["BatchSmartSensor"]

#: ``evaluate_every`` of the wrapped sensor: never by count, once per batch instead.
_NEVER = 2**62


class BatchSmartSensor(SmartSensor):
    """:class:`~taxelkit.smart.recogniser.SmartSensor` fed a batch of frames per call.

    Parameters are those of :class:`~taxelkit.smart.recogniser.SmartSensor`
    (without ``evaluate_every``: the open segment is evaluated once per batch).

    Examples
    --------
    >>> frames = np.zeros((40, 16, 16), bool); frames[5:30, 7:9, 7:9] = True
    >>> sensor = BatchSmartSensor((16, 16), pitch_mm=1.7625)
    >>> events, classes = sensor.push_many(frames, np.arange(40) * 0.05)
    >>> [e.kind for e in events][:2], classes.shape
    (['contact', 'tacteme'], (40,))
    """

    def __init__(
        self,
        shape: tuple[int, int],
        *,
        pitch_mm: float,
        threshold: float = _DEFAULT_THRESHOLD_MM,
        network: ContactNetwork = HAND_SET,
        confidence: float = DEFAULT_CONFIDENCE,
        config: TactemeConfig | None = None,
        cleaning: CleaningConfig | None = DEFAULT_CLEANING,
        limits: ContactLimits | None = DEFAULT_LIMITS,
    ) -> None:
        super().__init__(
            shape,
            pitch_mm=pitch_mm,
            threshold=threshold,
            network=network,
            confidence=confidence,
            config=config,
            cleaning=cleaning,
            limits=limits,
            evaluate_every=_NEVER,
        )

    def reset(self) -> None:
        """Start afresh (no frames seen)."""
        super().reset()
        self._batch_cleaner = (
            None if self.cleaning is None else ChunkCleaner(self.shape, config=self.cleaning)
        )
        self._batch_limits = LimitState()
        self._levels12: Iterator[tuple[int, tuple[float, ...]]] = iter(())

    def push_many(self, frames: ArrayLike, t_s: ArrayLike) -> tuple[list[Event], NDArray[np.int8]]:
        """Process a batch of frames.

        Parameters
        ----------
        frames : (n, rows, cols) bool or float
            Consecutive frames (``n`` may be 0).
        t_s : (n,) float, s
            Their timestamps.

        Returns
        -------
        events : list of Event
            The events the batch caused, in order.
        classes : (n,) int8
            Level 2 class of each frame of the batch.

        Raises
        ------
        InputError
            If the shapes do not match.
        """
        f = np.asarray(frames)
        t = np.asarray(t_s, dtype=np.float64)
        if f.ndim != 3 or f.shape[1:] != self.shape or t.shape != (f.shape[0],):
            raise InputError(
                f"frames must be (n, {self.shape[0]}, {self.shape[1]}) with t_s (n,), "
                f"got {f.shape} and {t.shape}"
            )
        start = len(self._state.events)
        if f.shape[0] == 0:
            return [], np.empty(0, np.int8)
        classes, rows = self._levels12_of(f, t)
        empty: tuple[float, ...] = ()
        self._levels12 = iter(
            [(c, r if c else empty) for c, r in zip(classes.tolist(), rows, strict=True)]
        )
        for frame, when in zip(f, t.tolist(), strict=True):
            self.push(frame, when)
        self._flush()  # the open segment's motion tactemes, once per batch
        del self.classes[:]
        return self._state.events[start:], classes

    def _levels12_of(
        self, frames: NDArray[Any], t_s: NDArray[np.float64]
    ) -> tuple[NDArray[np.int8], list[tuple[float, ...]]]:
        """Levels 1-2 of a batch, as :func:`recognise` computes them."""
        images = binary_images(frames, None if frames.dtype == bool else self.threshold)
        if self._batch_cleaner is not None:
            images = self._batch_cleaner.push(images, t_s)
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
                state=self._batch_limits,
            )
        table = np.column_stack(
            [stats.centre_mm, stats.orientation_deg, stats.area_mm2, stats.elongation, half]
        )
        rows: list[tuple[float, ...]] = [tuple(r) for r in table.tolist()]
        return np.asarray(classes, dtype=np.int8), rows

    def _classify(self, frame: NDArray[Any], t_s: float) -> tuple[int, tuple[float, ...]]:
        """The class and statistics computed for this frame by :meth:`push_many`."""
        found = next(self._levels12, None)
        if found is None:
            raise InputError("a BatchSmartSensor takes frames through push_many, not push")
        return found
