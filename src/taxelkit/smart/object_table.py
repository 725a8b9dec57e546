"""Object tables for Level 4: the six objects of paper 001 and objects learnt from meshes.

Table 1 of paper 001 is kept as data by tacteme
(:data:`~taxelkit.smart.tacteme_table.TABLE`: which objects each tacteme rules
out). An :class:`ObjectTable` holds the same knowledge by object: the set of
tactemes each object can produce when it rolls without slip, with a reason
for each. A tacteme rules out every object whose row lacks it. The six rows
of paper 001 (:data:`PAPER_OBJECTS`) are read off Table 1 and the face-shape
rows (:data:`~taxelkit.smart.tacteme_table.FACE_ROWS`); rows of new objects
come from their meshes (``taxelkit learn-object``, :mod:`taxelkit.learn`) and
are stored in a *user object table* file that ``taxelkit recognize --objects``
reads beside the six. The recogniser reads the file and never the world.

User object table file (JSON, UTF-8)
------------------------------------
.. code-block:: json

    {"format": "taxelkit-object-table", "version": 1,
     "objects": [{"name": "hex-prism",
                  "tactemes": ["PC", "LC", "AC", "LC -> AC", "..."],
                  "reasons": {"LC": "the prism's edges", "...": "..."},
                  "rare": ["LCMT"],
                  "source": "hex_prism.stl",
                  "checked": {"trials": 12, "seen": ["PC", "..."], "outside_row": []}}]}

``name``: lowercase letters, digits and ``-``, not one of the six;
``tactemes``: names of :class:`~taxelkit.smart.tacteme_table.Tacteme`;
``reasons``: optional, by tacteme; ``rare``: optional (:attr:`ObjectRow.rare`);
``source`` and ``checked``: optional free records (where the row came from,
what the simulation check saw). Unknown keys are ignored (a reader older than
``rare`` treats those as ordinary); a newer ``version`` is refused.
"""

from __future__ import annotations

import json
import re
from collections.abc import Collection, Iterable, Mapping
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import Any

from taxelkit.errors import InputError, RecordingAccessError, RecordingNotFoundError
from taxelkit.smart.tacteme_table import ALL_ROWS, OBJECTS, Tacteme

__all__ = [
    "FORMAT",
    "PAPER_OBJECTS",
    "VERSION",
    "ObjectRow",
    "ObjectTable",
    "Overlap",
    "dumps",
    "read_object_table",
    "table_from_json",
]

#: ``format`` of a user object table file.
FORMAT = "taxelkit-object-table"
#: Schema version written (and the newest read).
VERSION = 1

_NAME = re.compile(r"^[a-z0-9][a-z0-9-]{0,47}$")


@dataclass(frozen=True)
class ObjectRow:
    """What one object can produce.

    Attributes
    ----------
    name : str
    tactemes : frozenset of Tacteme
        Tactemes the object can produce rolling without slip.
    reasons : tuple of (Tacteme, str)
        Why, by tacteme (may be partial).
    source : str
        Where the row came from (``"paper 001, Table 1"``, a mesh file).
    checked : dict
        What a simulation check saw (free record; empty if none).
    rare : frozenset of Tacteme
        Tactemes of ``tactemes`` the object produced only rarely (its learning
        check saw them in a roll or two; not from its geometry). Seeing one
        does not rule it out, but it is never named on their strength
        (:meth:`ObjectTable.rare_seen`): the reading is as likely another
        object's stray tacteme. Empty for the six of paper 001.

    Raises
    ------
    InputError
        If ``rare`` is not part of ``tactemes``.
    """

    name: str
    tactemes: frozenset[Tacteme]
    reasons: tuple[tuple[Tacteme, str], ...] = ()
    source: str = ""
    checked: Mapping[str, Any] = field(default_factory=dict, compare=False, hash=False)
    rare: frozenset[Tacteme] = frozenset()

    def __post_init__(self) -> None:
        if not self.rare <= self.tactemes:
            extra = sorted(t.value for t in self.rare - self.tactemes)
            raise InputError(f"{self.name}: rare tactemes must be in its row; not: {extra}")

    def reason(self, tacteme: Tacteme) -> str:
        """The reason recorded for ``tacteme`` (empty if none)."""
        return dict(self.reasons).get(tacteme, "")

    def to_json(self) -> dict[str, Any]:
        """Plain JSON types (tactemes in :class:`Tacteme` order; ``rare`` only if any)."""
        order = [t for t in Tacteme if t in self.tactemes]
        out: dict[str, Any] = {
            "name": self.name,
            "tactemes": [t.value for t in order],
            "reasons": {t.value: r for t, r in self.reasons},
            "source": self.source,
            "checked": dict(self.checked),
        }
        if self.rare:
            out["rare"] = [t.value for t in Tacteme if t in self.rare]
        return out


@dataclass(frozen=True)
class Overlap:
    """Two objects the tactemes cannot always tell apart.

    Attributes
    ----------
    first, second : str
    identical : bool
        Same rows: every contact of one could be the other.
    sentence : str
        Which and why.
    """

    first: str
    second: str
    identical: bool
    sentence: str


