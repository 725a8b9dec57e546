"""The order-aware code: tangent signatures, their FFT matching, and the signature memory."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.memory import (
    SignatureMemory,
    StoredSignatures,
    chain_code_from_moves,
    signature_overlaps,
    tangent_signature,
)
from taxelkit.world.open_set_shapes import open_set_outline_mm
from taxelkit.world.relief import relief_shape

STEP_MM = 3.0


def walk(outline: np.ndarray, *, rotation_deg: float = 0.0, start: int = 0) -> np.ndarray:
    """Moves of a walk round a closed outline in 3 mm steps, turned and started elsewhere."""
    a = np.deg2rad(rotation_deg)
    rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    closed = np.vstack([outline, outline[:1]]) @ rot.T
    edges = np.diff(closed, axis=0)
    lengths = np.hypot(edges[:, 0], edges[:, 1])
    cum = np.concatenate([[0.0], np.cumsum(lengths)])
    arc = np.arange(0.0, cum[-1], STEP_MM)
    e = np.minimum(np.searchsorted(cum, arc, side="right") - 1, len(lengths) - 1)
    pts = closed[e] + edges[e] * ((arc - cum[e]) / lengths[e])[:, None]
    pts = np.roll(pts, -start, axis=0)
    return np.diff(np.vstack([pts, pts[:1]]), axis=0)


def square() -> np.ndarray:
    return relief_shape("square", diameter_mm=90.0).outline_mm()[:-1]


def l_shape() -> np.ndarray:
    return open_set_outline_mm("l-shape", diameter_mm=90.0)


def test_fft_overlaps_equal_the_direct_sum_over_every_start() -> None:
    rng = np.random.default_rng(0)
    stored = [np.exp(1j * rng.uniform(0, 6, n)) for n in (11, 23)]
    queries = [np.exp(1j * rng.uniform(0, 6, n)) for n in (4, 30)]
    r, samples = signature_overlaps(StoredSignatures(stored), queries)
    assert samples.tolist() == [4, 30]
    for q, v in enumerate(queries):
        for k, u in enumerate(stored):
            for j in range(u.size):
                direct = sum(v[t] * np.conj(u[(j + t) % u.size]) for t in range(v.size))
                assert abs(direct - r[q, k, j]) < 1e-9
            assert np.all(r[q, k, u.size :] == 0)


@pytest.mark.parametrize(("rotation_deg", "start"), [(0.0, 0), (37.0, 5), (-121.5, 17)])
def test_the_score_is_invariant_to_rotation_and_start_point(
    rotation_deg: float, start: int
) -> None:
    mem = SignatureMemory.from_moves(("square", "l"), [walk(square()), walk(l_shape())])
    res = mem.recall_moves([walk(square(), rotation_deg=rotation_deg, start=start)])
    assert res.recognised == ("square",)
    assert res.scores[0, 0] > 0.97
    turned = (
        res.rotation_deg[0, 0] - rotation_deg + 45.0
    ) % 90.0 - 45.0  # square: 90 deg symmetric
    assert abs(turned) < 3.0


def test_a_square_and_an_l_shape_share_their_chain_code_but_not_their_signature() -> None:
    sq, ls = walk(square()), walk(l_shape())
    assert np.array_equal(chain_code_from_moves(sq), chain_code_from_moves(ls))  # histogram twins
    mem = SignatureMemory.from_moves(("square", "l-shape"), [sq, ls])
    for rule in ("signature", "signature-dense"):
        res = mem.with_rule(rule).recall_moves(
            [
                walk(l_shape(), rotation_deg=70.0, start=9),
                walk(square(), rotation_deg=-20.0, start=3),
            ]
        )
        assert res.recognised == ("l-shape", "square")
        assert np.all(res.margin > 0.1)


def test_a_partial_signature_depends_only_on_the_part_traced() -> None:
    moves = walk(l_shape(), rotation_deg=15.0)
    full = tangent_signature(moves, closed=False)
    for k in (10, 25, 40):
        part = tangent_signature(moves[:k], closed=False)
        # the same samples, except the last one whose chord is cut at the end of the part
        np.testing.assert_allclose(part[:-2], full[: part.size - 2], atol=1e-12)


def test_equal_signatures_are_undecided_whatever_the_order() -> None:
    sq = walk(square())
    names = ("b", "a", "c")
    mem = SignatureMemory.from_moves(names, [sq, sq, walk(l_shape())])
    flipped = mem.subset([2, 1, 0])
    q = [tangent_signature(walk(square(), start=4), closed=False)]
    for m in (mem, flipped, mem.with_rule("signature-dense")):
        res = m.recall(q)
        assert res.recognised == (None,)
        assert res.verdicts == ("undecided between a and b",)
        assert res.margin[0] == pytest.approx(0.0, abs=1e-12)


def test_the_dense_memory_completes_the_unseen_rest_of_a_contour() -> None:
    sq, ls = walk(square()), walk(l_shape())
    mem = SignatureMemory.from_moves(("square", "l-shape"), [sq, ls], rule="signature-dense")
    moves = walk(l_shape(), rotation_deg=33.0, start=7)
    cue = tangent_signature(moves[:40], closed=False)  # about 40 % of the L
    truth = tangent_signature(moves, closed=False)
    done = mem.complete(cue, truth.size - 2)
    rest = slice(cue.size, truth.size - 2)  # the part the cue never saw
    agreement = np.real(np.vdot(done[rest], truth[rest])) / (rest.stop - rest.start)
    assert agreement > 0.85


def test_bad_input_is_refused_in_one_line() -> None:
    with pytest.raises(InputError, match="non-zero move"):
        tangent_signature(np.zeros((3, 2)), closed=True)
    with pytest.raises(InputError, match="step_mm"):
        tangent_signature(np.ones((3, 2)), closed=True, step_mm=0.0)
    with pytest.raises(InputError, match="rule"):
        SignatureMemory(("a",), (np.ones(5, dtype=complex),), "hebbian")
    with pytest.raises(InputError, match="unique"):
        SignatureMemory(("a", "a"), (np.ones(5, dtype=complex),) * 2)


def test_a_short_straight_cue_fits_every_polygon_within_a_sample_and_stays_undecided() -> None:
    tri = relief_shape("triangle", diameter_mm=90.0).outline_mm()[:-1]
    mem = SignatureMemory.from_moves(("square", "triangle"), [walk(square()), walk(tri)])
    cue = walk(square(), rotation_deg=10.0, start=2)[:4]  # 12 mm of one straight side
    res = mem.recall_moves([cue])
    assert res.recognised == (None,)
    assert res.verdicts == ("undecided between square and triangle",)
    assert res.margin[0] < 1.0 / 5  # within one of the cue's five samples


def test_the_dense_beta_keeps_k_minus_1_runners_up_below_one_over_e() -> None:
    from taxelkit.memory.signature_memory import dense_beta

    assert dense_beta(1) == dense_beta(2) == 1.0
    for k in (5, 100, 200):
        beta = dense_beta(k)
        assert (k - 1) * np.exp(-beta) == pytest.approx(np.exp(-1.0))
    mem = SignatureMemory.from_moves(
        ("a", "b", "c"), [walk(square()), walk(l_shape()), walk(square(), rotation_deg=45.0)]
    )
    assert mem.beta == pytest.approx(1 + np.log(2))
    assert mem.with_rule("signature-dense", 1.0).beta == 1.0
    with pytest.raises(InputError, match="beta_per_sample"):
        mem.with_rule("signature-dense", -1.0)
