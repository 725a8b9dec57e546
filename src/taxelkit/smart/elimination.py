"""Level 4 of the smart sensor: recognition by elimination (paper 001).

Before first contact every object is possible; each tacteme removes the
objects that cannot produce it (:data:`~taxelkit.smart.tacteme_table.TABLE`).
One candidate left: identified. None left: "unknown" (sliding, or a shape
outside the set). Lifted off before that: the candidates left. The state
resets when the object is lifted off, ready for the next one. A learnt object
left alone only through tactemes it produces rarely
(:attr:`~taxelkit.smart.object_table.ObjectRow.rare`) is not named: "doubt".
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from taxelkit.smart.tacteme_table import OBJECTS, Tacteme, eliminated_by

if TYPE_CHECKING:
    from taxelkit.smart.object_table import ObjectTable

__all__ = ["SLID", "UNKNOWN", "Eliminator", "Event", "Verdict", "explain"]

#: Outcome when every candidate has been eliminated.
UNKNOWN = "unknown"
#: Why a contact that slipped was not identified ("not identified: slid").
SLID = "slid"


@dataclass(frozen=True)
class Event:
    """Something the smart sensor reports as it happens.

    Attributes
    ----------
    kind : str
        ``"contact"`` (a contact class accepted), ``"tacteme"``,
        ``"candidates"`` (the candidate list changed), ``"identified"``,
        ``"doubt"`` (the only candidate left explains the tactemes only
        through ones it produces rarely: not named, an earlier name of it
        withdrawn; value: the object),
        ``"unknown"``, ``"lifted"`` (contact ended), ``"slip"`` and
        ``"slip-end"`` (a slip phase began, ended; value: what slipped, see
        :mod:`taxelkit.smart.slip`) or ``"withheld"`` (a tacteme seen while
        slipping, or one only slip produces: not used for elimination).
    frame : int
        Frame index at which it happened (a slip: its estimated first and
        last frame, reported when decided).
    value : str or tuple of str
        The class name, tacteme name, identity, or candidates left.
    """

    kind: str
    frame: int
    value: str | tuple[str, ...]


@dataclass
class Eliminator:
    """Mutable Level 4 state: the candidate objects of the current contact.

    With an object table (:class:`~taxelkit.smart.object_table.ObjectTable`),
    an object whose row lies inside another candidate's stays a candidate
    until the tactemes against it were seen ``superset_evidence`` times
    (:meth:`~taxelkit.smart.object_table.ObjectTable.doubtful`).
    """

    objects: tuple[str, ...] = OBJECTS
    candidates: tuple[str, ...] = field(default=OBJECTS)
    identified: str | None = None
    #: Rows by object (None: Table 1 of paper 001, the six objects).
    table: ObjectTable | None = None
    #: Candidates of plain elimination, and how often each tacteme was seen.
    strict: tuple[str, ...] = field(default=OBJECTS)
    seen: dict[Tacteme, int] = field(default_factory=dict)
    #: Tactemes of the contact, and the only candidate not named for its rare ones.
    kinds: set[Tacteme] = field(default_factory=set)
    doubted: str | None = None

    @classmethod
    def for_table(cls, table: ObjectTable | None) -> Eliminator:
        """Start with every object of ``table`` (None: the six of paper 001)."""
        if table is None:
            return cls()
        return cls(table.objects, table.objects, None, table, table.objects)

    def reset(self) -> None:
        """Forget the current object (after lift-off)."""
        self.candidates = self.strict = tuple(self.objects)
        self.identified = None
        self.seen = {}
        self.kinds = set()
        self.doubted = None

    def apply(self, tacteme: Tacteme, frame: int) -> list[Event]:
        """Eliminate what ``tacteme`` rules out; report what changed."""
        events = [Event("tacteme", frame, tacteme.value)]
        gone = eliminated_by(tacteme) if self.table is None else self.table.eliminated_by(tacteme)
        self.strict = tuple(c for c in self.strict if c not in gone)
        left = self.strict
        if self.table is not None and self.table.superset_evidence > 1:
            self.seen[tacteme] = self.seen.get(tacteme, 0) + 1
            doubt = self.table.doubtful(left, self.seen)
            left = tuple(c for c in self.objects if c in left or c in doubt)
        self.kinds.add(tacteme)
        rare = len(left) == 1 and self._rare(left[0])
        if left != self.candidates:
            self.candidates = left
            events.append(Event("candidates", frame, left))
            if len(left) == 1 and self.identified != left[0] and not rare:
                self.identified = left[0]
                events.append(Event("identified", frame, left[0]))
            elif not left and self.identified != UNKNOWN:
                self.identified = UNKNOWN
                events.append(Event("unknown", frame, UNKNOWN))
        if rare and self.doubted != left[0]:
            self.doubted = left[0]
            if self.identified == left[0]:
                self.identified = None
            events.append(Event("doubt", frame, left[0]))
        return events

    def _rare(self, name: str) -> bool:
        """Tactemes ``name`` produces only rarely were seen in this contact."""
        return self.table is not None and bool(self.table.rare_seen(name, self.kinds))

    @property
    def outcome(self) -> str | None:
        """The identity, ``"unknown"``, or None while undecided."""
        if len(self.candidates) == 1:
            return None if self.doubted == self.candidates[0] else self.candidates[0]
        if not self.candidates:
            return UNKNOWN
        return None


@dataclass(frozen=True)
class Verdict:
    """Why the recogniser concluded what it did, for one contact.

    Attributes
    ----------
    outcome : str or None
        The object, ``"unknown"``, or None (undecided).
    candidates : tuple of str
        Objects left.
    eliminated : tuple of (object, tacteme, frame, reason)
        For every object ruled out, the first tacteme that ruled it out, the
        frame it was seen at and the table's reason.
    deciders : tuple of (tacteme, leaves, reason)
        When undecided: each tacteme that would split the candidates, the
        objects it would leave, and the motion that produces it.
    slid : bool
        The contact slipped (:mod:`taxelkit.smart.slip`): when no object is
        identified, the reason is the slip.
    rare : tuple of str
        Tactemes seen that the only candidate left produces only rarely
        (:attr:`~taxelkit.smart.object_table.ObjectRow.rare`): it is not
        named (empty otherwise).
    unread_gap_s : float or None
        The contact's frames came this far apart, s, beyond
        :attr:`~taxelkit.smart.tactemes.TactemeConfig.max_motion_gap_s`: the
        motion tactemes seen in them were not read (None: every one was).
    passed_over : tuple of (int, int)
        Later contacts, ``(first frame, frame lifted)``, too brief to rule out
        any object (:attr:`~taxelkit.smart.tactemes.TactemeConfig.blip_s`):
        this verdict is that of the contact before them.
    still_on : bool
        The last of ``passed_over`` was still on when the recording ended,
        its second frame the recording's last: it began less than ``blip_s``
        before the end and ruled out nothing so far.
    """

    outcome: str | None
    candidates: tuple[str, ...]
    eliminated: tuple[tuple[str, str, int, str], ...]
    deciders: tuple[tuple[str, tuple[str, ...], str], ...]
    slid: bool = False
    rare: tuple[str, ...] = ()
    unread_gap_s: float | None = None
    passed_over: tuple[tuple[int, int], ...] = ()
    still_on: bool = False

    @property
    def reason(self) -> str | None:
        """Why nothing was identified: ``"slid"``, ``"ruled out"``, ``"undecided"``; else None."""
        if self.outcome not in (None, UNKNOWN):
            return None
        if self.slid:
            return SLID
        return "ruled out" if self.outcome == UNKNOWN else "undecided"

    def sentence(self) -> str:
        """One line a user can read."""
        if not self.passed_over:
            return self._sentence()
        spans = ", ".join(f"{a}-{b}" for a, b in self.passed_over)
        end = "; the last still on when the recording ended" if self.still_on else ""
        return (
            f"{self._sentence()} (the contact before the brief one(s) at frames {spans}, "
            f"which ruled out nothing{end})"
        )

    def _sentence(self) -> str:
        if self.reason == SLID:
            left = (
                f"; its rolling phases leave {', '.join(self.candidates)}"
                if self.candidates
                else "; every object was ruled out"
            )
            return "not identified: slid" + left
        if self.outcome == UNKNOWN:
            last = self.eliminated[-1] if self.eliminated else None
            tail = f"; last: {last[1]} at frame {last[2]} ({last[3]})" if last else ""
            return "unknown: every object was ruled out" + tail
        if self.outcome is not None:
            return f"{self.outcome}: the only object that can produce every tacteme seen"
        if self.rare:
            return (
                f"undecided: {self.candidates[0]} is the only object left, but only through "
                f"{', '.join(self.rare)}, which it produces only rarely (not named)"
            )
        options = "; ".join(f"{t} would leave {', '.join(left)}" for t, left, _ in self.deciders)
        sparse = (
            f"; its frames came {self.unread_gap_s:.3g} s apart, too far apart to follow its "
            "motion (the motion tactemes seen were not read)"
            if self.unread_gap_s is not None
            else ""
        )
        return f"undecided between {', '.join(self.candidates)}{sparse}" + (
            f"; {options}" if options else ""
        )

    def to_json(self) -> dict[str, object]:
        """Plain JSON types."""
        return {
            "outcome": self.outcome,
            "candidates": list(self.candidates),
            "slid": self.slid,
            "reason": self.reason,
            "sentence": self.sentence(),
            "eliminated": [
                {"object": o, "tacteme": t, "frame": f, "reason": r}
                for o, t, f, r in self.eliminated
            ],
            "deciders": [
                {"tacteme": t, "leaves": list(left), "reason": r} for t, left, r in self.deciders
            ],
            "rare": list(self.rare),
            "unread_gap_s": self.unread_gap_s,
            "passed_over": [
                {
                    "first_frame": a,
                    "lifted_frame": None if self.still_on and k == len(self.passed_over) - 1 else b,
                    "last_frame": b,
                }
                for k, (a, b) in enumerate(self.passed_over)
            ],
            "still_on": self.still_on,
        }


def explain(
    tactemes: list[tuple[str, int]],
    *,
    objects: tuple[str, ...] = OBJECTS,
    slid: bool = False,
    table: ObjectTable | None = None,
    unread_gap_s: float | None = None,
    passed_over: tuple[tuple[int, int], ...] = (),
    still_on: bool = False,
) -> Verdict:
    """The verdict and its reasons from the tactemes of one contact, in order.

    Parameters
    ----------
    tactemes : list of (name, frame)
    objects : tuple of str
        The objects the contact began with.
    slid : bool
        The contact slipped.
    table : ObjectTable, optional
        Rows by object (default: Table 1, the six objects of paper 001).
    unread_gap_s : float, optional
        The contact's frames were too sparse for its motion tactemes to be
        read (:attr:`Verdict.unread_gap_s`).
    passed_over : tuple of (int, int)
        Later contacts passed over as too brief (:attr:`Verdict.passed_over`).
    still_on : bool
        The last of them was still on at the recording's end (:attr:`Verdict.still_on`).
    """
    from taxelkit.smart.tacteme_table import ALL_ROWS, TABLE, TactemeRow

    rows: tuple[TactemeRow, ...] = TABLE
    if table is not None:
        objects = table.objects
        rows = tuple(
            TactemeRow(t, table.eliminated_by(t), table.reason(t))
            for t in (r.tacteme for r in ALL_ROWS)
        )
    # reasons of every row (face shapes included); deciders from ``rows`` only
    reason = {row.tacteme.value: row.reason for row in (ALL_ROWS if table is None else rows)}
    gone_by = {row.tacteme.value: row.eliminates for row in rows}
    left = list(objects)
    eliminated: list[tuple[str, str, int, str]] = []
    for name, frame in tactemes:
        gone = gone_by[name] if name in gone_by else eliminated_by(Tacteme(name))
        for o in [o for o in left if o in gone]:
            eliminated.append((o, name, frame, reason[name]))
            left.remove(o)
    if table is not None and table.superset_evidence > 1:  # as Eliminator.apply
        seen: dict[Tacteme, int] = {}
        for name, _ in tactemes:
            seen[Tacteme(name)] = seen.get(Tacteme(name), 0) + 1
        doubt = set(table.doubtful(left, seen))
        left = [o for o in objects if o in left or o in doubt]
        eliminated = [e for e in eliminated if e[0] not in doubt]
    outcome = left[0] if len(left) == 1 else (UNKNOWN if not left else None)
    rare: tuple[str, ...] = ()
    if table is not None and outcome not in (None, UNKNOWN):  # as Eliminator.apply
        rare = tuple(t.value for t in table.rare_seen(left[0], {Tacteme(n) for n, _ in tactemes}))
        outcome = None if rare else outcome
    deciders: list[tuple[str, tuple[str, ...], str]] = []
    if outcome is None:
        for row in rows:
            keep = tuple(o for o in left if o not in row.eliminates)
            if keep and len(keep) < len(left):
                deciders.append((row.tacteme.value, keep, row.reason))
    return Verdict(
        outcome,
        tuple(left),
        tuple(eliminated),
        tuple(deciders),
        bool(slid),
        rare,
        unread_gap_s,
        passed_over,
        bool(still_on and passed_over),
    )
