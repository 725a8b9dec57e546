"""Associatron memory and recall (paper 000, Eq. 10-12, 14) on ideal contours of the five shapes."""

from __future__ import annotations

import dataclasses
import doctest
import io
import math
from collections import Counter

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.memory import (
    RECALL_RULES,
    AssociativeMemory,
    ChainCodeConfig,
    all_cyclic_shifts,
    associatron,
    chain_code_from_moves,
    correlation,
    get_recall_rule,
    hebbian_matrix,
    memorise,
    partial_chain_code_from_moves,
    recall,
    recall_rules,
    ternary,
)

# ---------------------------------------------------------------- ideal contours
# The five specimens of paper 000, Section VI.3, built directly here (independent
# of taxelkit.world): circumscribed diameter 90 mm, walked in 3 mm PTP steps.

DIAMETER_MM = 90.0
STEP_MM = 3.0
#: Inner/outer radius ratio of the regular pentagram outline, sin 18 / sin 126 = 0.382
#: (with this value the two outer edges on each chord are exactly collinear).
STAR_RATIO = math.sin(math.radians(18.0)) / math.sin(math.radians(126.0))
SHAPES = ("circle", "square", "triangle", "star", "hexagon")
#: (vertices, angle of the first vertex in deg, inner radius ratio or None).
POLYGONS = {
    "square": (4, 45.0, None),
    "triangle": (3, 90.0, None),
    "hexagon": (6, 0.0, None),
    "star": (5, 90.0, STAR_RATIO),
}
#: Vertices of the fine polygon standing in for the circle.
CIRCLE_VERTICES = 3600


def outline_mm(name: str, rotation_rad: float = 0.0) -> NDArray[np.float64]:
    """Counter-clockwise vertices of a shape, centred at the origin, rotated."""
    radius = DIAMETER_MM / 2.0
    if name == "circle":
        t = 2.0 * np.pi * np.arange(CIRCLE_VERTICES) / CIRCLE_VERTICES + rotation_rad
        return radius * np.stack([np.cos(t), np.sin(t)], axis=1)
    n, first_deg, inner = POLYGONS[name]
    if inner is None:
        angle = math.radians(first_deg) + 2.0 * np.pi * np.arange(n) / n
        r = np.full(n, radius)
    else:
        angle = math.radians(first_deg) + np.pi * np.arange(2 * n) / n
        r = np.where(np.arange(2 * n) % 2 == 0, radius, inner * radius)
    angle = angle + rotation_rad
    return np.stack([r * np.cos(angle), r * np.sin(angle)], axis=1)


def contour_moves_mm(
    name: str, *, rotation_rad: float = 0.0, start: float = 0.0, fraction: float = 1.0
) -> NDArray[np.float64]:
    """Moves of a walk along the outline in 3 mm (arc length) steps.

    ``start`` and ``fraction`` are fractions of the perimeter: the walk begins
    at arc length ``start * L`` and covers ``fraction * L``.
    """
    vertices = outline_mm(name, rotation_rad)
    closed = np.vstack([vertices, vertices[:1]])
    edges = np.diff(closed, axis=0)
    lengths = np.hypot(edges[:, 0], edges[:, 1])
    cumulative = np.concatenate([[0.0], np.cumsum(lengths)])
    perimeter = cumulative[-1]
    arc = np.mod(
        start * perimeter + np.arange(0.0, fraction * perimeter + 1e-9, STEP_MM), perimeter
    )
    edge = np.minimum(np.searchsorted(cumulative, arc, side="right") - 1, len(lengths) - 1)
    points = closed[edge] + edges[edge] * ((arc - cumulative[edge]) / lengths[edge])[:, None]
    return np.diff(points, axis=0)


@pytest.fixture(scope="module")
def stored_moves() -> list[NDArray[np.float64]]:
    return [contour_moves_mm(name) for name in SHAPES]


@pytest.fixture(scope="module")
def memories(stored_moves: list[NDArray[np.float64]]) -> dict[str, AssociativeMemory]:
    return {rule: memorise(SHAPES, stored_moves, rule=rule) for rule in RECALL_RULES}


# ---------------------------------------------------------------- building blocks


def test_docstring_examples() -> None:
    for module in (associatron, recall, recall_rules):
        result = doctest.testmod(module)
        assert result.failed == 0


