"""``taxelkit trace --rule signature|signature-dense``: the order-aware code from the CLI."""

from __future__ import annotations

import json

import pytest

from taxelkit.cli import run
from taxelkit.cli.trace_signature import SIGNATURE_RULE_NAMES
from taxelkit.memory import SIGNATURE_RULES


def test_the_cli_lists_the_library_signature_rules() -> None:
    assert SIGNATURE_RULE_NAMES == SIGNATURE_RULES


@pytest.mark.parametrize("rule", SIGNATURE_RULES)
def test_trace_json_names_a_rotated_star_with_a_signature_rule(
    rule: str, capsys: pytest.CaptureFixture[str]
) -> None:
    code = run(["trace", "--shape", "star", "--rotate-deg", "25", "--seed", "2", "--rule", rule,
                "--json"])  # fmt: skip
    out = capsys.readouterr()
    assert code == 0, out.err
    doc = json.loads(out.out)
    assert doc["rule"] == rule and doc["verdict"] == "star" and doc["margin"] > 0
    assert doc["recall_curve"][-1]["verdict"] == "star"
    assert doc["calibrated"] is False and doc["probabilities"] is None
    assert 0.0 < doc["decided_at_s"] <= 1.0


def test_signature_rules_refuse_a_memory_file_in_one_line(tmp_path: object) -> None:
    errors: list[str] = []
    argv = ["trace", "--shape", "star", "--rule", "signature", "--memory", "m.npz"]
    assert run(argv, echo_err=errors.append) == 2
    assert len(errors) == 1 and "built-in shapes" in errors[0] and "\n" not in errors[0]
