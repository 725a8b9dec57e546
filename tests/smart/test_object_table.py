"""Object tables: the six rows are Table 1, the file format, overlaps, Level 4 with a table."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from taxelkit.errors import InputError
from taxelkit.smart.elimination import Eliminator, explain
from taxelkit.smart.object_table import (
    FORMAT,
    PAPER_OBJECTS,
    ObjectRow,
    ObjectTable,
    dumps,
    read_object_table,
    table_from_json,
)
from taxelkit.smart.tacteme_table import ALL_ROWS, OBJECTS, Tacteme, eliminated_by

T = Tacteme


def test_paper_rows_are_table_1_read_by_object() -> None:
    assert PAPER_OBJECTS.objects == OBJECTS
    for row in ALL_ROWS:
        assert PAPER_OBJECTS.eliminated_by(row.tacteme) == row.eliminates
        assert PAPER_OBJECTS.eliminated_by(row.tacteme) == eliminated_by(row.tacteme)
    assert PAPER_OBJECTS.row("sphere").tactemes == {T.PC, T.PC_MOVES, T.PC_ORTHOGONAL_TURN}


def _row(name: str, *tactemes: Tacteme) -> ObjectRow:
    return ObjectRow(name, frozenset(tactemes), tuple((t, f"why {t.value}") for t in tactemes))


def test_file_round_trip_and_errors(tmp_path: Path) -> None:
    table = ObjectTable((_row("prism", T.PC, T.LC, T.AC_ELONGATED), _row("egg", T.PC)))
    path = tmp_path / "objects.json"
    path.write_text(dumps(table))
    back = read_object_table(path)
    assert back.objects == ("prism", "egg")
    assert back.row("prism").tactemes == {T.PC, T.LC, T.AC_ELONGATED}
    assert back.row("prism").reason(T.LC) == "why LC"
    doc = json.loads(path.read_text())
    for bad, match in (
        ({**doc, "version": 99}, "version"),
        ({**doc, "format": "x"}, "format"),
        ({**doc, "objects": [{"name": "Bad Name", "tactemes": []}]}, "name"),
        ({**doc, "objects": [{"name": "cube", "tactemes": ["PC"]}]}, "six objects"),
        ({**doc, "objects": [{"name": "a", "tactemes": ["PC flies"]}]}, "unknown tacteme"),
        (
            {**doc, "objects": [{"name": "a", "tactemes": []}, {"name": "a", "tactemes": []}]},
            "unique",
        ),
    ):
        with pytest.raises(InputError, match=match):
            table_from_json(bad)
    path.write_text("{not json")
    with pytest.raises(InputError, match="not valid JSON"):
        read_object_table(path)
    assert FORMAT in dumps(table)


def test_overlaps_name_identical_and_contained_rows() -> None:
    table = PAPER_OBJECTS.plus(
        [
            _row("ball", T.PC, T.PC_MOVES, T.PC_ORTHOGONAL_TURN),
            _row("pill", *PAPER_OBJECTS.row("sphere").tactemes, T.LC),
        ]
    )
    found = {(o.first, o.second, o.identical) for o in table.overlaps()}
    assert ("sphere", "ball", True) in found
    assert ("sphere", "pill", False) in found and ("ball", "pill", False) in found
    assert not any(o.first == "cube" for o in table.overlaps())


def test_eliminator_and_explain_with_a_user_table() -> None:
    table = PAPER_OBJECTS.plus([_row("ball", T.PC, T.PC_MOVES, T.PC_ORTHOGONAL_TURN)])
    elim = Eliminator.for_table(table)
    elim.apply(T.PC, 0)
    elim.apply(T.PC_ORTHOGONAL_TURN, 5)
    assert elim.outcome is None and elim.candidates == ("sphere", "ball")  # undecided, not wrong
    v = explain([("PC", 0), ("PC takes an orthogonal turn", 5)], table=table)
    assert v.outcome is None and v.candidates == ("sphere", "ball")
    assert "undecided between sphere, ball" in v.sentence()
    v = explain([("LC", 3)], table=table)
    assert "sphere" not in v.candidates and "ball" not in v.candidates
    assert any(o == "ball" and t == "LC" for o, t, _, _ in v.eliminated)


def test_one_reading_does_not_rule_out_an_object_inside_another() -> None:
    """A sphere's row lies inside a pill's: one line (a spurious reading) leaves both."""
    pill = _row("pill", *PAPER_OBJECTS.row("sphere").tactemes, T.LC, T.LCM)
    table = PAPER_OBJECTS.plus([pill])
    seq = [T.PC, T.PC_MOVES, T.PC_ORTHOGONAL_TURN, T.LC]
    elim = Eliminator.for_table(table)
    for j, tac in enumerate(seq):
        elim.apply(tac, j)
    assert elim.candidates == ("sphere", "pill") and elim.strict == ("pill",)
    v = explain([(t.value, j) for j, t in enumerate(seq)], table=table)
    assert v.outcome is None and v.candidates == ("sphere", "pill")
    assert not any(o == "sphere" for o, *_ in v.eliminated)
    # a second reading against the sphere (the line again, or the line moving) decides
    for more in (T.LC, T.LCM):
        again = Eliminator.for_table(table)
        events = [e for j, t in enumerate([*seq, more]) for e in again.apply(t, j)]
        assert again.outcome == "pill"
        assert [e.value for e in events if e.kind == "identified"] == ["pill"]
        w = explain([(t.value, j) for j, t in enumerate([*seq, more])], table=table)
        assert w.outcome == "pill" and any(o == "sphere" for o, *_ in w.eliminated)
    # plain elimination (paper 001) names the pill at once; objects not inside it go
    strict = ObjectTable(table.rows, superset_evidence=1)
    plain = Eliminator.for_table(strict)
    for j, tac in enumerate(seq):
        plain.apply(tac, j)
    assert plain.outcome == "pill"
    assert explain([(t.value, j) for j, t in enumerate(seq)], table=strict).outcome == "pill"
    with pytest.raises(InputError, match="superset_evidence"):
        ObjectTable(table.rows, superset_evidence=0)
    # the six alone: no row inside another, nothing held back
    six = Eliminator.for_table(PAPER_OBJECTS)
    for j, tac in enumerate([T.PC, T.LC]):
        six.apply(tac, j)
    assert six.candidates == six.strict


def _capsule(*rare: Tacteme) -> ObjectRow:
    """A learnt capsule: a cylinder's roll with a point at each end; ``rare`` added, rare."""
    tactemes = {T.PC, T.LC, T.PC_MOVES, T.PC_ORTHOGONAL_TURN, T.LCM, T.LCMP, *rare}
    return ObjectRow("capsule", frozenset(tactemes), rare=frozenset(rare))


