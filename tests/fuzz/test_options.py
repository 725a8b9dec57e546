"""Every numeric option of every command, fed generated bad values.

The (command, option) pairs are discovered from the click tree, so a new
numeric option is fuzzed without editing this file. Each example must end
in exit code 2, one line naming the option, no traceback, no file written.
"""

from __future__ import annotations

import math
import tempfile
from collections.abc import Callable
from pathlib import Path

import click
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from taxelkit.cli import cli
from taxelkit.cli.options import MAX_SEED, FiniteFloat, Numbers, Seed
from tests.fuzz._harness import assert_refused, files_under, invoke

#: Examples per (command, option) pair; with the pairs below, over 1,000 cases.
EXAMPLES_PER_OPTION = 32

#: Arguments that make each command otherwise valid; ``{d}`` is an empty
#: temporary folder for outputs, ``{f}`` an input path (never read: the bad
#: option is refused first).
BASE_ARGV: dict[str, list[str]] = {
    "info": ["info", "{f}"],
    "show": ["show", "{f}", "--out", "{d}/s.png"],
    "recognize": ["recognize", "{f}"],
    "convert": ["convert", "{f}", "{d}/c.npz"],
    "trace": ["trace", "--shape", "circle", "--plot", "{d}/t.png"],
    "memorise": ["memorise", "--out", "{d}/m.npz"],
    "reproduce": ["reproduce", "fig7", "--out", "{d}/r"],
    "demo": ["demo", "--out", "{d}/demo"],
    "simulate press": ["simulate", "press", "--shape", "circle", "--out", "{d}/p.npz"],
    "simulate solid": ["simulate", "solid", "--object", "cube", "--out", "{d}/s.npz"],
    "simulate roll": ["simulate", "roll", "--object", "cube", "--out", "{d}/r.npz"],
    "learn-object": ["learn-object", "{f}", "--name", "x", "--out", "{d}/o.json"],
}


def _commands() -> dict[str, click.Command]:
    out: dict[str, click.Command] = {}
    for name, command in cli.commands.items():  # type: ignore[attr-defined]
        if isinstance(command, click.Group):
            for sub, subcommand in command.commands.items():
                out[f"{name} {sub}"] = subcommand
        else:
            out[name] = command
    return out


def _numeric(param: click.Parameter) -> bool:
    # Plain click FLOAT/INT options are included on purpose: they accept nan,
    # inf or any size, so a new option declared with ``type=float`` fails here.
    return isinstance(param, click.Option) and isinstance(
        param.type,
        Seed | FiniteFloat | Numbers | click.types.FloatParamType | click.types.IntParamType,
    )


def _pairs() -> list[tuple[str, str, click.ParamType]]:
    pairs = [
        ("", param.opts[-1], param.type)
        for param in cli.params
        if _numeric(param)  # the group's own options (--max-mb)
    ]
    for name, command in _commands().items():
        pairs += [(name, p.opts[-1], p.type) for p in command.params if _numeric(p)]
    return pairs


PAIRS = _pairs()


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


_JUNK = st.sampled_from(["", " ", "nan", "NaN", "inf", "-inf", "1e400", "-1e400", "0x10", "1,2,3"])


def _bad_float(kind: FiniteFloat) -> st.SearchStrategy[str]:
    text = st.text(max_size=12).filter(lambda t: not _is_number(t))
    parts = [_JUNK, text]
    if math.isfinite(kind.high):
        parts.append(st.floats(min_value=kind.high, exclude_min=True).map(repr))
    if math.isfinite(kind.low):
        parts.append(st.floats(max_value=kind.low, exclude_max=not kind.low_open).map(repr))
    return st.one_of(*parts)


def _python_int(text: str) -> bool:
    try:
        int(text)
    except ValueError:
        return False
    return True


def _bad_int(low: float, high: float) -> st.SearchStrategy[str]:
    outside = st.integers(max_value=int(low) - 1) if math.isfinite(low) else st.nothing()
    if math.isfinite(high):
        outside = outside | st.integers(min_value=int(high) + 1)
    # Text that no integer parser accepts (click's IntRange uses Python's int).
    text = st.text(max_size=12).filter(lambda t: not _python_int(t))
    floats = st.floats(allow_nan=True).filter(lambda v: not v.is_integer()).map(repr)
    return st.one_of(outside.map(str), text, floats, _JUNK)


