"""Per-frame Level 2 classes as run-length segments, and a recognition that reports them.

A day of frames at 240 frames/s is 20 million classes; as runs of one class
(``{class, first_frame, last_frame}``, with their times) it is a few per
contact. :class:`ChunkRecognition` is what the chunked and streaming
recognisers (:mod:`taxelkit.smart.recognise_chunks`) return: a
:class:`~taxelkit.smart.recogniser.Recognition` whose classes come as
:class:`ClassSegments`, the per-frame list only on request.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError
from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.elimination import Event, Verdict
from taxelkit.smart.slip import Slip, slip_to_json

__all__ = ["ChunkRecognition", "ClassSegments", "class_segments", "joined_segments", "json_doc"]

#: Runs turned into Python numbers at a time by :meth:`ClassSegments.iter_json`.
_JSON_BATCH = 4096


def json_doc(parts: list[tuple[str, Any]]) -> dict[str, Any]:
    """A JSON document from ``(key, value)`` parts whose long lists may be iterators."""
    return {k: list(v) if isinstance(v, Iterator) else v for k, v in parts}


@dataclass(frozen=True, eq=False)
class ClassSegments:
    """Per-frame Level 2 classes as runs of equal class.

    Attributes
    ----------
    class_code : (S,) int8
        :class:`~taxelkit.smart.contact_classes.ContactClass` of each run.
    first_frame, last_frame : (S,) int64
        First and last frame of each run (inclusive).
    first_s, last_s : (S,) float64, s
        Their timestamps.
    """

    class_code: NDArray[np.int8]
    first_frame: NDArray[np.int64]
    last_frame: NDArray[np.int64]
    first_s: NDArray[np.float64]
    last_s: NDArray[np.float64]

    @property
    def n_frames(self) -> int:
        """Frames covered (the recording's length)."""
        return int(self.last_frame[-1]) + 1 if self.last_frame.size else 0

    def per_frame(self) -> NDArray[np.int8]:
        """The per-frame classes again, ``(T,)`` int8."""
        out: NDArray[np.int8] = np.repeat(self.class_code, self.last_frame - self.first_frame + 1)
        return out

    def to_json(self) -> list[dict[str, Any]]:
        """One ``{class, first_frame, last_frame, first_s, last_s}`` object per run."""
        return list(self.iter_json())

    def iter_json(self) -> Iterator[dict[str, Any]]:
        """The objects of :meth:`to_json`, one at a time (a day's runs need not exist at once)."""
        names = {int(c): ContactClass(int(c)).name.lower() for c in np.unique(self.class_code)}
        for a in range(0, self.class_code.size, _JSON_BATCH):
            b = a + _JSON_BATCH
            for c, first, last, first_s, last_s in zip(
                self.class_code[a:b].tolist(),
                self.first_frame[a:b].tolist(),
                self.last_frame[a:b].tolist(),
                self.first_s[a:b].tolist(),
                self.last_s[a:b].tolist(),
                strict=True,
            ):
                yield {
                    "class": names[c],
                    "first_frame": first,
                    "last_frame": last,
                    "first_s": first_s,
                    "last_s": last_s,
                }


def class_segments(classes: ArrayLike, t_s: ArrayLike, *, first_frame: int = 0) -> ClassSegments:
    """Run-length segments of a class sequence.

    Parameters
    ----------
    classes : (T,) int
        Class codes.
    t_s : (T,) float, s
        Timestamps.
    first_frame : int
        Index of the first frame.

    Returns
    -------
    ClassSegments

    Examples
    --------
    >>> seg = class_segments([0, 0, 2, 2, 2, 0], np.arange(6) * 0.5)
    >>> seg.first_frame.tolist(), seg.last_frame.tolist(), seg.last_s.tolist()
    ([0, 2, 5], [1, 4, 5], [0.5, 2.0, 2.5])
    """
    c = np.asarray(classes, dtype=np.int8)
    t = np.asarray(t_s, dtype=np.float64)
    if c.ndim != 1 or t.shape != c.shape:
        raise InputError(f"classes and t_s must be (T,) of one length, got {c.shape}, {t.shape}")
    starts = np.flatnonzero(np.concatenate([[True], c[1:] != c[:-1]])) if c.size else c[:0]
    ends = np.concatenate([starts[1:], [c.size]]) - 1 if c.size else starts
    return ClassSegments(
        c[starts],
        (starts + first_frame).astype(np.int64),
        (ends + first_frame).astype(np.int64),
        t[starts],
        t[ends],
    )


def joined_segments(parts: list[ClassSegments]) -> ClassSegments:
    """Concatenate consecutive segments, merging a run that crosses a boundary."""
    if not parts:
        return class_segments(np.empty(0, np.int8), np.empty(0))
    code = np.concatenate([p.class_code for p in parts])
    first = np.concatenate([p.first_frame for p in parts])
    last = np.concatenate([p.last_frame for p in parts])
    first_s = np.concatenate([p.first_s for p in parts])
    last_s = np.concatenate([p.last_s for p in parts])
    keep = np.concatenate([[True], code[1:] != code[:-1]])  # a new class starts a run
    ends = np.concatenate([np.flatnonzero(keep)[1:] - 1, [code.size - 1]])
    return ClassSegments(code[keep], first[keep], last[ends], first_s[keep], last_s[ends])


@dataclass(frozen=True, eq=False)
class ChunkRecognition:
    """What :class:`ChunkRecogniser` concluded: a :class:`Recognition` with run-length classes.

    Attributes
    ----------
    segments : ClassSegments
        Level 2 classes of all frames as runs.
    tactemes, events, identified, candidates, verdict
        As in :class:`~taxelkit.smart.recogniser.Recognition`.
    classes : (T,) int8 or None
        Per-frame classes, kept only when asked for (``per_frame=True``).
    slips : tuple of Slip
        Slip phases (:mod:`taxelkit.smart.slip`).
    """

    segments: ClassSegments
    tactemes: tuple[tuple[str, int], ...]
    events: tuple[Event, ...]
    identified: str | None
    candidates: tuple[str, ...]
    verdict: Verdict
    classes: NDArray[np.int8] | None = None
    slips: tuple[Slip, ...] = ()

    @property
    def n_frames(self) -> int:
        """Frames recognised."""
        return self.segments.n_frames

    def to_json(self, *, per_frame: bool = False) -> dict[str, Any]:
        """JSON types: ``class_segments`` always, ``classes`` (per frame) on request."""
        return json_doc(self.json_parts(per_frame=per_frame))

    def json_parts(self, *, per_frame: bool = False) -> list[tuple[str, Any]]:
        """The keys and values of :meth:`to_json`, the long lists as iterators (to stream them)."""
        parts: list[tuple[str, Any]] = [
            ("identified", self.identified),
            ("candidates", list(self.candidates)),
            ("why", self.verdict.to_json()),
            ("tactemes", ({"name": n, "frame": f} for n, f in self.tactemes)),
            ("slips", [slip_to_json(s) for s in self.slips]),
            ("n_frames", self.n_frames),
            ("class_segments", self.segments.iter_json()),
        ]
        if per_frame:
            codes = self.segments.per_frame() if self.classes is None else self.classes
            names = {int(c): c.name.lower() for c in ContactClass}
            parts.append(("classes", (names[c] for c in codes.tolist())))
        return parts
