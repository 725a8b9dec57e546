"""Option types shared by every command: one rule per kind of value.

Each numeric option of the CLI is parsed by one of these types, so the same
option obeys the same rule in every command (``--seed`` in ``simulate``,
``trace``, ``memorise``, ``reproduce``, ``demo``; ``--threshold`` in ``show``
and ``recognize``; ...). A bad value ends as one line on stderr and exit
code 2, naming the option, the rule and the value.

The bounds are physical sanity limits, not precision limits: they keep every
product of inputs far from float64 overflow, so that no numpy warning can
precede the error they would announce.
"""

from __future__ import annotations

import importlib
import math
import re
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TypeVar

import click

if TYPE_CHECKING:  # click >= 8.5 types ParamType by its value and input types
    _ParamType = click.ParamType[Any, Any]
    _StrChoice = click.Choice[str]
else:
    _ParamType = click.ParamType
    _StrChoice = click.Choice

__all__ = [
    "ANGLE_DEG",
    "COORDINATE_MM",
    "DURATION_S",
    "EULER_DEG",
    "EXPERIMENT",
    "INDENT_MM",
    "LENGTH_MM",
    "MAX_ANGLE_DEG",
    "MAX_COORDINATE_MM",
    "MAX_MB",
    "MAX_SEED",
    "MAX_THRESHOLD",
    "PITCH_MM",
    "RATE_HZ",
    "RECALL_RULE",
    "ROLL_OBJECT",
    "SCALE",
    "SEED",
    "SENSOR",
    "SHAPE",
    "SOLID",
    "STEP_HEIGHT_UM",
    "THRESHOLD",
    "TIMEOUT_S",
    "TRACE_RULE",
    "FiniteFloat",
    "NameChoice",
    "Numbers",
    "Seed",
    "relief_options",
]

#: Largest seed: NumPy seeds are unsigned 64-bit; the CLI keeps to signed
#: 64-bit so that every seed is also a valid JSON and C ``int64`` value.
MAX_SEED = 2**63 - 1
#: A seed as typed: ASCII decimal digits with an optional sign (no ``1_000``,
#: no other scripts' digits, which Python's ``int`` would accept).
_DECIMAL_INTEGER = re.compile(r"[+-]?[0-9]+")
#: Largest magnitude of a position or offset, mm (10 m: far beyond any specimen).
MAX_COORDINATE_MM = 1e4
#: Largest magnitude of an angle, degrees (ten turns).
MAX_ANGLE_DEG = 3600.0
#: Largest contact threshold, in the frames' units (mm, or counts up to 65535).
MAX_THRESHOLD = 1e6


class Seed(_ParamType):
    """A seed: an integer from 0 to :data:`MAX_SEED`."""

    name = "seed"

    def convert(self, value: Any, param: click.Parameter | None, ctx: click.Context | None) -> int:
        """Parse ``value``; ``self.fail`` (a usage error) if it is not a valid seed."""
        if isinstance(value, int) and not isinstance(value, bool):
            number = value
        else:
            text = str(value).strip()
            if not _DECIMAL_INTEGER.fullmatch(text):
                self.fail(f"{value!r} is not an integer seed (0 to 2**63-1)", param, ctx)
            number = int(text, 10)
        if not 0 <= number <= MAX_SEED:
            self.fail(f"{value!r} is not in 0 to 2**63-1", param, ctx)
        return number


def _parse_float(text: str) -> float | None:
    try:
        return float(text)
    except ValueError:
        return None


class FiniteFloat(_ParamType):
    """A finite number in ``[low, high]`` (``(low, high]`` with ``low_open``).

    Parameters
    ----------
    low, high : float
        Bounds.
    low_open : bool
        Exclude ``low`` (for quantities that must be > 0).
    """

    name = "number"

    def __init__(self, low: float, high: float, *, low_open: bool = False) -> None:
        self.low, self.high, self.low_open = float(low), float(high), low_open

    def _rule(self) -> str:
        left = "(" if self.low_open else "["
        return f"a finite number in {left}{self.low:g}, {self.high:g}]"

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> float:
        """Parse ``value``; ``self.fail`` if it is not finite or out of range."""
        number = _parse_float(str(value)) if not isinstance(value, float | int) else float(value)
        if number is None or not math.isfinite(number):
            self.fail(f"{value!r} is not {self._rule()}", param, ctx)
        below = number <= self.low if self.low_open else number < self.low
        if below or number > self.high:
            self.fail(f"{value!r} is not {self._rule()}", param, ctx)
        return number


