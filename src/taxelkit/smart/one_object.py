"""One object touched several times: Level 4 over the evidence of all its contacts.

Beyond paper 001, whose Level 4 forgets an object when it is lifted off
(:mod:`taxelkit.smart.elimination`). A robot that handles one object again
and again (puts it down on another face, rolls it another way) knows that
the contacts are of the same object, and their tactemes together may decide
what none of them decides alone: a cylinder rolled on its side is a
cylinder or a capsule until one contact shows its flat end.

:func:`contacts_of` splits a recogniser's events into contacts, each with
the tactemes that took part in elimination (the withheld ones of a slipping
contact stay out) and whether it slipped; :func:`one_object_verdict` runs
Level 4 once over the tactemes of every contact, in order, with the same
table and the same superset rule as a single contact
(:meth:`~taxelkit.smart.object_table.ObjectTable.doubtful`). A tacteme that
rules out the object in any contact rules it out for good: a spurious
reading is not forgotten at lift-off, so more contacts mean more evidence
and more chances of a misreading alike (the ``new-objects`` experiment
measures both).

The caller asserts that every contact is of one object; nothing in the
frames can check it.

Measured (the learnt ten-object table of ``new-objects`` seed 0, face
tactemes on), on the ``robustness`` recordings of seed 0 (both engines,
every rate and imperfection): five consecutive rolls of one cell handled as
one object, stopping once decided, against each roll alone. Cylinders
identified 911 of 3,200 rolls alone, 540 of 640 handled; cones and
truncated cones 640 and 636 of 640 handled, none wrong. Wrong names: cubes
named square pyramid 3 of 3,200 rolls alone, 7 of 640 handled (threshold
spread and every imperfection at once: a face that loses a corner reads
triangular, and two such readings among five handlings pass the superset
rule); cylinders and spheres named capsule 0 and 1 of 3,200 alone, 1 and 1
of 640 handled. On clean frames (``new-objects``) no object of the table
got a wrong name, handled or not, while the triangular prism, in no table,
is named square pyramid far more often handled than alone.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from taxelkit.errors import InputError
from taxelkit.smart.elimination import Event, Verdict, explain
from taxelkit.smart.tacteme_table import OBJECTS

if TYPE_CHECKING:
    from taxelkit.smart.object_results import ObjectRecognition
    from taxelkit.smart.object_table import ObjectTable

__all__ = ["ContactEvidence", "contacts_of", "one_object_verdict", "track_contacts"]


@dataclass(frozen=True)
class ContactEvidence:
    """What one contact contributed to Level 4.

    Attributes
    ----------
    tactemes : tuple of (str, int)
        Tacteme names with the frame each was seen at (of its own
        recording), in the order found; only those used for elimination.
    slid : bool
        The contact slipped (some of its tactemes may have been withheld).
    """

    tactemes: tuple[tuple[str, int], ...]
    slid: bool = False


def contacts_of(events: Iterable[Event]) -> tuple[ContactEvidence, ...]:
    """Split a recogniser's events into its contacts.

    Parameters
    ----------
    events : iterable of Event
        As :attr:`~taxelkit.smart.levels34.Recognition.events` (one object
        at a time; a contact runs from its first accepted class to its
        ``"lifted"`` event, or to the end).

    Returns
    -------
    tuple of ContactEvidence
        One per contact, in order; a contact without any tacteme is kept
        (it decided nothing).
    """
    out: list[ContactEvidence] = []
    seen: list[tuple[str, int]] | None = None
    slid = False
    for e in events:
        if e.kind == "contact" and seen is None:
            seen, slid = [], False
        elif seen is None:
            continue
        elif e.kind == "tacteme":
            seen.append((str(e.value), e.frame))
        elif e.kind in ("slip", "withheld"):
            slid = True
        elif e.kind == "lifted":
            out.append(ContactEvidence(tuple(seen), slid))
            seen = None
    if seen is not None:
        out.append(ContactEvidence(tuple(seen), slid))
    return tuple(out)


def track_contacts(objects: ObjectRecognition) -> tuple[ContactEvidence, ...]:
    """The contacts of a per-track result (:mod:`taxelkit.smart.objects`), by first frame.

    Tracks that never accepted a contact class are left out.
    """
    tracks = sorted((o for o in objects.objects if o.accepted), key=lambda o: o.first_frame)
    return tuple(
        ContactEvidence(tuple((n, f) for n, f, _ in o.tactemes), o.verdict.slid) for o in tracks
    )


def one_object_verdict(
    contacts: Sequence[ContactEvidence], *, table: ObjectTable | None = None
) -> Verdict:
    """Level 4 over every contact of one object, in order.

    Parameters
    ----------
    contacts : sequence of ContactEvidence
        At least one.
    table : ObjectTable, optional
        The object table the contacts were recognised with (default: the six
        objects of paper 001).

    Returns
    -------
    Verdict
        As for one contact; ``slid`` if any contact slipped (the reason when
        nothing is identified). Frames in ``eliminated`` are those of each
        tacteme's own contact.

    Raises
    ------
    InputError
        If ``contacts`` is empty.

    Examples
    --------
    >>> rolled = ContactEvidence((("LC", 3), ("LCMP", 40)))
    >>> one_object_verdict([rolled]).outcome
    'cylinder'
    """
    if not contacts:
        raise InputError("one_object_verdict needs at least one contact")
    tactemes = [t for c in contacts for t in c.tactemes]
    slid = any(c.slid for c in contacts)
    objects = OBJECTS if table is None else table.objects
    return explain(tactemes, objects=objects, slid=slid, table=table)
