"""Level 4 of the smart sensor: recognition by elimination (paper 001).

Before first contact every object is possible; each tacteme removes the
objects that cannot produce it (:data:`~taxelkit.smart.tacteme_table.TABLE`).
One candidate left: identified. None left: "unknown" (sliding, or a shape
outside the set). Lifted off before that: the candidates left. The state
resets when the object is lifted off, ready for the next one.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from taxelkit.smart.tacteme_table import OBJECTS, Tacteme, eliminated_by

__all__ = ["UNKNOWN", "Eliminator", "Event"]

#: Outcome when every candidate has been eliminated.
UNKNOWN = "unknown"


@dataclass(frozen=True)
class Event:
    """Something the smart sensor reports as it happens.

    Attributes
    ----------
    kind : str
        ``"contact"`` (a contact class accepted), ``"tacteme"``,
        ``"candidates"`` (the candidate list changed), ``"identified"``,
        ``"unknown"`` or ``"lifted"`` (contact ended).
    frame : int
        Frame index at which it happened.
    value : str or tuple of str
        The class name, tacteme name, identity, or candidates left.
    """

    kind: str
    frame: int
    value: str | tuple[str, ...]


@dataclass
class Eliminator:
    """Mutable Level 4 state: the candidate objects of the current contact."""

    objects: tuple[str, ...] = OBJECTS
    candidates: tuple[str, ...] = field(default=OBJECTS)
    identified: str | None = None

    def reset(self) -> None:
        """Forget the current object (after lift-off)."""
        self.candidates = tuple(self.objects)
        self.identified = None

    def apply(self, tacteme: Tacteme, frame: int) -> list[Event]:
        """Eliminate what ``tacteme`` rules out; report what changed."""
        events = [Event("tacteme", frame, tacteme.value)]
        gone = eliminated_by(tacteme)
        left = tuple(c for c in self.candidates if c not in gone)
        if left != self.candidates:
            self.candidates = left
            events.append(Event("candidates", frame, left))
            if len(left) == 1 and self.identified != left[0]:
                self.identified = left[0]
                events.append(Event("identified", frame, left[0]))
            elif not left and self.identified != UNKNOWN:
                self.identified = UNKNOWN
                events.append(Event("unknown", frame, UNKNOWN))
        return events

    @property
    def outcome(self) -> str | None:
        """The identity, ``"unknown"``, or None while undecided."""
        if len(self.candidates) == 1:
            return self.candidates[0]
        if not self.candidates:
            return UNKNOWN
        return None