def _paper_rows() -> tuple[ObjectRow, ...]:
    rows = []
    for obj in OBJECTS:
        can = [r for r in ALL_ROWS if obj not in r.eliminates]
        rows.append(
            ObjectRow(
                obj,
                frozenset(r.tacteme for r in can),
                tuple((r.tacteme, r.reason) for r in can),
                "paper 001, Table 1 (reconstructed) and the face-shape rows",
            )
        )
    return tuple(rows)


@dataclass(frozen=True)
class ObjectTable:
    """Rows of the objects Level 4 starts with, in order.

    Parameters
    ----------
    rows : tuple of ObjectRow
        Names unique.
    superset_evidence : int
        Readings it takes to rule out an object whose row lies inside another
        candidate's (a sphere inside a capsule's, a cube inside a square
        pyramid's) by tactemes that larger object makes: with fewer, the
        smaller object stays a candidate (:func:`doubtful`). One spurious
        reading of an imperfect array (a sphere's contact read as a line for
        a moment, a cube's face that loses a corner and reads triangular)
        otherwise names the larger object, where the six-object table ends
        "unknown". 1: plain elimination (paper 001). Set with the robustness
        recordings of seed 0 through the ten-object table (both engines,
        every rate and imperfection): spheres named capsule 8 -> 0 of 3,200,
        cubes named square pyramid 11 -> 3; on ``new-objects`` (clean
        sensors) capsules identified 97 -> 88, hexagonal prisms 61 -> 58,
        nothing else changed (3: cubes 11 -> 0, but capsules 97 -> 64).
        Held-out seed 11: cubes named square pyramid 2 -> 0; ``new-objects``
        capsules 98 -> 92, hexagonal prisms 66 -> 60, no wrong name either way.

    Raises
    ------
    InputError
        If two rows share a name, or ``superset_evidence`` is below 1.
    """

    rows: tuple[ObjectRow, ...]
    superset_evidence: int = 2

    def __post_init__(self) -> None:
        names = [r.name for r in self.rows]
        dup = sorted({n for n in names if names.count(n) > 1})
        if dup:
            raise InputError(f"object table names must be unique; repeated: {', '.join(dup)}")
        if int(self.superset_evidence) < 1:
            raise InputError(f"superset_evidence must be >= 1, got {self.superset_evidence!r}")

    @property
    def objects(self) -> tuple[str, ...]:
        """Names, in order."""
        return tuple(r.name for r in self.rows)

    def row(self, name: str) -> ObjectRow:
        """The row of ``name`` (KeyError if absent)."""
        for r in self.rows:
            if r.name == name:
                return r
        raise KeyError(name)

    def eliminated_by(self, tacteme: Tacteme) -> frozenset[str]:
        """Objects whose row lacks ``tacteme``."""
        return frozenset(r.name for r in self.rows if tacteme not in r.tactemes)

    def reason(self, tacteme: Tacteme) -> str:
        """Why ``tacteme`` rules objects out: who can produce it, from the rows."""
        makers = [r for r in self.rows if tacteme in r.tactemes]
        if not makers:
            return "no object of the table can produce it rolling without slip"
        parts = [f"{r.name} ({r.reason(tacteme)})" if r.reason(tacteme) else r.name for r in makers]
        return "only " + "; ".join(parts) + " can produce it"

    def rare_seen(self, name: str, seen: Collection[Tacteme]) -> tuple[Tacteme, ...]:
        """The tactemes of ``seen`` that ``name`` produces only rarely (:attr:`ObjectRow.rare`).

        Non-empty: ``name`` is not named when it is the only candidate left.
        """
        rare = self.row(name).rare
        return tuple(t for t in Tacteme if t in rare and t in seen)

    def plus(self, extra: Iterable[ObjectRow]) -> ObjectTable:
        """This table with ``extra`` rows appended."""
        return ObjectTable((*self.rows, *extra), self.superset_evidence)

    def doubtful(self, strict: Collection[str], seen: Mapping[Tacteme, int]) -> tuple[str, ...]:
        """Objects ruled out on too few readings to leave a larger one (see ``superset_evidence``).

        Parameters
        ----------
        strict : collection of str
            The candidates plain elimination leaves.
        seen : mapping Tacteme -> int
            How often each tacteme of the contact was seen.

        Returns
        -------
        tuple of str
            Objects outside ``strict`` whose row lies inside a row of
            ``strict`` and lacks tactemes seen fewer than
            ``superset_evidence`` times in all, in table order.
        """
        left = [self.row(n).tactemes for n in strict]
        out = []
        for r in self.rows:
            if r.name in strict:
                continue
            against = sum(k for t, k in seen.items() if t not in r.tactemes)
            if against < self.superset_evidence and any(r.tactemes < b for b in left):
                out.append(r.name)
        return tuple(out)

    def overlaps(self) -> tuple[Overlap, ...]:
        """Pairs where one object's row holds all of another's (the latter never identified)."""
        out = []
        for i, a in enumerate(self.rows):
            for b in self.rows[i + 1 :]:
                if a.tactemes == b.tactemes:
                    out.append(
                        Overlap(
                            a.name,
                            b.name,
                            True,
                            f"{a.name} and {b.name} cannot be told apart: both can produce "
                            f"exactly the same tactemes",
                        )
                    )
                    continue
                for small, big in ((a, b), (b, a)):
                    if small.tactemes < big.tactemes:
                        extra = sorted(t.value for t in big.tactemes - small.tactemes)
                        out.append(
                            Overlap(
                                small.name,
                                big.name,
                                False,
                                f"{small.name} is never identified beside {big.name}: every "
                                f"tacteme {small.name} produces, {big.name} produces too "
                                f"({big.name} alone also makes {', '.join(extra)})",
                            )
                        )
        return tuple(out)

    def to_json(self) -> dict[str, Any]:
        """The file's JSON document."""
        return {"format": FORMAT, "version": VERSION, "objects": [r.to_json() for r in self.rows]}


