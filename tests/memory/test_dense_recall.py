"""The dense associative memory rule: its update is the energy descent of Demircigil et al."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.memory import RECALL_RULES, AssociativeMemory, DenseRecall, ternary


def brute_force_fields(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """h_i = sum_k exp(x_k . y^(i+)) - exp(x_k . y^(i-)), element by element."""
    h = np.empty(y.shape[0])
    for i in range(y.shape[0]):
        up, down = y.copy(), y.copy()
        up[i], down[i] = 1, -1
        h[i] = np.exp(x @ up).sum() - np.exp(x @ down).sum()
    return h


def test_fields_have_the_sign_and_proportions_of_the_energy_differences() -> None:
    rng = np.random.default_rng(0)
    x = rng.choice([-1.0, 1.0], size=(9, 14))
    y = rng.choice([-1.0, 0.0, 1.0], size=(6, 14))
    h = DenseRecall(x).fields(y)
    for q in range(6):
        exact = brute_force_fields(x, y[q])
        # the rule drops the common factor exp(max overlap)
        np.testing.assert_allclose(h[q] * np.exp((x @ y[q]).max()), exact, rtol=1e-10)


def test_dense_recalls_a_stored_pattern_from_a_partial_noisy_cue_where_hebbian_fails() -> None:
    rng = np.random.default_rng(1)
    n, k = 96, 200  # 200 patterns: far beyond the Hebbian capacity of about 0.14 N = 13
    x = rng.choice([-1, 1], size=(k, n)).astype(np.int8)
    target = 17
    cue = x[target].astype(np.float64)
    cue[rng.choice(n, 48, replace=False)] = 0  # half unknown
    known = np.flatnonzero(cue)
    cue[rng.choice(known, 8, replace=False)] *= -1  # and 8 of the rest flipped
    dense = DenseRecall(x.astype(np.float64))
    z = ternary(dense.fields(cue[None, :]), dense.epsilon)[0]
    np.testing.assert_array_equal(z, x[target])  # the whole pattern, unknowns filled in
    hebb = RECALL_RULES["hebbian"].build(x.astype(np.float64))
    z_h = ternary(hebb.fields(cue[None, :]), hebb.epsilon)[0]
    assert np.mean(z_h == x[target]) < 0.9


def test_dense_is_a_selectable_rule_and_not_the_faithful_one() -> None:
    spec = RECALL_RULES["dense"]
    assert not spec.faithful and "Krotov" in spec.reference
    x = np.array([[1, 1, -1, -1], [1, -1, 1, -1], [-1, 1, 1, -1]], dtype=np.int8)
    from taxelkit.memory import ChainCodeConfig

    cfg = ChainCodeConfig(m=2, l=2, thresholds=(0.3, 0.6))
    mem = AssociativeMemory(("a", "b", "c"), x, cfg, "dense")
    res = mem.recall(x)
    assert res.recognised == ("a", "b", "c")


@pytest.mark.parametrize("order", [(0, 1, 2), (2, 0, 1), (1, 2, 0)])
def test_dense_verdicts_do_not_depend_on_the_order_of_the_memory(order: tuple[int, ...]) -> None:
    from taxelkit.memory import ChainCodeConfig

    cfg = ChainCodeConfig(m=3, l=2, thresholds=(0.2, 0.5))
    x = np.array([[1, -1, -1, 1, -1, -1], [1, 1, -1, -1, -1, -1], [1, 1, 1, -1, -1, -1]])
    names = ("a", "b", "c")
    queries = np.array([[1, 0, 0, 0, 0, 0], [1, 1, 0, -1, 0, 0], [0, 0, 0, 0, 0, 0]])
    mem = AssociativeMemory(tuple(names[i] for i in order), x[list(order)], cfg, "dense")
    ref = AssociativeMemory(names, x, cfg, "dense")
    assert mem.recall(queries).verdicts == ref.recall(queries).verdicts
