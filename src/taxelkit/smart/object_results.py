"""What the per-track recogniser reports: per-track events, verdicts and the whole result.

The records of :mod:`taxelkit.smart.objects`, with their JSON forms (the
``objects`` and ``track_events`` keys of ``taxelkit recognize --json``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.class_segments import json_doc
from taxelkit.smart.elimination import SLID, Verdict

__all__ = ["ObjectRecognition", "ObjectVerdict", "TrackSlip", "TrackedEvent", "interleaved"]


@dataclass(frozen=True)
class TrackedEvent:
    """An event of one track.

    Attributes
    ----------
    track : int
    kind : str
        A tracker event (``"birth"``, ``"death"``, ``"merge"``, ``"split"``)
        or a recogniser event of :class:`~taxelkit.smart.elimination.Event`
        (``"contact"``, ``"tacteme"``, ``"candidates"``, ``"identified"``,
        ``"unknown"``, ``"lifted"``).
    frame : int
    t_s : float, s
    value : str, tuple of str or int or None
        The recogniser event's value; for a merge or split the other track.
    """

    track: int
    kind: str
    frame: int
    t_s: float
    value: str | tuple[str, ...] | int | None = None

    def to_json(self) -> dict[str, Any]:
        """JSON types."""
        value: Any = list(self.value) if isinstance(self.value, tuple) else self.value
        return {
            "track": self.track,
            "kind": self.kind,
            "frame": self.frame,
            "t_s": self.t_s,
            "value": value,
        }


@dataclass(frozen=True)
class TrackSlip:
    """A slip phase of one track (:class:`~taxelkit.smart.slip.Slip` in recording frames, timed).

    Attributes
    ----------
    kind : str
        What slipped (``"area slides"``, ``"line slides along itself"``).
    first_frame, detected_frame : int
        Estimated start; frame at which it was decided.
    last_frame : int or None
        Estimated end; None while it goes on.
    t_start_s, t_detected_s : float, s
    t_end_s : float or None, s
    """

    kind: str
    first_frame: int
    detected_frame: int
    last_frame: int | None
    t_start_s: float
    t_detected_s: float
    t_end_s: float | None

    def to_json(self) -> dict[str, Any]:
        """JSON types (the ``slips`` entries of an ``objects`` record)."""
        return {
            "kind": self.kind,
            "first_frame": self.first_frame,
            "last_frame": self.last_frame,
            "detected_frame": self.detected_frame,
            "t_start_s": self.t_start_s,
            "t_end_s": self.t_end_s,
            "t_detected_s": self.t_detected_s,
        }


@dataclass(frozen=True, eq=False)
class ObjectVerdict:
    """What one track concluded.

    Attributes
    ----------
    track : int
    first_frame, last_frame : int
        Frames of its first and last region (birth and last sighting).
    first_t_s, last_t_s : float, s
    identified : str or None
        The object, ``"unknown"``, or None (undecided).
    candidates : tuple of str
        Objects not eliminated.
    verdict : Verdict
        Why.
    tactemes : tuple of (str, int, float)
        Level 3 tactemes with their frame and time, s.
    accepted : bool
        False if no contact class was ever accepted (a track shorter than the
        debounce): nothing was concluded.
    slips : tuple of TrackSlip
        The track's slip phases.
    """

    track: int
    first_frame: int
    last_frame: int
    first_t_s: float
    last_t_s: float
    identified: str | None
    candidates: tuple[str, ...]
    verdict: Verdict
    tactemes: tuple[tuple[str, int, float], ...]
    accepted: bool
    slips: tuple[TrackSlip, ...] = ()

    def outcome_text(self) -> str:
        """The outcome in words: the object, "not identified: slid", "unknown" or undecided."""
        if self.verdict.reason == SLID:
            return "not identified: slid"
        if self.identified is None:
            return f"undecided among {', '.join(self.candidates)}"
        return str(self.identified)

    def summary(self) -> str:
        """One line: the track, its span and its outcome."""
        span = (
            f"frames {self.first_frame}-{self.last_frame} "
            f"({self.first_t_s:.3f}-{self.last_t_s:.3f} s)"
        )
        if not self.accepted:
            outcome = "no contact accepted (too short)"
        elif self.verdict.reason == SLID or self.identified is None:
            outcome = self.outcome_text()
        else:
            outcome = f"identified {self.identified}"
        slipped = f"; {len(self.slips)} slip phase(s)" if self.slips else ""
        return f"object {self.track}: {span}: {outcome}{slipped}"

    def to_json(self) -> dict[str, Any]:
        """JSON types (the ``objects`` entries of ``taxelkit recognize --json``)."""
        return {
            "track": self.track,
            "first_frame": self.first_frame,
            "last_frame": self.last_frame,
            "first_t_s": self.first_t_s,
            "last_t_s": self.last_t_s,
            "accepted": self.accepted,
            "identified": self.identified,
            "candidates": list(self.candidates),
            "why": self.verdict.to_json(),
            "tactemes": [{"name": n, "frame": f, "t_s": t} for n, f, t in self.tactemes],
            "slips": [s.to_json() for s in self.slips],
        }


@dataclass(frozen=True, eq=False)
class ObjectRecognition:
    """Every track's verdict and every event.

    Attributes
    ----------
    objects : tuple of ObjectVerdict
        One per track, by track number.
    events : tuple of TrackedEvent
        Tracker and recogniser events, by track; in a track the recogniser's
        in the order they were found (a tacteme can be found after the frame
        it names), the tracker's placed by frame among them, the death last.
    n_frames : int
    track_map : (T, rows, cols) int16 or None
        The track of every contact taxel (-1 off contact), when kept.
    """

    objects: tuple[ObjectVerdict, ...]
    events: tuple[TrackedEvent, ...]
    n_frames: int
    track_map: NDArray[np.int16] | None = None

    def to_json(self) -> dict[str, Any]:
        """``objects`` and ``track_events`` as JSON types."""
        return json_doc(self.json_parts())

    def json_parts(self) -> list[tuple[str, Any]]:
        """The keys and values of :meth:`to_json`, the lists as iterators (to stream them)."""
        return [
            ("n_frames", self.n_frames),
            ("objects", (o.to_json() for o in self.objects)),
            ("track_events", (e.to_json() for e in self.events)),
        ]


def interleaved(
    recogniser_events: list[TrackedEvent], tracker_events: list[TrackedEvent]
) -> list[TrackedEvent]:
    """Events by track; in a track, the recogniser's in the order found, the tracker's by frame.

    A Level 3 tacteme is reported when it is found, which can be after the
    frame it names, so the recogniser's events are not re-sorted by frame.
    """
    found: dict[int, list[TrackedEvent]] = {}
    tracked: dict[int, list[TrackedEvent]] = {}
    for events, by_track in ((recogniser_events, found), (tracker_events, tracked)):
        for e in events:  # each track's events in their order (one pass: a day has many tracks)
            by_track.setdefault(e.track, []).append(e)
    out: list[TrackedEvent] = []
    for tid in sorted(found.keys() | tracked.keys()):
        mine = tracked.get(tid, [])
        i = 0
        for e in found.get(tid, []):
            while i < len(mine) and mine[i].kind != "death" and mine[i].frame <= e.frame:
                out.append(mine[i])
                i += 1
            out.append(e)
        out.extend(mine[i:])
    return out