def _bad_numbers(kind: Numbers) -> st.SearchStrategy[str]:
    good = st.floats(min_value=-kind.bound, max_value=kind.bound).map(repr)
    bad = st.one_of(
        st.floats(min_value=kind.bound, exclude_min=True).map(repr),
        st.floats(max_value=-kind.bound, exclude_max=True).map(repr),
        st.sampled_from(["nan", "inf", "-inf", "", "x", "1e400"]),
    )

    def with_one_bad(values: list[str], position: int, value: str) -> str:
        values[position % len(values)] = value
        return ",".join(values)

    one_bad = st.builds(
        with_one_bad, st.lists(good, min_size=kind.count, max_size=kind.count), st.integers(), bad
    )
    wrong_count = st.lists(good, max_size=6).filter(lambda v: len(v) != kind.count).map(",".join)
    return st.one_of(one_bad, wrong_count, st.text(max_size=12))


def _strategy(kind: click.ParamType) -> st.SearchStrategy[str]:
    if isinstance(kind, Seed):
        return _bad_int(0, MAX_SEED)
    if isinstance(kind, FiniteFloat):
        return _bad_float(kind)
    if isinstance(kind, Numbers):
        return _bad_numbers(kind)
    if isinstance(kind, click.IntRange):
        low = -math.inf if kind.min is None else float(kind.min)
        high = math.inf if kind.max is None else float(kind.max)
        return _bad_int(low, high)
    if isinstance(kind, click.types.IntParamType):
        return _bad_int(-math.inf, math.inf)
    return _bad_float(FiniteFloat(-math.inf, math.inf))


def test_the_fuzzed_options_cover_every_command() -> None:
    commands = {name for name, _, _ in PAIRS}
    assert set(BASE_ARGV) | {""} >= commands
    assert {
        "",
        "info",
        "show",
        "recognize",
        "convert",
        "trace",
        "memorise",
        "reproduce",
    } <= commands
    assert {"simulate press", "simulate solid", "simulate roll", "demo"} <= commands
    assert len(PAIRS) * EXAMPLES_PER_OPTION >= 1000


@pytest.mark.parametrize(
    ("command", "option", "kind"),
    [pytest.param(c, o, k, id=f"{c or 'taxelkit'} {o}") for c, o, k in PAIRS],
)
@settings(
    max_examples=EXAMPLES_PER_OPTION,
    deadline=None,
    derandomize=True,
    database=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.filter_too_much],
)
@given(data=st.data())
def test_bad_option_value_is_one_line_exit_2(
    command: str, option: str, kind: click.ParamType, data: st.DataObject
) -> None:
    value = data.draw(_strategy(kind), label=option)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        fill: Callable[[str], str] = lambda a: a.format(d=folder, f=folder / "in.npz")  # noqa: E731
        if command:
            argv = [*fill_command(command, fill), f"{option}={value}", *rest(command, fill)]
        else:
            argv = [f"{option}={value}", "info", fill("{f}")]
        line = assert_refused(invoke(argv))
        assert option in line, line
        assert files_under(folder) == set(), "a file was left behind"


def fill_command(command: str, fill: Callable[[str], str]) -> list[str]:
    """The command words (``simulate press``) of ``BASE_ARGV[command]``."""
    return [fill(a) for a in BASE_ARGV[command][: len(command.split())]]


def rest(command: str, fill: Callable[[str], str]) -> list[str]:
    """The arguments after the command words."""
    return [fill(a) for a in BASE_ARGV[command][len(command.split()) :]]


def test_the_same_option_has_the_same_rule_in_every_command() -> None:
    by_name: dict[str, set[int]] = {}
    for _, option, kind in PAIRS:
        if isinstance(kind, Seed | FiniteFloat | Numbers):
            by_name.setdefault(option, set()).add(id(kind))
    assert "--seed" in by_name and "--threshold" in by_name
    assert {name: len(ids) for name, ids in by_name.items() if len(ids) > 1} == {}