def test_an_object_left_only_through_its_rare_readings_is_not_named() -> None:
    """A truncated cone's stray LCMP rules it out; the capsule is left only through its rare
    "LCMT in an arc": not named ("doubt"), in the live eliminator and in ``explain`` alike."""
    table = PAPER_OBJECTS.plus([_capsule(T.LCMT, T.LCMT_ARC)])
    frustum = [T.LC, T.LCM, T.LCMT, T.LCMT_ARC, T.LCMP]
    elim = Eliminator.for_table(table)
    events = [e for j, t in enumerate(frustum) for e in elim.apply(t, j)]
    assert elim.candidates == ("capsule",) and elim.outcome is None
    assert not [e for e in events if e.kind == "identified"]
    assert [(e.kind, e.frame, e.value) for e in events if e.kind == "doubt"] == [
        ("doubt", 4, "capsule")
    ]
    v = explain([(t.value, j) for j, t in enumerate(frustum)], table=table)
    assert v.outcome is None and v.candidates == ("capsule",) and v.reason == "undecided"
    assert v.rare == ("LCMT", "LCMT in an arc")
    assert "only through LCMT, LCMT in an arc, which it produces only rarely" in v.sentence()
    assert v.to_json()["rare"] == ["LCMT", "LCMT in an arc"]
    # named first, then a rare reading: the name is withdrawn
    late = Eliminator.for_table(table)
    seq = [T.LC, T.LCM, T.LCMP, T.PC_MOVES, T.PC_ORTHOGONAL_TURN, T.LCMT]
    kinds = [(e.kind, e.value) for j, t in enumerate(seq) for e in late.apply(t, j)]
    assert ("identified", "capsule") in kinds and kinds[-1] == ("doubt", "capsule")
    assert late.outcome is None and late.identified is None
    late.reset()
    assert late.doubted is None and not late.kinds
    # the capsule's own roll without its rare readings is named; the six alone are unchanged
    own = Eliminator.for_table(table)
    for j, t in enumerate([T.LC, T.LCM, T.LCMP, T.PC_MOVES, T.PC_ORTHOGONAL_TURN]):
        own.apply(t, j)
    assert own.outcome == "capsule"
    six = Eliminator.for_table(PAPER_OBJECTS)
    for j, t in enumerate([T.LC, T.LCM, T.LCMP]):
        six.apply(t, j)
    assert six.outcome == "cylinder" and explain([("LC", 0), ("LCMP", 1)]).rare == ()


def test_rare_tactemes_round_trip_and_must_be_in_the_row(tmp_path: Path) -> None:
    assert "rare" not in PAPER_OBJECTS.to_json()["objects"][0]  # the six: none
    table = ObjectTable((_row("egg", T.PC), _capsule(T.LCMT)))
    doc = table.to_json()
    assert doc["objects"][-1]["rare"] == ["LCMT"] and "rare" not in doc["objects"][0]
    back = table_from_json(json.loads(dumps(table)))
    assert back.row("capsule").rare == frozenset({T.LCMT})
    assert back.rare_seen("capsule", {T.LCMT, T.LC}) == (T.LCMT,)
    assert back.rare_seen("egg", {T.LCMT}) == ()
    old = json.loads(dumps(table))
    del old["objects"][-1]["rare"]  # a file written before rare: ordinary members
    assert table_from_json(old).row("capsule").rare == frozenset()
    bad = json.loads(dumps(table))
    bad["objects"][-1]["rare"] = ["LCMP in an arc"]
    with pytest.raises(InputError, match="rare must be a list of tactemes of the row"):
        table_from_json(bad)
    with pytest.raises(InputError, match="rare tactemes must be in its row"):
        ObjectRow("pill", frozenset({T.PC}), rare=frozenset({T.LC}))


def test_the_recognition_summary_follows_the_doubt() -> None:
    import numpy as np

    from taxelkit.smart.elimination import Event
    from taxelkit.smart.levels34 import finish

    table = PAPER_OBJECTS.plus([_capsule(T.LCMT, T.LCMT_ARC)])
    elim = Eliminator.for_table(table)
    events = [Event("contact", 0, "line")]
    for j, t in enumerate([T.LC, T.LCM, T.LCMT, T.LCMT_ARC, T.LCMP], start=1):
        events += elim.apply(t, j)
    rec = finish(np.zeros(8, np.int8), events, objects=table)
    assert rec.identified is None and rec.candidates == ("capsule",)
    assert rec.verdict.rare == ("LCMT", "LCMT in an arc") and rec.verdict.outcome is None
