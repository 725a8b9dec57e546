"""The CLI explains itself: help on every command and option, choices listed and enforced."""

from __future__ import annotations

import re
from collections.abc import Iterator

import click
import pytest

from taxelkit.cli import cli, run
from taxelkit.cli.options import EXPERIMENT, NameChoice
from taxelkit.experiments.registry import EXPERIMENTS
from taxelkit.memory.recall_rules import RECALL_RULES
from taxelkit.motion.scenarios import SCENARIO_NAMES
from taxelkit.sensors.presets import SENSORS
from taxelkit.world.relief import SHAPE_NAMES
from taxelkit.world.solids import SOLID_NAMES


def _commands(
    command: click.Command = cli, path: tuple[str, ...] = ()
) -> Iterator[tuple[tuple[str, ...], click.Command]]:
    """Every command of the tree, with the words that invoke it."""
    yield path, command
    if isinstance(command, click.Group):
        for name, sub in command.commands.items():
            yield from _commands(sub, (*path, name))


COMMANDS = list(_commands())


def _id(path: tuple[str, ...]) -> str:
    return " ".join(path) or "taxelkit"


def test_the_walk_sees_every_command() -> None:
    names = {_id(p) for p, _ in COMMANDS}
    assert {"taxelkit", "info", "show", "recognize", "reproduce", "simulate solid"} <= names
    assert len(names) >= 15


@pytest.mark.parametrize(("path", "command"), COMMANDS, ids=[_id(p) for p, _ in COMMANDS])
def test_every_command_option_and_argument_is_explained(
    path: tuple[str, ...], command: click.Command
) -> None:
    assert (command.help or "").strip(), f"{_id(path)} has no docstring"
    assert (command.short_help or command.help or "").split("\n")[0].strip()
    help_text = command.help or ""
    for param in command.params:
        if isinstance(param, click.Option):
            assert (param.help or "").strip(), f"{_id(path)} {param.opts[0]} has no help"
        else:  # click arguments take no help: the docstring must name them
            name = param.make_metavar(click.Context(command)).rstrip(".").strip("[]")
            mentioned = re.search(rf"\b{re.escape(name)}\b", help_text)
            assert mentioned, f"{_id(path)}: the docstring does not mention {name}"


def test_help_renders_on_every_command(capsys: pytest.CaptureFixture[str]) -> None:
    for path, _ in COMMANDS:
        assert run([*path, "--help"]) == 0, path
        assert "Usage:" in capsys.readouterr().out


@pytest.mark.parametrize(
    ("argv", "choices"),
    [
        (["trace", "--shape", "hexgon"], SHAPE_NAMES),
        (["simulate", "press", "--shape", "hexgon", "--out", "x.npz"], SHAPE_NAMES),
        (["trace", "--shape", "star", "--rule", "hebian"], tuple(RECALL_RULES)),
        (["memorise", "--rule", "hebian", "--out", "m.npz"], tuple(RECALL_RULES)),
        (["simulate", "solid", "--object", "cub", "--out", "x.npz"], SOLID_NAMES),
        (["simulate", "roll", "--object", "cub", "--out", "x.npz"], SCENARIO_NAMES),
        (["simulate", "solid", "--object", "cube", "--sensor", "x", "--out", "x.npz"], SENSORS),
        (["reproduce", "fig99", "--out", "x"], (*EXPERIMENTS, "all")),
    ],
)
def test_a_name_not_in_the_list_fails_with_the_list(argv: list[str], choices: tuple[str]) -> None:
    errors: list[str] = []
    assert run(argv, echo_err=errors.append) == 2
    assert len(errors) == 1 and "\n" not in errors[0]
    assert all(repr(name) in errors[0] for name in choices), errors[0]


def test_choices_are_listed_in_help(capsys: pytest.CaptureFixture[str]) -> None:
    run(["trace", "--help"])
    out = capsys.readouterr().out
    assert "[" + "|".join(SHAPE_NAMES) + "]" in out
    run(["simulate", "roll", "--help"])
    assert "|".join(SCENARIO_NAMES) in capsys.readouterr().out.replace("\n", "").replace(" ", "")


def test_reproduce_help_lists_every_experiment(capsys: pytest.CaptureFixture[str]) -> None:
    assert run(["reproduce", "--help"]) == 0
    out = capsys.readouterr().out
    for experiment in EXPERIMENTS.values():
        assert f"{experiment.name} " in out and experiment.title in out
    assert "  all " in out


def test_simulate_solid_help_states_the_euler_convention_and_units(
    capsys: pytest.CaptureFixture[str],
) -> None:
    run(["simulate", "solid", "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert "extrinsic x-y-z" in out and "R = Rz Ry Rx" in out
    assert "degrees" in out and "mm" in out
    run(["simulate", "--help"])
    assert "columns run along +x" in " ".join(capsys.readouterr().out.split())


def test_name_choices_come_from_the_registries_and_load_lazily() -> None:
    choice = NameChoice("taxelkit.world.relief:SHAPE_NAMES")
    assert choice._names is None
    assert choice.choices == SHAPE_NAMES
    assert EXPERIMENT.choices == (*EXPERIMENTS, "all")
    assert choice.convert("star", None, None) == "star"
    with pytest.raises(click.BadParameter, match="hexgon"):
        choice.convert("hexgon", None, None)