def test_ternary_is_eq9() -> None:
    assert ternary([-2.0, -0.5, 0.0, 0.5, 2.0]).tolist() == [-1, -1, 0, 1, 1]
    assert ternary([-2.0, -0.5, 0.0, 0.5, 2.0], 1.0).tolist() == [-1, 0, 0, 0, 1]


def test_correlation_eq14() -> None:
    x = np.array([1, -1, 1, -1])
    assert float(correlation(x, x)) == 1.0
    assert float(correlation(x, -x)) == -1.0  # the paper's text says 0; for +/-1 it is -1
    assert float(correlation(x, np.zeros(4))) == 0.0
    assert correlation(np.ones((3, 1, 4)), np.ones((5, 4))).shape == (3, 5)
    with pytest.raises(InputError, match="same non-empty last axis"):
        correlation(np.ones(4), np.ones(5))


def test_hebbian_matrix_is_eq11() -> None:
    rng = np.random.default_rng(1)
    x = rng.choice([-1, 1], size=(4, 10))
    m = hebbian_matrix(x)
    np.testing.assert_array_equal(m, sum(np.outer(row, row) for row in x))
    np.testing.assert_array_equal(np.diag(m), np.full(10, 4))
    np.testing.assert_array_equal(m, m.T)


def test_faithful_recall_completes_nearly_orthogonal_patterns() -> None:
    """Eq. 12 with the paper's rule: a pattern with a quarter unknown comes back whole."""
    rng = np.random.default_rng(2)
    cfg = ChainCodeConfig()
    x = rng.choice(np.array([-1, 1], dtype=np.int8), size=(3, cfg.n_elements))
    mem = AssociativeMemory(("a", "b", "c"), x, cfg, "hebbian")
    y = x.copy()
    y[:, rng.permutation(cfg.n_elements)[:12]] = 0
    result = mem.recall(y)
    assert result.recognised == ("a", "b", "c")
    np.testing.assert_array_equal(result.best_shift[np.arange(3), np.arange(3)], 0)
    np.testing.assert_array_equal(result.recalled, x)


@pytest.mark.parametrize("rule", ["zero_mean", "projection", "masked_projection"])
def test_stored_patterns_are_fixed_points_of_the_improved_rules(
    memories: dict[str, AssociativeMemory], rule: str
) -> None:
    mem = memories[rule]
    z = ternary(mem.operator.fields(mem.patterns.astype(float)), mem.operator.epsilon)
    np.testing.assert_array_equal(z, mem.patterns)


def test_masked_projection_equals_projection_without_unknowns(
    memories: dict[str, AssociativeMemory],
) -> None:
    y = np.random.default_rng(4).choice([-1.0, 1.0], size=(6, 12, 48))
    np.testing.assert_allclose(
        memories["masked_projection"].operator.fields(y),
        memories["projection"].operator.fields(y),
        atol=1e-4,
    )


@given(
    st.lists(st.floats(-3.0, 3.0), min_size=1, max_size=30),
    st.sampled_from([0.0, 1e-9, 0.5]),
)
@settings(max_examples=60, deadline=None)
def test_internal_phi_equals_ternary(values: list[float], epsilon: float) -> None:
    h = np.asarray([*values, epsilon, -epsilon, 0.0])
    np.testing.assert_array_equal(recall._phi(h, epsilon), ternary(h, epsilon))


def test_masked_projection_is_least_squares_on_known_elements(
    memories: dict[str, AssociativeMemory],
) -> None:
    mem = memories["masked_projection"]
    x = mem.patterns.astype(float)
    rng = np.random.default_rng(10)
    y = rng.choice([-1.0, 0.0, 1.0], size=(8, 48), p=[0.3, 0.5, 0.2])
    y[0] = 0.0
    fields = mem.operator.fields(y)
    np.testing.assert_array_equal(fields[0], 0.0)  # nothing known, nothing recalled
    for row, h in zip(y[1:], fields[1:], strict=True):
        known = row != 0
        coeff = np.linalg.lstsq(x[:, known].T, row[known], rcond=None)[0]
        np.testing.assert_allclose(h, coeff @ x, atol=1e-4)


# ---------------------------------------------------------------- batched vs naive


