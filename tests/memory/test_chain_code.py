"""Chain-symbolizing (paper 000, Eq. 13): histogram, quantisation, rotation, partial traces."""

from __future__ import annotations

import dataclasses
import doctest
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from taxelkit.errors import InputError
from taxelkit.memory import (
    DEFAULT_CHAIN_CODE,
    ChainCodeConfig,
    all_cyclic_shifts,
    chain_code,
    chain_code_from_directions,
    chain_code_from_histogram,
    chain_code_from_moves,
    code_rotation,
    cyclic_shift_index,
    direction_histogram,
    directions_from_moves,
    histogram_from_directions,
    histogram_from_moves,
    partial_chain_code_from_histogram,
    partial_chain_code_from_moves,
    partial_code,
    relative_frequency,
    rounding_thresholds,
)

SMALL = ChainCodeConfig(m=4, l=2, thresholds=(0.2, 0.5))

#: Directions closer than this to a sector boundary are avoided where a test
#: rotates them (rounding of the rotation could move them across), rad.
BOUNDARY_GUARD_RAD = 1e-6


def _rotation(angle_rad: float) -> np.ndarray:
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[c, -s], [s, c]])


@pytest.mark.parametrize("module", [chain_code, code_rotation, direction_histogram, partial_code])
def test_docstring_examples(module: object) -> None:
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS)  # type: ignore[arg-type]
    assert result.attempted > 0
    assert result.failed == 0


# ---------------------------------------------------------------- config


def test_default_config_is_the_papers() -> None:
    cfg = DEFAULT_CHAIN_CODE
    assert (cfg.m, cfg.l, cfg.n_elements) == (12, 4, 48)
    assert cfg.thresholds == pytest.approx((1 / 24, 3 / 24, 5 / 24, 7 / 24))
    assert cfg.sector_width_rad == pytest.approx(math.radians(30.0))
    assert ChainCodeConfig() == cfg
    with pytest.raises(dataclasses.FrozenInstanceError):
        cfg.m = 6  # type: ignore[misc]


def test_rounding_thresholds_are_midpoints_of_multiples_of_one_over_m() -> None:
    d = rounding_thresholds(12, 4)
    for j, dj in enumerate(d, start=1):
        assert dj == pytest.approx(((j - 1) / 12 + j / 12) / 2)
    assert ChainCodeConfig(m=8, l=3).thresholds == pytest.approx((1 / 16, 3 / 16, 5 / 16))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"thresholds": (0.1, 0.3, 0.2, 0.4)}, "strictly increasing"),
        ({"thresholds": (0.1, 0.1, 0.2, 0.4)}, "strictly increasing"),
        ({"thresholds": (0.0, 0.1, 0.2, 0.4)}, r"thresholds\[0\] must be in \(0, 1\]"),
        ({"thresholds": (0.1, 0.2, 0.3, 1.5)}, r"thresholds\[3\] must be in \(0, 1\]"),
        ({"thresholds": (0.1, float("nan"), 0.3, 0.4)}, r"thresholds\[1\]"),
        ({"thresholds": (0.1, 0.2, 0.3)}, "must have l=4 values, got 3"),
        ({"thresholds": ("a", "b", "c", "d")}, "sequence of numbers"),
        ({"m": 0}, "m must be an integer >= 1, got 0"),
        ({"l": True}, "l must be an integer >= 1, got True"),
        ({"m": 2.5}, "m must be an integer"),
        ({"m": 3, "l": 4}, "l must be <= m"),
    ],
)
def test_config_validation(kwargs: dict[str, object], match: str) -> None:
    with pytest.raises(InputError, match=match):
        ChainCodeConfig(**kwargs)  # type: ignore[arg-type]


def test_explicit_thresholds_are_kept_as_floats() -> None:
    cfg = ChainCodeConfig(m=4, l=2, thresholds=(np.float32(0.25), 1))  # type: ignore[arg-type]
    assert cfg.thresholds == (0.25, 1.0)
    assert all(type(v) is float for v in cfg.thresholds)


# ---------------------------------------------------------------- Eq. 13


def test_eq13_by_hand() -> None:
    # f = (0.3, 0.1, 0.0, 0.6); d = (0.2, 0.5)
    code = chain_code_from_histogram([3, 1, 0, 6], config=SMALL)
    assert code.dtype == np.int8
    assert code.tolist() == [1, -1, -1, 1, -1, -1, -1, 1]
    # The paper's 1-based element i + m (j - 1) is 0-based index (i - 1) + m (j - 1).
    f = np.array([0.3, 0.1, 0.0, 0.6])
    for i in range(1, 5):
        for j in range(1, 3):
            expected = 1 if f[i - 1] >= SMALL.thresholds[j - 1] else -1
            assert code[(i - 1) + SMALL.m * (j - 1)] == expected
    assert code.reshape(SMALL.l, SMALL.m)[1].tolist() == [-1, -1, -1, 1]


