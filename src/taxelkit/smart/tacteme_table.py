"""Level 4 data: which objects each tacteme rules out (paper 001, Table 1).

The marks of the paper's Table 1 were lost in the copy we have; this table is
reconstructed from the kinematics of rolling without slip (SEED-NOTES) and
checked against the simulator (``tests/smart/test_table_check.py`` and
``taxelkit reproduce tacteme-table``). Every row carries its reason.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

__all__ = [
    "ALL_ROWS",
    "FACE_ROWS",
    "FACE_TACTEMES",
    "OBJECTS",
    "TABLE",
    "Tacteme",
    "TactemeRow",
    "eliminated_by",
]

#: The six objects of paper 001, in the order used everywhere (taxelkit solid names).
OBJECTS: tuple[str, ...] = (
    "sphere",
    "cylinder",
    "cube",
    "cone",
    "truncated-cone",
    "tetrahedron",
)


class Tacteme(enum.StrEnum):
    """Significant tactile images or transitions (paper 001, Level 3, Table 1)."""

    PC = "PC"
    LC = "LC"
    AC = "AC"
    PC_MOVES = "PC moves"
    PC_ORTHOGONAL_TURN = "PC takes an orthogonal turn"
    LCM = "LCM"
    AC_MOVES = "AC moves"
    AC_ROTATES = "AC rotates"
    LCMP = "LCMP"
    LCMT = "LCMT"
    LCMT_ABOUT_END = "LCMT about one end"
    LCMT_ARC = "LCMT in an arc"
    LC_TO_AC = "LC -> AC"
    AC_TO_LC = "AC -> LC"
    LC_AC_LC_SQUARE = "LC -> AC -> LC (parallel or 90 deg)"
    LC_AC_LC_TRIANGLE = "LC -> AC -> LC (60 or 120 deg)"
    LC_SLIDES = "LC slides along itself"
    LC_SPINS = "LC spins about its middle"
    AC_COMPACT = "AC compact"
    AC_ELONGATED = "AC elongated"
    AC_TRIANGULAR = "AC triangular"
    AC_ELONGATED_TRIANGULAR = "AC elongated triangular"
    AC_OVER = "AC -> LC -> AC onto another face"


@dataclass(frozen=True)
class TactemeRow:
    """One row of the table.

    Attributes
    ----------
    tacteme : Tacteme
    eliminates : frozenset of str
        Objects that cannot produce the tacteme when rolling without slip.
    reason : str
        Why.
    """

    tacteme: Tacteme
    eliminates: frozenset[str]
    reason: str


def _all_but(*keep: str) -> frozenset[str]:
    return frozenset(o for o in OBJECTS if o not in keep)


#: The tacteme-object table (paper 001, Table 1, reconstructed).
TABLE: tuple[TactemeRow, ...] = (
    TactemeRow(
        Tacteme.PC,
        frozenset(),
        "a sphere always; a cylinder, cone or truncated cone tilted on a rim; a cube or "
        "tetrahedron on a vertex; a cone on its apex",
    ),
    TactemeRow(
        Tacteme.LC,
        frozenset({"sphere"}),
        "straight generators (cylinder, cone, truncated cone) and edges (cube, tetrahedron); "
        "a sphere touches in a point",
    ),
    TactemeRow(
        Tacteme.AC,
        frozenset({"sphere"}),
        "flat faces: the ends of a cylinder and cone, both faces of a truncated cone, the "
        "faces of a cube and tetrahedron",
    ),
    TactemeRow(
        Tacteme.PC_MOVES,
        frozenset({"cube", "tetrahedron"}),
        "a rolling sphere, or a round body rolling on a rim; a vertex cannot roll",
    ),
    TactemeRow(
        Tacteme.PC_ORTHOGONAL_TURN,
        _all_but("sphere"),
        "only a sphere can change its rolling direction sharply",
    ),
    TactemeRow(
        Tacteme.LCM,
        frozenset({"sphere", "cube", "tetrahedron"}),
        "a curved side rolls (cylinder, cone, truncated cone); an edge can only pivot",
    ),
    TactemeRow(Tacteme.AC_MOVES, frozenset(OBJECTS), "a face cannot move without sliding"),
    TactemeRow(Tacteme.AC_ROTATES, frozenset(OBJECTS), "spinning on a face is sliding too"),
    TactemeRow(
        Tacteme.LC_SLIDES,
        frozenset(OBJECTS),
        "a rolling line moves across itself; moving along itself is sliding (beyond paper 001)",
    ),
    TactemeRow(
        Tacteme.LC_SPINS,
        frozenset(OBJECTS),
        "a rolling line turns about a point at or beyond its end (a cone's apex, a truncated"
        " cone's virtual apex); turning about its middle is spinning (beyond paper 001)",
    ),
    TactemeRow(Tacteme.LCMP, _all_but("cylinder"), "only a cylinder rolls in a straight line"),
    TactemeRow(
        Tacteme.LCMT,
        frozenset({"sphere", "cylinder", "cube", "tetrahedron"}),
        "a cone and a truncated cone roll in circles",
    ),
    TactemeRow(
        Tacteme.LCMT_ABOUT_END,
        _all_but("cone"),
        "the cone's contact line turns about its apex, which stays on the sensor",
    ),
    TactemeRow(
        Tacteme.LCMT_ARC,
        _all_but("truncated-cone"),
        "the truncated cone's line turns about its virtual apex, beyond the line's end",
    ),
    TactemeRow(
        Tacteme.LC_TO_AC,
        frozenset({"sphere", "cylinder", "cone", "truncated-cone"}),
        "a polyhedron tips from an edge onto a face; a round body passes through a rim "
        "point (PC) between its side and a flat face",
    ),
    TactemeRow(
        Tacteme.AC_TO_LC,
        frozenset({"sphere", "cylinder", "cone", "truncated-cone"}),
        "a polyhedron tips from a face onto an edge; a round body passes through a rim point",
    ),
    TactemeRow(
        Tacteme.LC_AC_LC_SQUARE,
        _all_but("cube"),
        "the two edges of a square face are parallel or at 90 deg",
    ),
    TactemeRow(
        Tacteme.LC_AC_LC_TRIANGLE,
        _all_but("tetrahedron"),
        "the two edges of a triangular face are at 60 (or 120) deg",
    ),
)

#: The shape classes of a held face (beyond paper 001; emitted only with
#: ``TactemeConfig(face_shapes=True)``, see :mod:`taxelkit.smart.face_shapes`).
FACE_TACTEMES: tuple[Tacteme, ...] = (
    Tacteme.AC_COMPACT,
    Tacteme.AC_ELONGATED,
    Tacteme.AC_TRIANGULAR,
    Tacteme.AC_ELONGATED_TRIANGULAR,
)

#: Rows of the face tactemes (the shape classes and tipping over onto another
#: face) for the six objects (beyond paper 001).
FACE_ROWS: tuple[TactemeRow, ...] = (
    TactemeRow(
        Tacteme.AC_COMPACT,
        frozenset({"sphere"}),
        "a held face as wide as it is long and centrally symmetric: a cube's square, the "
        "discs of a cylinder, cone and truncated cone; and a tetrahedron's triangle of a few "
        "dozen taxels, which the taxel grid can make look symmetric",
    ),
    TactemeRow(
        Tacteme.AC_ELONGATED,
        frozenset(OBJECTS),
        "a held face at least 1.6 times as long as it is wide (a rectangle, an ellipse): none "
        "of the six has one",
    ),
    TactemeRow(
        Tacteme.AC_TRIANGULAR,
        _all_but("tetrahedron"),
        "a held face whose second moments are those of a triangle (the tetrahedron's faces)",
    ),
    TactemeRow(
        Tacteme.AC_ELONGATED_TRIANGULAR,
        frozenset(OBJECTS),
        "a held face both elongated and triangular (a tall isosceles triangle): none of the six",
    ),
    TactemeRow(
        Tacteme.AC_OVER,
        frozenset({"sphere", "cylinder", "cone", "truncated-cone"}),
        "a polyhedron tips over an edge from one face onto the next (the second face lies "
        "across the edge from the first); a round body has no edge between two faces",
    ),
)

#: Table 1 and the face-shape rows.
ALL_ROWS: tuple[TactemeRow, ...] = TABLE + FACE_ROWS

_BY_TACTEME = {row.tacteme: row for row in ALL_ROWS}


def eliminated_by(tacteme: Tacteme) -> frozenset[str]:
    """Objects ruled out by ``tacteme``."""
    return _BY_TACTEME[tacteme].eliminates