class Numbers(_ParamType):
    """``count`` comma-separated finite numbers, each within ``+-bound``.

    Parameters
    ----------
    count : int
        How many numbers (2 for ``X,Y``, 3 for ``RX,RY,RZ``).
    bound : float
        Largest magnitude of each number.
    metavar : str
        How the value is written in messages, e.g. ``"X,Y"``.
    """

    name = "numbers"

    def __init__(self, count: int, bound: float, metavar: str) -> None:
        self.count, self.bound, self.metavar = count, float(bound), metavar

    def get_metavar(self, param: click.Parameter, ctx: click.Context | None = None) -> str:
        """The metavar shown by ``--help``."""
        return self.metavar

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> tuple[float, ...]:
        """Parse ``"a,b[,c]"``; ``self.fail`` on a wrong count or a bad number."""
        if isinstance(value, tuple):
            return value
        parts = str(value).split(",")
        numbers = [_parse_float(p) for p in parts]
        rule = f"{self.count} finite numbers {self.metavar} within +-{self.bound:g}"
        if len(parts) != self.count or any(n is None for n in numbers):
            self.fail(f"{value!r} is not {rule}", param, ctx)
        checked = tuple(float(n) for n in numbers if n is not None)
        if not all(math.isfinite(n) and abs(n) <= self.bound for n in checked):
            self.fail(f"{value!r} is not {rule}", param, ctx)
        return checked


class NameChoice(_StrChoice):
    """One of the names a library registry holds, read when first needed.

    A ``click.Choice`` (``--help`` lists the names, completion offers them, a
    name not in the list is refused with the list) whose names come from
    ``module:attribute`` (a tuple of names or a mapping keyed by them), so the
    CLI starts without importing the simulator or the memory.

    Parameters
    ----------
    source : str
        ``"package.module:ATTRIBUTE"``.
    extra : iterable of str
        Names accepted beside the registry's (``"all"`` for experiments).
    """

    name = "choice"

    def __init__(self, source: str, *, extra: Iterable[str] = ()) -> None:
        self.source, self.extra = source, tuple(extra)
        self.case_sensitive = True
        self._names: tuple[str, ...] | None = None

    @property
    def choices(self) -> tuple[str, ...]:
        """The accepted names, in the registry's order, then ``extra``."""
        if self._names is None:
            module, attribute = self.source.split(":")
            names = getattr(importlib.import_module(module), attribute)
            self._names = (*(str(n) for n in names), *self.extra)
        return self._names

    @choices.setter
    def choices(self, names: tuple[str, ...]) -> None:
        self._names = tuple(names)