def test_eq13_threshold_is_inclusive() -> None:
    # f = (0.5, 0.5, 0, 0): exactly at d_2 = 0.5 gives +1 (f(i) >= d_j).
    assert chain_code_from_histogram([1, 1, 0, 0], config=SMALL).tolist() == [
        1, 1, -1, -1, 1, 1, -1, -1,
    ]  # fmt: skip


def test_relative_frequency_makes_the_code_length_independent() -> None:
    counts = np.array([3, 1, 0, 6, 0, 0, 2, 0, 0, 1, 0, 7])
    np.testing.assert_array_equal(
        chain_code_from_histogram(counts), chain_code_from_histogram(10 * counts)
    )
    np.testing.assert_allclose(relative_frequency(counts).sum(), 1.0)


@given(st.lists(st.integers(0, 50), min_size=12, max_size=12).filter(lambda c: sum(c) > 0))
@settings(max_examples=60, deadline=None)
def test_code_is_thermometer_per_sector(counts: list[int]) -> None:
    """Thresholds increase, so within a sector the +1 levels come first."""
    table = chain_code_from_histogram(counts).reshape(4, 12)
    assert set(np.unique(table)) <= {-1, 1}
    assert np.all(np.diff(table, axis=0) <= 0)


@pytest.mark.parametrize(
    ("counts", "match"),
    [
        ([0, 0, 0, 0], "at least one move"),
        ([1, 2, 3], r"shape \(4,\)"),
        ([1, -2, 3, 0], ">= 0"),
        ([1, np.inf, 3, 0], "finite"),
    ],
)
def test_histogram_validation(counts: list[float], match: str) -> None:
    with pytest.raises(InputError, match=match):
        chain_code_from_histogram(counts, config=SMALL)


# ---------------------------------------------------------------- directions, histogram


def test_sectors_are_half_open_and_boundaries_are_stable() -> None:
    m = 12
    width = 2 * math.pi / m
    boundaries = width * np.arange(m)
    np.testing.assert_array_equal(histogram_from_directions(boundaries, m=m), np.ones(m))
    just_below = boundaries + width - 1e-6
    np.testing.assert_array_equal(histogram_from_directions(just_below, m=m), np.ones(m))
    # Directions computed from moves that lie exactly along 0, 90, 180, 270 deg.
    moves = 3.0 * np.array([[1, 0], [0, 1], [-1, 0], [0, -1]], dtype=float)
    np.testing.assert_array_equal(np.flatnonzero(histogram_from_moves(moves)), [0, 3, 6, 9])
    # Same through rotation by 90 deg in floating point.
    turned = moves @ _rotation(math.pi / 2).T
    np.testing.assert_array_equal(np.flatnonzero(histogram_from_moves(turned)), [0, 3, 6, 9])


def test_directions_wrap_and_zero_moves_are_ignored() -> None:
    assert histogram_from_directions([-0.1, 2 * math.pi + 0.1], m=4).tolist() == [1, 0, 0, 1]
    moves = [[3.0, 0.0], [0.0, 0.0], [1e-12, 0.0], [0.0, -3.0]]
    theta = directions_from_moves(moves)
    np.testing.assert_allclose(theta, [0.0, 1.5 * math.pi])
    assert histogram_from_moves(moves, m=4).tolist() == [1, 0, 0, 1]
    with pytest.raises(InputError, match="at least one move"):
        chain_code_from_moves([[0.0, 0.0]])


@pytest.mark.parametrize(
    ("moves", "match"),
    [
        (np.zeros((3, 3)), r"shape \(K, 2\)"),
        (np.zeros(4), r"shape \(K, 2\)"),
        ([[1.0, np.nan]], "finite"),
        ([["a", "b"]], "numeric"),
    ],
)
def test_moves_validation(moves: object, match: str) -> None:
    with pytest.raises(InputError, match=match):
        chain_code_from_moves(moves)  # type: ignore[arg-type]


def test_directions_validation() -> None:
    with pytest.raises(InputError, match=r"shape \(K,\)"):
        histogram_from_directions(np.zeros((2, 2)))
    with pytest.raises(InputError, match="finite"):
        histogram_from_directions([0.1, np.inf])


def test_translation_invariance() -> None:
    rng = np.random.default_rng(3)
    points = rng.normal(size=(40, 2)) * 20.0
    shifted = points + np.array([123.0, -45.6])
    np.testing.assert_array_equal(
        chain_code_from_moves(np.diff(points, axis=0)),
        chain_code_from_moves(np.diff(shifted, axis=0)),
    )


# ---------------------------------------------------------------- rotation


