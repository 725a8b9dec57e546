"""Level 4 over several contacts of one object (``taxelkit.smart.one_object``, ``--one-object``)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from taxelkit.cli import run
from taxelkit.errors import InputError
from taxelkit.frames import TactileFrames
from taxelkit.io.recordings import read_recording, write_recording
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import make_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart.elimination import Event
from taxelkit.smart.object_table import PAPER_OBJECTS, ObjectRow, ObjectTable
from taxelkit.smart.one_object import ContactEvidence, contacts_of, one_object_verdict
from taxelkit.smart.recogniser import recognise
from taxelkit.smart.tacteme_table import OBJECTS
from taxelkit.smart.tacteme_table import Tacteme as T
from tests.test_schemas import assert_valid

#: A capsule-like object: rolls as a cylinder does, on points as a sphere does, no face.
PILL = ObjectRow("pill", frozenset({T.PC, T.PC_MOVES, T.LC, T.LCM, T.LCMP}))
TABLE = PAPER_OBJECTS.plus([PILL])


def test_contacts_split_at_lift_off_and_keep_only_eliminating_tactemes() -> None:
    events = [
        Event("contact", 1, "area"),
        Event("tacteme", 2, "AC"),
        Event("withheld", 5, "AC moves"),
        Event("lifted", 9, OBJECTS),
        Event("tacteme", 10, "PC"),  # outside any contact: ignored
        Event("contact", 12, "line"),
        Event("tacteme", 13, "LC"),
    ]
    first, second = contacts_of(events)
    assert first == ContactEvidence((("AC", 2),), slid=True)
    assert second == ContactEvidence((("LC", 13),), slid=False)
    assert contacts_of([]) == ()


def test_contacts_together_decide_what_neither_decides() -> None:
    rolled = ContactEvidence((("LC", 3), ("LCMP", 40)))  # a cylinder or the pill
    on_end = ContactEvidence((("AC", 5),))  # a face: not the pill
    assert one_object_verdict([rolled], table=TABLE).candidates == ("cylinder", "pill")
    assert one_object_verdict([on_end], table=TABLE).outcome is None
    # the pill's row lies inside the cylinder's: it goes once a face was seen twice,
    # counted over every contact
    once = one_object_verdict([rolled, on_end], table=TABLE)
    assert once.candidates == ("cylinder", "pill")
    both = one_object_verdict([rolled, on_end, on_end], table=TABLE)
    assert both.outcome == "cylinder"
    assert ("pill", "AC", 5) in [e[:3] for e in both.eliminated]
    # order does not change the outcome
    assert one_object_verdict([on_end, rolled, on_end], table=TABLE).outcome == "cylinder"
    # paper 001's plain elimination: once is enough
    plain = ObjectTable(TABLE.rows, superset_evidence=1)
    assert one_object_verdict([rolled, on_end], table=plain).outcome == "cylinder"


def test_a_tacteme_against_the_object_in_any_contact_rules_it_out() -> None:
    rolled = ContactEvidence((("LCMP", 40),))
    turned = ContactEvidence((("PC takes an orthogonal turn", 7),))
    verdict = one_object_verdict([rolled, turned])
    assert verdict.outcome == "unknown" and verdict.reason == "ruled out"


def test_slid_is_the_reason_only_when_nothing_is_identified() -> None:
    slid = ContactEvidence((("AC", 2),), slid=True)
    assert one_object_verdict([slid]).reason == "slid"
    rolled = ContactEvidence((("LC", 3), ("LCMP", 40)))
    assert one_object_verdict([slid, rolled]).outcome == "cylinder"
    with pytest.raises(InputError, match="at least one contact"):
        one_object_verdict([])


@pytest.mark.parametrize(("name", "seed"), [("cube", 3), ("cone", 1), ("cylinder", 5)])
def test_one_contact_gives_the_recognisers_own_verdict(name: str, seed: int) -> None:
    rng = np.random.default_rng(seed)
    rec = frames_from_scenario(BONNEVILLE_16X16, make_scenario(name, rng=rng), rng=rng)
    result = recognise(rec)
    (contact,) = contacts_of(result.events)
    assert one_object_verdict([contact]) == result.verdict


def _two_handlings() -> TactileFrames:
    """Two rolls of one cylinder (seeds 5 and 6) back to back, lifted between."""
    recs = []
    for seed in (5, 6):
        rng = np.random.default_rng(seed)
        recs.append(
            frames_from_scenario(BONNEVILLE_16X16, make_scenario("cylinder", rng=rng), rng=rng)
        )
    frames = np.concatenate([r.frames for r in recs])
    dt = float(recs[0].t_s[1] - recs[0].t_s[0])
    return TactileFrames(
        frames, t_s=np.arange(frames.shape[0]) * dt, pitch_mm=recs[0].pitch_mm, units="mm"
    )


def test_recognize_one_object(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "two.h5"
    write_recording(_two_handlings(), path)
    assert run(["recognize", str(path), "--json", "--one-object"]) == 0
    doc = json.loads(capsys.readouterr().out)
    accepted = [o for o in doc["objects"] if o["accepted"]]
    assert doc["one_object"]["contacts"] == len(accepted) >= 2
    assert doc["one_object"]["identified"] == "cylinder"
    assert doc["one_object"]["why"]["outcome"] == "cylinder"
    assert_valid("cli-recognize", doc)
    assert run(["recognize", str(path), "--one-object"]) == 0
    assert f"one object over {len(accepted)} contact(s): cylinder" in capsys.readouterr().out
    assert run(["recognize", str(path), "--json"]) == 0
    assert "one_object" not in json.loads(capsys.readouterr().out)


def test_recognize_one_object_without_contact(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "blank.h5"
    write_recording(TactileFrames(np.zeros((5, 4, 4), bool)), path)
    assert run(["recognize", str(path), "--json", "--one-object"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["one_object"] == {"contacts": 0, "identified": None, "candidates": [], "why": None}
    assert_valid("cli-recognize", doc)
    assert run(["recognize", str(path), "--one-object"]) == 0
    assert "one object: nothing (no contact accepted)" in capsys.readouterr().out


def test_simulate_roll_handlings_then_recognize_one_object(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "three.npz"
    argv = ["simulate", "roll", "--object", "cube", "--seed", "4", "--handlings", "3"]
    assert run([*argv, "--contact", "--out", str(out)]) == 0
    assert "3 handlings" in capsys.readouterr().out
    rec = read_recording(out)
    one = [read_recording(tmp_path / f"h{k}.npz") for k in range(3) if _roll_one(tmp_path, k)]
    assert rec.n_frames == sum(r.n_frames for r in one)
    assert np.array_equal(rec.frames, np.concatenate([r.frames for r in one]))
    assert np.all(np.diff(rec.t_s) > 0)
    capsys.readouterr()
    assert run(["recognize", str(out), "--json", "--one-object"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["one_object"]["contacts"] >= 3
    assert doc["one_object"]["identified"] in ("cube", None)


def _roll_one(folder: Path, k: int) -> bool:
    """Handling ``k`` of the three above alone (seed 4 + k)."""
    argv = ["simulate", "roll", "--object", "cube", "--seed", str(4 + k), "--contact"]
    return run([*argv, "--out", str(folder / f"h{k}.npz")]) == 0


def test_recognize_one_object_refuses_live(capsys: pytest.CaptureFixture[str]) -> None:
    assert run(["recognize", "--live", "udp:127.0.0.1:9", "--one-object"]) == 2
    assert "--one-object applies to recordings" in capsys.readouterr().err
