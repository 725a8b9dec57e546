"""The ``new-objects`` experiment: a small run scores, renders and plots."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.experiments import new_objects
from taxelkit.experiments.report import render_block
from taxelkit.smart.object_table import PAPER_OBJECTS, ObjectRow
from taxelkit.smart.tacteme_table import Tacteme


def test_decidable_rolls_are_those_whose_tactemes_rule_out_every_other_object() -> None:
    ball = ObjectRow("ball", frozenset({Tacteme.PC, Tacteme.PC_MOVES, Tacteme.PC_ORTHOGONAL_TURN}))
    table = PAPER_OBJECTS.plus([ball])
    assert not new_objects.decidable(
        table, "sphere", ("PC", "PC moves", "PC takes an orthogonal turn")
    )
    assert new_objects.decidable(table, "cone", ("LC", "LCMT about one end"))
    assert not new_objects.decidable(table, "cone", ("LC", "LCM"))


def test_a_small_run_scores_renders_and_plots(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(new_objects, "DEFAULT_CHECK_ROLLS", 1)
    result = new_objects.run_new_objects(n_trials=1, n_outside=1, workers=1)
    doc = result.to_json()
    assert len(doc["objects"]) == 10 and doc["objects"][:6] == list(PAPER_OBJECTS.objects)
    assert sum(r["trials"] for r in doc["per_object"]) == 10
    assert doc["acceptance"]["six_rows_agree"] and not any(doc["six_differences"].values())
    assert {"sphere", "ellipsoid"} <= set(doc["not_distinguishable"])
    text = render_block("new-objects", {"new-objects": doc})
    assert "| hex-prism |" in text and "Acceptance (the rolls as the array gives them):" in text
    # the same motions through every imperfection at once: a table and a summary of their own
    faulty = doc["imperfect"]["all"]
    assert sum(r["trials"] for r in faulty["per_object"]) == 11  # ten objects and the prism
    assert "seen through every imperfection" in text and "With all:" in text
    explore = doc["explore"]
    assert explore["handlings"] == new_objects.EXPLORE_HANDLINGS
    for row in explore["per_object"]:
        by = row["identified_by_handling"]
        assert len(by) == explore["handlings"] and by == sorted(by) and by[-1] == row["identified"]
        assert 1.0 <= row["mean_handlings"] <= explore["handlings"]
        assert sum(row["outcomes"].values()) == row["trials"] == 1
    assert "handled until decided" in text
    from taxelkit.plotting.experiments import plot_experiment

    fig = plot_experiment("new-objects", result)
    assert len(fig.axes) == 3


def test_the_imperfect_view_sees_the_same_motions_and_changes_nothing_else() -> None:
    table = PAPER_OBJECTS
    seq = np.random.SeedSequence(0).spawn(3)[2]
    clean = new_objects._trial(("cylinder", seq, table, 2, ()))
    both = new_objects._trial(("cylinder", seq, table, 2, ("all",)))
    assert clean[:5] == both[:5] and clean[5] == {}
    first, outcome, used = both[5]["all"]
    assert 1 <= used <= 2 and {first, outcome} <= {*PAPER_OBJECTS.objects, "undecided", "unknown"}
    with pytest.raises(InputError, match="unknown imperfection"):
        new_objects.run_new_objects(n_trials=1, imperfections=["rust"])


def test_the_first_handling_is_the_single_roll() -> None:
    """Exploring changes nothing in the single-roll outcome; one handling explores nothing."""
    table = PAPER_OBJECTS
    seq = np.random.SeedSequence(0).spawn(3)[2]
    one = new_objects._trial(("cylinder", seq, table, 1, ()))
    five = new_objects._trial(("cylinder", seq, table, 5, ()))
    assert one[:4] == five[:4]
    assert one[4][1] == 1 and one[4][0] == one[1]


def test_the_held_out_run_is_marked_and_renders_beside_the_main_one(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    from taxelkit.experiments.new_objects_heldout import run_new_objects_heldout

    monkeypatch.setattr(new_objects, "DEFAULT_CHECK_ROLLS", 1)
    main = new_objects.run_new_objects(n_trials=1, n_outside=1, handlings=2, workers=1)
    held = run_new_objects_heldout(n_trials=1, n_outside=1, handlings=2, workers=1)
    doc = held.to_json()
    assert doc["experiment"] == "new-objects-heldout"
    assert (doc["tuned_on_seed"], doc["held_out_seed"], doc["seed"]) == (0, 11, 11)
    text = render_block(
        "new-objects-heldout", {"new-objects": main.to_json(), "new-objects-heldout": doc}
    )
    assert "| capsule | yes |" in text and "seed 0 / seed 11" in text
    assert "(in neither table: named)" in text and "Held-out seed:" in text