def test_all_cyclic_shifts_layout_and_sign() -> None:
    x = np.arange(SMALL.n_elements)
    shifts = all_cyclic_shifts(x, config=SMALL)
    assert shifts.shape == (SMALL.m, SMALL.n_elements)
    assert shifts.dtype == x.dtype
    np.testing.assert_array_equal(shifts[0], x)
    # Shift +1: element i goes to i + 1 inside each block; the last wraps to the first.
    assert shifts[1].tolist() == [3, 0, 1, 2, 7, 4, 5, 6]
    for s in range(SMALL.m):
        blocks = np.roll(x.reshape(SMALL.l, SMALL.m), s, axis=1).reshape(-1)
        np.testing.assert_array_equal(shifts[s], blocks)


def test_all_cyclic_shifts_batched_and_index_table() -> None:
    rng = np.random.default_rng(0)
    codes = rng.choice(np.array([-1, 0, 1], dtype=np.int8), size=(5, 7, 48))
    out = all_cyclic_shifts(codes)
    assert out.shape == (5, 7, 12, 48)
    assert out.dtype == np.int8
    np.testing.assert_array_equal(out[3, 2], all_cyclic_shifts(codes[3, 2]))
    table = cyclic_shift_index()
    assert table.shape == (12, 48)
    assert not table.flags.writeable
    with pytest.raises(InputError, match=r"shape \(\.\.\., 48\)"):
        all_cyclic_shifts(np.zeros(47))


@given(
    st.lists(st.floats(0.0, 2 * math.pi, exclude_max=True), min_size=1, max_size=60),
    st.integers(0, 11),
)
@settings(max_examples=80, deadline=None)
def test_rotating_directions_by_k_sectors_shifts_the_code_by_k(
    directions: list[float], k: int
) -> None:
    theta = np.asarray(directions)
    position = theta * 12 / (2 * math.pi)
    keep = np.abs(position - np.rint(position)) * (2 * math.pi / 12) > BOUNDARY_GUARD_RAD
    if not keep.any():
        return
    theta = theta[keep]
    code = chain_code_from_directions(theta)
    rotated = chain_code_from_directions(theta + k * math.radians(30.0))
    np.testing.assert_array_equal(rotated, all_cyclic_shifts(code)[k])
    # The same through the moves, rotated by a rotation matrix (counter-clockwise).
    moves = 3.0 * np.stack([np.cos(theta), np.sin(theta)], axis=1)
    turned = moves @ _rotation(k * math.radians(30.0)).T
    np.testing.assert_array_equal(chain_code_from_moves(turned), all_cyclic_shifts(code)[k])


# ---------------------------------------------------------------- partial traces


@given(st.lists(st.integers(0, 40), min_size=12, max_size=12).filter(lambda c: sum(c) > 0))
@settings(max_examples=60, deadline=None)
def test_partial_code_with_full_coverage_is_eq13(counts: list[int]) -> None:
    full = chain_code_from_histogram(counts)
    np.testing.assert_array_equal(partial_chain_code_from_histogram(counts, coverage=1.0), full)


@given(
    st.lists(st.integers(0, 30), min_size=12, max_size=12).filter(lambda c: sum(c) > 0),
    st.data(),
)
@settings(max_examples=100, deadline=None)
def test_partial_code_never_contradicts_the_full_trace(
    counts: list[int], data: st.DataObject
) -> None:
    """Each non-zero element of a partial code equals the full trace's Eq. 13 element."""
    full_counts = np.asarray(counts)
    seen = np.array([data.draw(st.integers(0, c)) for c in counts])
    if seen.sum() == 0:
        return
    coverage = seen.sum() / full_counts.sum()
    partial = partial_chain_code_from_histogram(seen, coverage=coverage)
    full = chain_code_from_histogram(full_counts)
    known = partial != 0
    np.testing.assert_array_equal(partial[known], full[known])


def test_partial_code_examples() -> None:
    # Half a square: two sides seen.
    moves = np.array([[3.0, 0.0]] * 10 + [[0.0, 3.0]] * 10)
    code = partial_chain_code_from_moves(moves, coverage=0.5).reshape(4, 12)
    assert code.dtype == np.int8
    assert code[:, 0].tolist() == [1, 1, 1, 0]
    assert code[:, 3].tolist() == [1, 1, 1, 0]
    assert np.all(code[:, [1, 2, 4, 5, 6, 7, 8, 9, 10, 11]] == 0)
    # The plain Eq. 13 code of the same half over-states the sides (+1 at level 4).
    assert chain_code_from_moves(moves).reshape(4, 12)[:, 0].tolist() == [1, 1, 1, 1]
    # Near the end of the trace the empty sectors become -1 at the high levels.
    late = partial_chain_code_from_moves(moves, coverage=0.9).reshape(4, 12)
    assert late[:, 1].tolist() == [0, -1, -1, -1]
    # Nothing observed: everything unknown.
    assert not np.any(partial_chain_code_from_histogram(np.zeros(12), coverage=0.3))


@pytest.mark.parametrize("coverage", [0.0, -0.1, 1.01, float("nan")])
def test_partial_code_coverage_validation(coverage: float) -> None:
    with pytest.raises(InputError, match="coverage"):
        partial_chain_code_from_histogram(np.ones(12), coverage=coverage)
