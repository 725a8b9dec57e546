"""The associative memory of paper 000: named chain codes and their recall (Eq. 11-12).

:class:`AssociativeMemory` holds ``K`` named chain codes, the chain-code
configuration and the name of the recall rule; :func:`memorise` builds one from
codes or traced moves (Eq. 11, "the five specimen contours were first stored").
Recall over all rotations is :func:`taxelkit.memory.recall.recall_with_operator`;
the rules are in :mod:`taxelkit.memory.recall_rules`. The memory converts to and
from plain arrays (:meth:`AssociativeMemory.to_arrays`) so the CLI can keep it
in a ``.npz`` file; this module does no file I/O.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError
from taxelkit.memory.chain_code import DEFAULT_CHAIN_CODE, ChainCodeConfig, chain_code_from_moves
from taxelkit.memory.recall import TIE_TOLERANCE, RecallResult, recall_with_operator
from taxelkit.memory.recall_rules import FAITHFUL_RULE, RecallOperator, get_recall_rule
from taxelkit.neuron.quantisers import ternary

__all__ = ["MEMORY_FORMAT_VERSION", "AssociativeMemory", "memorise", "ternary"]

#: Version of the array layout written by :meth:`AssociativeMemory.to_arrays`.
MEMORY_FORMAT_VERSION = 1

_ARRAY_KEYS = ("format_version", "names", "patterns", "m", "l", "thresholds", "rule")


def _check_names(names: object) -> tuple[str, ...]:
    if isinstance(names, str) or not isinstance(names, Sequence | np.ndarray):
        raise InputError(f"names must be a sequence of strings, got {names!r}")
    out = tuple(names)
    if not out:
        raise InputError("names must hold at least one name, got none")
    for i, name in enumerate(out):
        if not isinstance(name, str | np.str_) or not str(name).strip():
            raise InputError(f"names[{i}] must be a non-empty string, got {name!r}")
    out = tuple(str(v) for v in out)
    if len(set(out)) != len(out):
        dupes = sorted({v for v in out if out.count(v) > 1})
        raise InputError(f"names must be unique, got duplicates {dupes}")
    return out


def _check_patterns(patterns: object, n: int) -> NDArray[np.int8]:
    try:
        x = np.asarray(patterns, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"patterns must be a numeric (K, {n}) array, got {patterns!r}") from None
    if x.ndim != 2 or x.shape[1] != n or x.shape[0] == 0:
        raise InputError(f"patterns must have shape (K, {n}) with K >= 1, got shape {x.shape}")
    if not np.all((x == 1.0) | (x == -1.0)):
        raise InputError(
            "patterns must hold only -1 and +1 (a stored code is complete; "
            "0 = unknown is for queries)"
        )
    out = x.astype(np.int8)
    out.setflags(write=False)
    return out


@dataclass(frozen=True, eq=False)
class AssociativeMemory:
    """Named chain codes stored in an Associatron-style memory.

    Build with :func:`memorise`; recall with :meth:`recall`. Immutable:
    :meth:`with_pattern` returns a new memory.

    Parameters
    ----------
    names : tuple of str
        ``K`` unique, non-empty names.
    patterns : (K, N) int8
        Stored chain codes, values +/-1 (kept as a read-only copy).
    config : ChainCodeConfig
        Chain-code parameters; ``N = config.n_elements``.
    rule : str
        Recall rule, a key of :data:`~taxelkit.memory.recall_rules.RECALL_RULES`
        (``"hebbian"`` = the paper's).

    Raises
    ------
    InputError
        If any field is invalid.
    """

    names: tuple[str, ...]
    patterns: NDArray[np.int8]
    config: ChainCodeConfig = DEFAULT_CHAIN_CODE
    rule: str = FAITHFUL_RULE

    def __post_init__(self) -> None:
        if not isinstance(self.config, ChainCodeConfig):
            raise InputError(f"config must be a ChainCodeConfig, got {self.config!r}")
        names = _check_names(self.names)
        patterns = _check_patterns(self.patterns, self.config.n_elements)
        if patterns.shape[0] != len(names):
            raise InputError(
                f"patterns must have one row per name ({len(names)}), got {patterns.shape[0]} rows"
            )
        get_recall_rule(self.rule)
        object.__setattr__(self, "names", names)
        object.__setattr__(self, "patterns", patterns)

    @cached_property
    def operator(self) -> RecallOperator:
        """The recall operator of :attr:`rule` built from :attr:`patterns` (cached)."""
        return get_recall_rule(self.rule).build(self.patterns.astype(np.float64))

    @property
    def n_patterns(self) -> int:
        """Number of stored patterns ``K``."""
        return len(self.names)

    def recall(self, queries: ArrayLike, *, tie_tolerance: float = TIE_TOLERANCE) -> RecallResult:
        """Recognise queries over all ``m`` rotations (Eq. 12, 14).

        Parameters
        ----------
        queries : (Q, N) or (N,) int
            Chain codes with values in {-1, 0, +1} (0 = unknown).
        tie_tolerance : float
            Patterns whose ``c`` is within this of the best are tied and the
            query is undecided between them
            (:data:`~taxelkit.memory.recall.TIE_TOLERANCE`).

        Returns
        -------
        RecallResult
            ``Q = 1`` for a single ``(N,)`` query.

        Raises
        ------
        InputError
            If the queries have the wrong shape or values.
        """
        return recall_with_operator(
            self.operator,
            self.patterns,
            queries,
            names=self.names,
            config=self.config,
            tie_tolerance=tie_tolerance,
        )

    def with_pattern(self, name: str, pattern_or_moves: ArrayLike) -> AssociativeMemory:
        """A new memory with one more pattern (same config and rule).

        Parameters
        ----------
        name : str
            New, unique name.
        pattern_or_moves : (N,) int or (n, 2) float, mm
            A chain code of +/-1, or the moves of a traced contour.

        Returns
        -------
        AssociativeMemory

        Raises
        ------
        InputError
            If the name is taken or the pattern invalid.
        """
        code = _code_of(pattern_or_moves, self.config, f"pattern for {name!r}")
        return AssociativeMemory(
            names=(*self.names, name),
            patterns=np.vstack([self.patterns, code[np.newaxis, :]]),
            config=self.config,
            rule=self.rule,
        )

    def with_rule(self, rule: str) -> AssociativeMemory:
        """The same patterns under another recall rule."""
        return AssociativeMemory(self.names, self.patterns, self.config, rule)

    def to_arrays(self) -> dict[str, NDArray[Any]]:
        """The memory as plain arrays, e.g. for ``numpy.savez``.

        Returns
        -------
        dict of str to ndarray
            ``format_version`` () int64, ``names`` (K,) unicode, ``patterns``
            (K, N) int8, ``m`` () int64, ``l`` () int64, ``thresholds`` (l,)
            float64, ``rule`` () unicode. Loads without pickling.
        """
        return {
            "format_version": np.array(MEMORY_FORMAT_VERSION, dtype=np.int64),
            "names": np.array(self.names, dtype=np.str_),
            "patterns": np.array(self.patterns, dtype=np.int8),
            "m": np.array(self.config.m, dtype=np.int64),
            "l": np.array(self.config.l, dtype=np.int64),
            "thresholds": self.config.thresholds_array(),
            "rule": np.array(self.rule, dtype=np.str_),
        }

    @classmethod
    def from_arrays(cls, arrays: Mapping[str, ArrayLike]) -> AssociativeMemory:
        """Rebuild a memory from :meth:`to_arrays` output, validating everything.

        Parameters
        ----------
        arrays : mapping of str to array_like
            E.g. an opened ``.npz`` file.

        Returns
        -------
        AssociativeMemory

        Raises
        ------
        InputError
            If a key is missing or a value has the wrong type, shape or content.
        """
        missing = [key for key in _ARRAY_KEYS if key not in arrays]
        if missing:
            raise InputError(f"memory arrays must contain {list(_ARRAY_KEYS)}; missing {missing}")
        version = _scalar_int(arrays, "format_version")
        if version != MEMORY_FORMAT_VERSION:
            raise InputError(f"format_version must be {MEMORY_FORMAT_VERSION}, got {version}")
        names = np.asarray(arrays["names"])
        if names.ndim != 1 or names.dtype.kind != "U":
            raise InputError(
                f"names must be a 1-D unicode array, got dtype {names.dtype} shape {names.shape}"
            )
        rule = np.asarray(arrays["rule"])
        if rule.ndim != 0 or rule.dtype.kind != "U":
            raise InputError(f"rule must be a 0-d unicode array, got {rule!r}")
        thresholds = np.asarray(arrays["thresholds"])
        if thresholds.ndim != 1 or thresholds.dtype.kind not in "fiu":
            raise InputError(
                f"thresholds must be a 1-D numeric array, got dtype {thresholds.dtype} "
                f"shape {thresholds.shape}"
            )
        patterns = np.asarray(arrays["patterns"])
        if patterns.dtype.kind not in "iu":
            raise InputError(f"patterns must be an integer array, got dtype {patterns.dtype}")
        config = ChainCodeConfig(
            m=_scalar_int(arrays, "m"),
            l=_scalar_int(arrays, "l"),
            thresholds=tuple(float(v) for v in thresholds),
        )
        return cls(
            names=tuple(str(v) for v in names),
            patterns=patterns,
            config=config,
            rule=str(rule),
        )


def _scalar_int(arrays: Mapping[str, ArrayLike], key: str) -> int:
    value = np.asarray(arrays[key])
    if value.ndim != 0 or value.dtype.kind not in "iu":
        raise InputError(f"{key} must be a 0-d integer array, got {value!r}")
    return int(value)


def _code_of(item: ArrayLike, config: ChainCodeConfig, what: str) -> NDArray[np.int8]:
    try:
        a = np.asarray(item, dtype=np.float64)
    except (TypeError, ValueError):
        raise InputError(f"{what} must be a numeric array, got {item!r}") from None
    if a.ndim == 2 and a.shape[1] == 2:
        return chain_code_from_moves(a, config=config)
    if a.ndim == 1:
        code: NDArray[np.int8] = _check_patterns(a[np.newaxis, :], config.n_elements)[0]
        return code
    raise InputError(
        f"{what} must be a chain code ({config.n_elements},) or moves (n, 2) in mm, "
        f"got shape {a.shape}"
    )


def memorise(
    names: Sequence[str],
    patterns_or_moves: ArrayLike | Sequence[ArrayLike],
    *,
    config: ChainCodeConfig = DEFAULT_CHAIN_CODE,
    rule: str = FAITHFUL_RULE,
) -> AssociativeMemory:
    """Store named contours in an associative memory (paper 000, Eq. 11).

    Parameters
    ----------
    names : sequence of str
        ``K`` unique names.
    patterns_or_moves : (K, N) int, or sequence of K arrays
        Either the chain codes as one ``(K, N)`` array of +/-1, or one item per
        name, each a chain code ``(N,)`` of +/-1 or the moves ``(n, 2)`` in mm
        of a traced contour (encoded with :func:`chain_code_from_moves`).
        Directions can be encoded first with
        :func:`~taxelkit.memory.chain_code.chain_code_from_directions`.
    config : ChainCodeConfig
        Chain-code parameters.
    rule : str
        Recall rule name (``"hebbian"``, the paper's, by default).

    Returns
    -------
    AssociativeMemory

    Raises
    ------
    InputError
        If the names, items or rule are invalid; unknown rule names are listed.

    References
    ----------
    Paper 000, Section V.1, Eq. 11; Section VI.3 (five shapes stored first).
    """
    name_tuple = _check_names(names)
    if isinstance(patterns_or_moves, str) or not isinstance(
        patterns_or_moves, Sequence | np.ndarray
    ):
        raise InputError(
            f"patterns_or_moves must be an array or a sequence, got {patterns_or_moves!r}"
        )
    items = list(patterns_or_moves)
    if len(items) != len(name_tuple):
        raise InputError(
            f"patterns_or_moves must have one item per name ({len(name_tuple)}), got {len(items)}"
        )
    codes = [_code_of(item, config, f"patterns_or_moves[{i}]") for i, item in enumerate(items)]
    return AssociativeMemory(names=name_tuple, patterns=np.stack(codes), config=config, rule=rule)