#: The six objects of paper 001 as an object table.
PAPER_OBJECTS = ObjectTable(_paper_rows())


def _row_from_json(item: object, where: str) -> ObjectRow:
    if not isinstance(item, dict):
        raise InputError(f"{where}: must be an object, got {type(item).__name__}")
    name = item.get("name")
    if not isinstance(name, str) or not _NAME.match(name):
        raise InputError(
            f"{where}: name must be 1-48 lowercase letters, digits or '-', got {name!r}"
        )
    names = item.get("tactemes")
    if not isinstance(names, list) or not all(isinstance(n, str) for n in names):
        raise InputError(f"{where} ({name}): tactemes must be a list of tacteme names")
    known = {t.value: t for t in Tacteme}
    bad = [n for n in names if n not in known]
    if bad:
        raise InputError(f"{where} ({name}): unknown tacteme(s) {bad}")
    reasons = item.get("reasons", {})
    if not isinstance(reasons, dict) or not all(
        k in known and isinstance(v, str) for k, v in reasons.items()
    ):
        raise InputError(f"{where} ({name}): reasons must map tacteme names to text")
    checked = item.get("checked", {})
    rare = item.get("rare", [])
    if not isinstance(rare, list) or not all(isinstance(n, str) and n in names for n in rare):
        raise InputError(f"{where} ({name}): rare must be a list of tactemes of the row")
    return ObjectRow(
        name,
        frozenset(known[n] for n in names),
        tuple((known[k], v) for k, v in reasons.items()),
        str(item.get("source", "")),
        checked if isinstance(checked, dict) else {},
        frozenset(known[n] for n in rare),
    )


def table_from_json(doc: object, *, where: str = "object table") -> ObjectTable:
    """The user objects of a parsed table file (without the six).

    Parameters
    ----------
    doc : object
        ``json.load`` of the file.
    where : str
        Named in error messages (the file name).

    Raises
    ------
    InputError
        One line naming ``where``, the field and what was found.
    """
    if not isinstance(doc, dict) or doc.get("format") != FORMAT:
        raise InputError(f"{where}: not a taxelkit object table (format must be {FORMAT!r})")
    version = doc.get("version")
    if not isinstance(version, int) or not 1 <= version <= VERSION:
        raise InputError(f"{where}: version must be 1..{VERSION}, got {version!r}")
    items = doc.get("objects")
    if not isinstance(items, list):
        raise InputError(f"{where}: 'objects' must be a list")
    rows = tuple(_row_from_json(item, f"{where}: objects[{i}]") for i, item in enumerate(items))
    clash = [r.name for r in rows if r.name in OBJECTS]
    if clash:
        raise InputError(f"{where}: {', '.join(clash)} is one of the six objects of paper 001")
    return ObjectTable(rows)


def dumps(table: ObjectTable) -> str:
    """The file's text (sorted keys, indented, newline at the end)."""
    return json.dumps(table.to_json(), indent=2, sort_keys=True) + "\n"


#: Largest object table file read, bytes.
MAX_TABLE_BYTES = 1 << 20


def read_object_table(path: str | PathLike[str]) -> ObjectTable:
    """Read a user object table file (the user objects, without the six).

    Raises
    ------
    RecordingNotFoundError, RecordingAccessError
        If the file is missing or unreadable.
    InputError
        If it is not a valid table (one line naming the file).
    """
    p = Path(path)
    if not p.exists():
        raise RecordingNotFoundError(f"{p}: no such object table")
    if not p.is_file():
        raise RecordingAccessError(f"{p}: not a regular file")
    if p.stat().st_size > MAX_TABLE_BYTES:
        raise InputError(f"{p}: object table larger than {MAX_TABLE_BYTES} bytes")
    try:
        doc = json.loads(p.read_text(encoding="utf-8"))
    except OSError as exc:
        raise RecordingAccessError(f"{p}: cannot read ({exc.strerror or exc})") from None
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(f"{p}: not valid JSON ({exc})") from None
    return table_from_json(doc, where=str(p))