def _naive_recall(mem: AssociativeMemory, query: NDArray[np.int8]) -> tuple[list[float], list[int]]:
    """Per-shift, per-element Python loops; Hebbian fields written out in full."""
    m, n = mem.config.m, mem.config.n_elements
    x = mem.patterns.astype(int).tolist()
    phi_m = ternary(hebbian_matrix(mem.patterns), 0.0).astype(int).tolist()
    best_key: list[tuple[int, int]] = [(-(10**9), 0)] * len(x)
    best_shift = [0] * len(x)
    for s in range(m):
        y = [int(query[(e % m - s) % m + m * (e // m)]) for e in range(n)]
        if mem.rule == "hebbian":
            h = [sum(phi_m[i][j] * y[j] for j in range(n)) for i in range(n)]
            z = [1 if v > 0 else (-1 if v < 0 else 0) for v in h]
        else:
            z = ternary(mem.operator.fields(np.array(y, float)), mem.operator.epsilon).tolist()
        for k, xk in enumerate(x):
            key = (sum(a * b for a, b in zip(xk, z, strict=True)),
                   sum(a * b for a, b in zip(xk, y, strict=True)))  # fmt: skip
            if key > best_key[k]:
                best_key[k], best_shift[k] = key, s
    return [key[0] / n for key in best_key], best_shift


@pytest.mark.parametrize("rule", sorted(RECALL_RULES))
def test_batched_all_shift_recall_equals_naive_loops(
    memories: dict[str, AssociativeMemory], rule: str
) -> None:
    rng = np.random.default_rng(5)
    mem = memories[rule]
    queries = rng.choice(np.array([-1, 0, 1], dtype=np.int8), size=(6, 48), p=[0.5, 0.2, 0.3])
    queries[0] = mem.patterns[2]
    result = mem.recall(queries)
    for q, y in enumerate(queries):
        corr, shift = _naive_recall(mem, y)
        np.testing.assert_allclose(result.correlations[q], corr)
        np.testing.assert_array_equal(result.best_shift[q], shift)
    # Verdict: best correlation, then best evidence; several equal -> undecided (-1).
    for q in range(len(queries)):
        keys = list(zip(result.correlations[q], result.evidence[q], strict=True))
        best = [k for k in range(5) if keys[k] == max(keys)]
        assert result.recognised_index[q] == (best[0] if len(best) == 1 else -1)
        assert result.tied[q] == tuple(sorted(SHAPES[k] for k in best))


# ---------------------------------------------------------------- result, shapes, ties


def test_result_shapes_dtypes_and_single_query(memories: dict[str, AssociativeMemory]) -> None:
    mem = memories["projection"]
    result = mem.recall(np.ones((7, 48), dtype=np.int8))
    assert result.correlations.shape == (7, 5) and result.correlations.dtype == np.float64
    assert result.best_shift.shape == (7, 5) and result.best_shift.dtype == np.int64
    assert result.evidence.shape == (7, 5)
    assert result.recalled.shape == (7, 48) and result.recalled.dtype == np.int8
    assert result.margin.shape == (7,) and np.all(result.margin >= 0)
    assert len(result.recognised) == 7 and result.names == SHAPES
    single = mem.recall(mem.patterns[1])
    assert single.correlations.shape == (1, 5)
    assert single.recognised == ("square",)
    assert single.correlations[0, 1] == 1.0
    np.testing.assert_array_equal(single.recalled[0], mem.patterns[1])
    empty = mem.recall(np.zeros((0, 48)))
    assert empty.correlations.shape == (0, 5) and empty.recognised == ()


def test_best_shift_sign_convention() -> None:
    """A query rotated by +t sectors matches its pattern at shift (m - t) mod m."""
    rng = np.random.default_rng(6)
    x = rng.choice(np.array([-1, 1], dtype=np.int8), size=(4, 48))
    mem = AssociativeMemory(("a", "b", "c", "d"), x, ChainCodeConfig(), "projection")
    for t in (0, 1, 5, 11):
        rotated = all_cyclic_shifts(x)[:, t]  # (4, 48): every pattern turned by +t sectors
        result = mem.recall(rotated)
        assert result.recognised == ("a", "b", "c", "d")
        np.testing.assert_array_equal(np.diag(result.best_shift), (12 - t) % 12)
        np.testing.assert_array_equal(np.diag(result.correlations), 1.0)
        np.testing.assert_array_equal(result.recalled, x)


def test_a_tie_is_undecided_never_the_first_name() -> None:
    x = np.ones((2, 48), dtype=np.int8)
    x[1, 0] = -1
    mem = AssociativeMemory(("second", "first"), x, rule="hebbian")
    # All-unknown query: every recall is 0, every score 0 -> undecided, margin 0.
    result = mem.recall(np.zeros(48))
    assert result.recognised == (None,) and result.recognised_index[0] == -1
    assert result.tied == (("first", "second"),)
    assert result.verdicts == ("undecided between first and second",)
    assert not result.decided[0]
    assert result.margin[0] == 0.0
    np.testing.assert_array_equal(result.best_shift[0], [0, 0])
    # One stored pattern: margin is infinite.
    solo = AssociativeMemory(("only",), x[:1])
    assert solo.recall(x[0]).margin[0] == np.inf


@pytest.mark.parametrize("rule", ["hebbian", "projection"])
def test_evidence_breaks_a_tie_in_correlation(rule: str) -> None:
    cfg = ChainCodeConfig(m=4, l=1, thresholds=(0.2,))
    x = np.array([[-1, 1, 1, -1], [1, 1, 1, -1]], dtype=np.int8)
    mem = AssociativeMemory(("a", "b"), x, cfg, rule)
    # Both patterns are recalled cleanly (c = 1), but the query is "b" turned
    # by one sector, so "b" agrees with the evidence at every element.
    result = mem.recall([-1, 1, 1, 1])
    np.testing.assert_array_equal(result.correlations[0], [1.0, 1.0])
    np.testing.assert_array_equal(result.evidence[0], [0.5, 1.0])
    assert result.recognised == ("b",) and result.tied == (("b",),)
    assert result.best_shift[0, 1] == 3
    assert result.margin[0] == 0.0  # the gap in c; the evidence decided


def test_tie_tolerance_widens_ties_and_is_validated() -> None:
    cfg = ChainCodeConfig(m=4, l=1, thresholds=(0.2,))
    x = np.array([[1, 1, 1, -1], [1, -1, -1, -1]], dtype=np.int8)
    mem = AssociativeMemory(("a", "b"), x, cfg, "matched")
    query = [1, 1, -1, 0]  # c = 0.75 against "a" (shift 1), 0.25 against "b"
    assert mem.recall(query).recognised == ("a",)
    assert mem.recall(query).margin[0] == pytest.approx(0.5)
    assert mem.recall(query, tie_tolerance=0.49).recognised == ("a",)
    wide = mem.recall(query, tie_tolerance=0.5)
    assert wide.recognised == (None,) and wide.tied == (("a", "b"),)
    with pytest.raises(InputError, match="tie_tolerance"):
        mem.recall(query, tie_tolerance=-1.0)


@pytest.mark.parametrize("rule", sorted(RECALL_RULES))
def test_shuffling_the_stored_shapes_changes_no_verdict(
    stored_moves: list[NDArray[np.float64]], rule: str
) -> None:
    """Acceptance "Ties": the verdicts are a specification, not a list order."""
    eq13, unknown, _ = _partial_trials(40, seed=13, low=0.05, high=1.0)
    queries = np.vstack([eq13, unknown, np.zeros((1, 48), dtype=np.int8)])
    base = memorise(SHAPES, stored_moves, rule=rule).recall(queries)
    rng = np.random.default_rng(14)
    for _ in range(3):
        order = rng.permutation(5)
        names = [SHAPES[k] for k in order]
        shuffled = memorise(names, [stored_moves[k] for k in order], rule=rule).recall(queries)
        assert shuffled.verdicts == base.verdicts
        assert shuffled.tied == base.tied
        np.testing.assert_array_equal(shuffled.margin, base.margin)
        np.testing.assert_array_equal(shuffled.correlations, base.correlations[:, order])


# ---------------------------------------------------------------- the five shapes


def _recognition_rate(
    mem: AssociativeMemory, queries: NDArray[np.int8], labels: NDArray[np.int64]
) -> float:
    return float(np.mean(mem.recall(queries).recognised_index == labels))


def test_five_shape_codes(memories: dict[str, AssociativeMemory]) -> None:
    """The codes follow from the per-sector fractions named in rounding_thresholds."""
    table = memories["hebbian"].patterns.reshape(5, 4, 12)
    plus_per_level = (table == 1).sum(axis=2)  # (shape, level)
    assert plus_per_level.tolist() == [
        [12, 0, 0, 0],  # circle: 1/12 per sector
        [4, 4, 4, 0],  # square: 1/4 in 4 sectors
        [3, 3, 3, 3],  # triangle: 1/3 in 3 sectors
        [5, 5, 0, 0],  # star: ~0.19 in 5 sectors (collinear edge pairs)
        [6, 6, 0, 0],  # hexagon: 1/6 in 6 sectors
    ]


def test_full_contours_at_random_rotations(memories: dict[str, AssociativeMemory]) -> None:
    """20 random rotations (not multiples of 30 deg) per shape, full contours."""
    rng = np.random.default_rng(7)
    rotations = rng.uniform(0.0, 2.0 * np.pi, size=(5, 20))
    queries = np.array(
        [
            chain_code_from_moves(contour_moves_mm(name, rotation_rad=a))
            for name, angles in zip(SHAPES, rotations, strict=True)
            for a in angles
        ]
    )
    labels = np.repeat(np.arange(5), 20)
    # Improved rules: every full contour recognised, with a positive margin.
    for rule in ("zero_mean", "projection", "masked_projection"):
        result = memories[rule].recall(queries)
        assert np.all(result.recognised_index == labels), rule
        assert np.all(result.margin > 0), rule
    # Faithful rule (golden, measured): the shared -1 elements pull the square,
    # triangle and star to the hexagon; circle and hexagon are right -> 40 %.
    # Every verdict is decided by c or, where c ties (margin 0), by the evidence:
    # none by list order (test_shuffling_the_stored_shapes_changes_no_verdict).
    faithful = memories["hebbian"].recall(queries)
    assert faithful.decided.all()
    by_shape = {
        name: Counter(faithful.recognised[20 * i : 20 * (i + 1)]) for i, name in enumerate(SHAPES)
    }
    assert by_shape == {
        "circle": {"circle": 20},
        "square": {"hexagon": 20},
        "triangle": {"hexagon": 20},
        "star": {"hexagon": 20},
        "hexagon": {"hexagon": 20},
    }
    assert _recognition_rate(memories["hebbian"], queries, labels) == pytest.approx(0.4)


def _partial_trials(
    n_trials: int, seed: int, low: float, high: float
) -> tuple[NDArray[np.int8], NDArray[np.int8], NDArray[np.int64]]:
    rng = np.random.default_rng(seed)
    labels = rng.integers(0, 5, size=n_trials)
    eq13, unknown = [], []
    for k in labels:
        s = rng.uniform(low, high)
        moves = contour_moves_mm(
            SHAPES[k], rotation_rad=rng.uniform(0, 2 * np.pi), start=rng.uniform(), fraction=s
        )
        eq13.append(chain_code_from_moves(moves))
        unknown.append(partial_chain_code_from_moves(moves, coverage=s))
    return np.array(eq13), np.array(unknown), labels


def test_partial_contours(memories: dict[str, AssociativeMemory]) -> None:
    """Half to all of the contour from a random start point, random rotation.

    Measured with seed 8, 150 trials, s in [0.5, 1] (seeds 11 and 12 agree
    within a few %), Eq. 13 codes / 0 = unknown codes: hebbian 0.29 / 0.50;
    zero_mean 0.89 / 0.75; projection 0.99 / 0.96; masked_projection
    0.99 / 1.00. The floors below sit a few trials under those figures.
    """
    eq13, unknown, labels = _partial_trials(150, seed=8, low=0.5, high=1.0)
    rate = {
        (rule, name): _recognition_rate(memories[rule], codes, labels)
        for rule in RECALL_RULES
        for name, codes in (("eq13", eq13), ("unknown", unknown))
    }
    assert rate["masked_projection", "unknown"] >= 0.97
    assert rate["projection", "eq13"] >= 0.95
    assert rate["projection", "unknown"] >= 0.92
    # The improved rules beat the paper's on the same trials.
    assert rate["projection", "eq13"] > rate["hebbian", "eq13"] + 0.5


def test_short_partial_contours_need_unknown_elements(
    memories: dict[str, AssociativeMemory],
) -> None:
    """30-50 % of the contour: the plain Eq. 13 code of a short trace misleads.

    Measured with seed 8, 150 trials, Eq. 13 codes / 0 = unknown codes:
    hebbian 0.28 / 0.91; projection 0.76 / 0.89; masked_projection 0.76 / 0.93.
    """
    eq13, unknown, labels = _partial_trials(150, seed=8, low=0.3, high=0.5)
    masked = memories["masked_projection"]
    assert _recognition_rate(masked, unknown, labels) >= 0.9
    assert (
        _recognition_rate(masked, unknown, labels) > _recognition_rate(masked, eq13, labels) + 0.1
    )
    hebbian = memories["hebbian"]
    assert (
        _recognition_rate(hebbian, unknown, labels) > _recognition_rate(hebbian, eq13, labels) + 0.4
    )


def test_recall_is_deterministic(stored_moves: list[NDArray[np.float64]]) -> None:
    a = memorise(SHAPES, stored_moves, rule="masked_projection")
    b = memorise(SHAPES, stored_moves, rule="masked_projection")
    np.testing.assert_array_equal(a.patterns, b.patterns)
    _, queries, _ = _partial_trials(20, seed=9, low=0.3, high=0.9)
    ra, rb = a.recall(queries), b.recall(queries)
    for field in dataclasses.fields(ra):
        np.testing.assert_array_equal(getattr(ra, field.name), getattr(rb, field.name))


# ---------------------------------------------------------------- memory object


def test_memorise_accepts_codes_or_moves(stored_moves: list[NDArray[np.float64]]) -> None:
    codes = np.array([chain_code_from_moves(m) for m in stored_moves])
    from_codes = memorise(SHAPES, codes)
    from_moves = memorise(SHAPES, stored_moves)
    mixed = memorise(SHAPES, [codes[0], *stored_moves[1:]])
    for mem in (from_codes, from_moves, mixed):
        np.testing.assert_array_equal(mem.patterns, codes)
        assert mem.patterns.dtype == np.int8
        assert mem.rule == "hebbian"


def test_memory_is_immutable(memories: dict[str, AssociativeMemory]) -> None:
    mem = memories["hebbian"]
    with pytest.raises(dataclasses.FrozenInstanceError):
        mem.rule = "projection"  # type: ignore[misc]
    with pytest.raises(ValueError, match="read-only"):
        mem.patterns[0, 0] = 1
    source = np.ones((1, 48), dtype=np.int8)
    solo = AssociativeMemory(("one",), source)
    source[0, 0] = -1
    assert solo.patterns[0, 0] == 1


def test_with_pattern_returns_a_new_memory(
    memories: dict[str, AssociativeMemory], stored_moves: list[NDArray[np.float64]]
) -> None:
    mem = memories["projection"]
    bigger = mem.with_pattern("square again", stored_moves[1][::-1] * -1.0)
    assert mem.n_patterns == 5 and bigger.n_patterns == 6
    assert bigger.names[-1] == "square again" and bigger.rule == "projection"
    np.testing.assert_array_equal(bigger.patterns[5], mem.patterns[1])
    other = mem.with_rule("hebbian")
    assert other.rule == "hebbian" and mem.rule == "projection"
    with pytest.raises(InputError, match="unique"):
        mem.with_pattern("circle", mem.patterns[0])


def test_arrays_round_trip_through_npz(memories: dict[str, AssociativeMemory]) -> None:
    mem = memories["masked_projection"]
    buffer = io.BytesIO()
    np.savez(buffer, **mem.to_arrays())
    buffer.seek(0)
    with np.load(buffer, allow_pickle=False) as loaded:
        back = AssociativeMemory.from_arrays(loaded)
    assert back.names == mem.names and back.rule == mem.rule and back.config == mem.config
    np.testing.assert_array_equal(back.patterns, mem.patterns)
    query = np.asarray(mem.patterns[3])
    np.testing.assert_array_equal(back.recall(query).correlations, mem.recall(query).correlations)


def _broken(key: str, value: object) -> dict[str, object]:
    arrays: dict[str, object] = dict(memorise(SHAPES, np.ones((5, 48))).to_arrays())
    if value is None:
        del arrays[key]
    else:
        arrays[key] = value
    return arrays


@pytest.mark.parametrize(
    ("key", "value", "match"),
    [
        ("patterns", None, "missing"),
        ("format_version", np.array(2), "format_version must be 1"),
        ("names", np.array([1, 2, 3, 4, 5]), "unicode"),
        ("names", np.array(["a", "a", "b", "c", "d"]), "unique"),
        ("names", np.array(["a", "", "b", "c", "d"]), "non-empty"),
        ("names", np.array(["a", "b"]), "one row per name"),
        ("patterns", np.zeros((5, 48), dtype=np.int8), "only -1 and \\+1"),
        ("patterns", np.ones((5, 47), dtype=np.int8), r"shape \(K, 48\)"),
        ("patterns", np.ones((5, 48)), "integer array"),
        ("rule", np.array("nearest"), "rule must be one of"),
        ("rule", np.array(["hebbian"]), "0-d unicode"),
        ("m", np.array(12.0), "0-d integer"),
        ("thresholds", np.array([0.3, 0.2, 0.4, 0.5]), "strictly increasing"),
        ("thresholds", np.array(["x"] * 4), "numeric"),
    ],
)
def test_from_arrays_rejects_bad_content(key: str, value: object, match: str) -> None:
    with pytest.raises(InputError, match=match):
        AssociativeMemory.from_arrays(_broken(key, value))  # type: ignore[arg-type]


def test_unknown_rule_lists_the_names() -> None:
    with pytest.raises(
        InputError, match="hebbian, masked_projection, matched, projection, zero_mean"
    ):
        get_recall_rule("nearest")
    with pytest.raises(InputError, match="rule must be one of"):
        memorise(SHAPES, np.ones((5, 48)), rule="nearest")
    assert RECALL_RULES["hebbian"].faithful
    assert not any(spec.faithful for name, spec in RECALL_RULES.items() if name != "hebbian")


@pytest.mark.parametrize(
    ("names", "items", "match"),
    [
        (SHAPES, np.ones((4, 48)), "one item per name"),
        ("circle", np.ones((1, 48)), "sequence of strings"),
        ((), np.ones((0, 48)), "at least one name"),
        (("a",), [np.ones((3, 3))], r"chain code \(48,\) or moves \(n, 2\)"),
        (("a",), [np.zeros(48)], "only -1 and \\+1"),
        (("a",), [np.ones(40)], r"shape \(K, 48\)"),
        (("a",), 5, "array or a sequence"),
    ],
)
def test_memorise_validation(names: object, items: object, match: str) -> None:
    with pytest.raises(InputError, match=match):
        memorise(names, items)  # type: ignore[arg-type]


@pytest.mark.parametrize(
    ("queries", "match"),
    [
        (np.ones(47), r"shape \(48,\) or \(Q, 48\)"),
        (np.ones((2, 3, 48)), r"shape \(48,\) or \(Q, 48\)"),
        (np.full(48, 2), "only -1, 0 and \\+1"),
        (np.full(48, 0.5), "only -1, 0 and \\+1"),
        ([["x"] * 48], "numeric"),
    ],
)
def test_query_validation(
    memories: dict[str, AssociativeMemory], queries: object, match: str
) -> None:
    with pytest.raises(InputError, match=match):
        memories["hebbian"].recall(queries)  # type: ignore[arg-type]


def test_matched_rule_scores_the_agreement_on_known_elements() -> None:
    """The identity memory: c of Eq. 14 is the evidence, unknown elements add nothing."""
    rng = np.random.default_rng(3)
    patterns = np.where(rng.random((4, 48)) < 0.5, -1, 1).astype(np.int8)
    memory = memorise(["a", "b", "c", "d"], patterns, rule="matched")
    query = patterns[2].copy()
    query[rng.random(48) < 0.5] = 0  # half unknown
    result = memory.recall(query)
    assert result.recognised[0] == "c"
    known = query != 0
    expected = np.sum(patterns[2][known] * query[known]) / 48
    assert result.correlations[0, 2] == pytest.approx(expected)
    np.testing.assert_allclose(result.correlations, result.evidence)