#: ``--seed`` everywhere.
SEED = Seed()
#: Contact thresholds (``show --threshold``, ``recognize --threshold``).
THRESHOLD = FiniteFloat(0.0, MAX_THRESHOLD)
#: Single angles (``--rotate-deg``, ``--yaw-deg``).
ANGLE_DEG = FiniteFloat(-MAX_ANGLE_DEG, MAX_ANGLE_DEG)
#: ``X,Y`` positions and offsets, mm.
COORDINATE_MM = Numbers(2, MAX_COORDINATE_MM, "X,Y")
#: ``RX,RY,RZ`` rotations, degrees.
EULER_DEG = Numbers(3, MAX_ANGLE_DEG, "RX,RY,RZ")
#: Lengths that must be > 0, mm (diameters, 10 m at most).
LENGTH_MM = FiniteFloat(0.0, MAX_COORDINATE_MM, low_open=True)
#: Taxel pitch, mm.
PITCH_MM = FiniteFloat(0.0, 1e3, low_open=True)
#: Step heights of relief specimens, um (> 0, 10 cm at most).
STEP_HEIGHT_UM = FiniteFloat(0.0, 1e5, low_open=True)
#: Indentation depths, mm (0 to 100).
INDENT_MM = FiniteFloat(0.0, 100.0)
#: Scale factors (mm per file unit, or size multipliers).
SCALE = FiniteFloat(0.0, 1e4, low_open=True)
#: Frame rates, Hz.
RATE_HZ = FiniteFloat(0.0, 1e6, low_open=True)
#: Time-outs, s.
TIMEOUT_S = FiniteFloat(0.0, 1e6, low_open=True)
#: Durations that may be 0, s.
DURATION_S = FiniteFloat(0.0, 1e6)
#: The read limit of ``taxelkit --max-mb``, MiB (see :mod:`taxelkit.io.limits`).
MAX_MB = FiniteFloat(0.0, 1e7, low_open=True)
#: ``--shape``: the built-in relief shapes of paper 000.
SHAPE = NameChoice("taxelkit.world.relief:SHAPE_NAMES")
#: ``simulate solid --object``: the six solids of paper 001.
SOLID = NameChoice("taxelkit.world.solids:SOLID_NAMES")
#: ``simulate roll --object``: the six solids and sliding.
ROLL_OBJECT = NameChoice("taxelkit.motion.scenarios:SCENARIO_NAMES")
#: ``--rule``: the Associatron recall rules.
RECALL_RULE = NameChoice("taxelkit.memory.recall_rules:RECALL_RULES")
#: ``trace --rule``: the chain-code rules and the order-aware signature rules.
TRACE_RULE = NameChoice(
    "taxelkit.memory.recall_rules:RECALL_RULES", extra=("signature", "signature-dense")
)
#: ``--sensor``: the sensor presets.
SENSOR = NameChoice("taxelkit.sensors.presets:SENSORS")
#: ``reproduce NAME``: the registered experiments, or ``all``.
EXPERIMENT = NameChoice("taxelkit.experiments.registry:EXPERIMENTS", extra=("all",))


_F = TypeVar("_F", bound=Callable[..., Any])

#: The options that choose and place a relief (``trace``, ``simulate press``).
_RELIEF_OPTIONS = (
    click.option(
        "--shape", type=SHAPE, default=None, help="A built-in relief shape (or give --specimen)."
    ),
    click.option(
        "--specimen",
        type=click.Path(path_type=Path),
        default=None,
        help="Your own relief: a heightmap .npz (docs/recording-format.md), instead of --shape.",
    ),
    click.option(
        "--rotate-deg",
        type=ANGLE_DEG,
        default=0.0,
        show_default=True,
        help="Rotation of the --shape (or --specimen, about its raised relief's centroid), "
        "degrees counter-clockwise (x towards y).",
    ),
    click.option(
        "--offset-mm",
        type=COORDINATE_MM,
        default="0,0",
        show_default=True,
        help="Centre of the --shape on the plate X,Y, mm (a --specimen is moved by X,Y).",
    ),
    click.option(
        "--diameter-mm",
        type=LENGTH_MM,
        default=90.0,
        show_default=True,
        help="Size of the --shape (circumscribed circle), mm; a --specimen is scaled so that "
        "the circle about its raised relief's centroid that holds it has this diameter.",
    ),
    click.option(
        "--step-height-um",
        type=STEP_HEIGHT_UM,
        default=200.0,
        show_default=True,
        help="Height of the --shape's relief step, um; a --specimen's heights are scaled so "
        "that its highest is this.",
    ),
)


def relief_options(command: _F) -> _F:
    """Add ``--shape``, ``--specimen``, ``--rotate-deg``, ``--offset-mm``, ``--diameter-mm``
    and ``--step-height-um`` to a command (in that order in its help)."""
    for option in reversed(_RELIEF_OPTIONS):
        command = option(command)
    return command
