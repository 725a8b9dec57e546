"""Level 1 image statistics: closed forms, invariances, scikit-image, batching.

Closed forms take each taxel as a ``pitch x pitch`` cell (module notes of
:mod:`taxelkit.smart.moments`): a ``k x 1`` line has second moments
``k^2 / 12`` and ``1 / 12`` (pitch^2), so elongation ``k``; a diagonal line of
``k`` taxels has ``var = k^2 / 12`` on both axes and ``cov = (k^2 - 1) / 12``,
so eigenvalues ``(2 k^2 - 1) / 12`` and ``1 / 12`` and elongation
``sqrt(2 k^2 - 1)``.
"""

from __future__ import annotations

import doctest
import math
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays
from numpy.typing import NDArray

import taxelkit.smart.index_sums as index_sums_module
import taxelkit.smart.moments as moments_module
from taxelkit.errors import InputError
from taxelkit.frames import TactileFrames
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart.area_moments import moments_central, moments_of_area
from taxelkit.smart.contact_classes import HAND_SET, _forward
from taxelkit.smart.index_sums import ONE_THREAD_PRODUCT, index_sums, product_rows
from taxelkit.smart.moments import (
    CELL_SECOND_MOMENT,
    ImageStats,
    binary_images,
    frame_stats,
    image_stats,
)

PITCH = BONNEVILLE_16X16.array.pitch_mm  # 1.7625 mm
N = 16
C = (N - 1) / 2.0  # index of the array centre

Image = NDArray[np.bool_]


def blank(rows: int = N, cols: int = N) -> Image:
    return np.zeros((rows, cols), dtype=bool)


def xy_mm(i: float, j: float) -> tuple[float, float]:
    """Physical centre of taxel (row i, column j) on the 16 x 16 array."""
    return ((j - C) * PITCH, (i - C) * PITCH)


def stats_of(*images: Image, pitch: float = PITCH) -> ImageStats:
    return image_stats(np.stack(images), pitch_mm=pitch)


def same(a: Any, b: Any) -> None:
    """Bit-for-bit equality that treats NaN as equal to NaN."""
    np.testing.assert_array_equal(np.asarray(a), np.asarray(b))


def angle_diff_mod_180(a: float, b: float) -> float:
    """``a - b`` reduced to ``[-90, 90)``."""
    return (a - b + 90.0) % 180.0 - 90.0


# --------------------------------------------------------------------- closed forms


def test_single_taxel() -> None:
    img = blank()
    img[3, 11] = True
    s = stats_of(img).frame(0)
    assert s.n_taxels == 1
    assert s.area_mm2 == pytest.approx(PITCH**2, rel=1e-15)
    assert s.centre_mm == pytest.approx(xy_mm(3, 11), abs=1e-12)
    assert s.elongation == 1.0
    assert s.orientation_deg == 0.0  # isotropic: atan2(0, 0)
    assert s.var_x_mm2 == pytest.approx(PITCH**2 / 12, rel=1e-14)
    assert s.var_y_mm2 == pytest.approx(PITCH**2 / 12, rel=1e-14)
    assert s.cov_xy_mm2 == 0.0


@pytest.mark.parametrize("k", [2, 3, 6, 16])
def test_horizontal_and_vertical_lines(k: int) -> None:
    h = blank()
    h[5, 0:k] = True
    v = blank()
    v[0:k, 9] = True
    s = stats_of(h, v)
    assert s.elongation[0] == pytest.approx(k, rel=1e-12)
    assert s.elongation[1] == pytest.approx(k, rel=1e-12)
    assert s.orientation_deg[0] == 0.0
    assert s.orientation_deg[1] == 90.0
    np.testing.assert_allclose(s.area_mm2, k * PITCH**2, rtol=1e-14)
    np.testing.assert_allclose(s.centre_mm[0], xy_mm(5, (k - 1) / 2), atol=1e-12)
    np.testing.assert_allclose(s.centre_mm[1], xy_mm((k - 1) / 2, 9), atol=1e-12)
    assert s.var_x_mm2[0] == pytest.approx(k * k * PITCH**2 / 12, rel=1e-12)


@pytest.mark.parametrize("k", [2, 4, 7])
def test_diagonal_lines(k: int) -> None:
    d = blank()
    a = blank()
    for t in range(k):
        d[2 + t, 3 + t] = True  # along x = y
        a[2 + t, 12 - t] = True  # along x = -y
    s = stats_of(d, a)
    expected = math.sqrt(2 * k * k - 1)
    np.testing.assert_allclose(s.elongation, expected, rtol=1e-12)
    assert s.orientation_deg[0] == pytest.approx(45.0, abs=1e-12)
    assert s.orientation_deg[1] == pytest.approx(-45.0, abs=1e-12)


@pytest.mark.parametrize("radius", [1.5, 3.0, 5.2, 7.4])
def test_filled_disc(radius: float) -> None:
    i, j = np.mgrid[0:N, 0:N]
    img = (i - C) ** 2 + (j - C) ** 2 <= radius**2
    s = stats_of(img).frame(0)
    assert s.area_mm2 == pytest.approx(img.sum() * PITCH**2, rel=1e-14)
    # symmetric under a quarter turn: exactly isotropic
    assert s.elongation == 1.0
    assert s.centre_mm == pytest.approx((0.0, 0.0), abs=1e-12)


@pytest.mark.parametrize(("a", "b"), [(2, 1), (4, 3), (5, 2), (9, 4), (3, 3)])
def test_rectangle(a: int, b: int) -> None:
    wide = blank()
    wide[4 : 4 + b, 2 : 2 + a] = True  # a along x, b along y
    tall = wide.T.copy()
    s = stats_of(wide, tall)
    np.testing.assert_allclose(s.elongation, a / b, rtol=1e-12)
    if a != b:
        assert s.orientation_deg.tolist() == [0.0, 90.0]
    # the cell term gives the continuous rectangle's second moments
    assert s.var_x_mm2[0] == pytest.approx((a * PITCH) ** 2 / 12, rel=1e-12)
    assert s.var_y_mm2[0] == pytest.approx((b * PITCH) ** 2 / 12, rel=1e-12)


def test_moments_of_area_closed_form_rectangle() -> None:
    img = blank()
    img[1:4, 10:15] = True  # x from (10 - C - 1/2) p to (15 - C - 1/2) p
    x0, x1 = (10 - C - 0.5) * PITCH, (15 - C - 0.5) * PITCH
    y0, y1 = (1 - C - 0.5) * PITCH, (4 - C - 0.5) * PITCH
    m = moments_of_area(img[None], pitch_mm=PITCH, order=3)[0]
    for p in range(4):
        for q in range(4):
            ix = (x1 ** (p + 1) - x0 ** (p + 1)) / (p + 1)
            iy = (y1 ** (q + 1) - y0 ** (q + 1)) / (q + 1)
            assert m[p, q] == pytest.approx(ix * iy, rel=1e-12, abs=1e-9)


def test_stats_agree_with_moments() -> None:
    rng = np.random.default_rng(5)
    imgs = rng.random((20, N, N)) < 0.2
    imgs[3] = False
    s = image_stats(imgs, pitch_mm=PITCH)
    m = moments_of_area(imgs, pitch_mm=PITCH)
    mu = moments_central(imgs, pitch_mm=PITCH)
    m00 = m[:, 0, 0]
    np.testing.assert_allclose(s.area_mm2, m00, rtol=1e-12)
    full = m00 > 0
    np.testing.assert_allclose(s.centre_mm[full, 0], m[full, 1, 0] / m00[full], atol=1e-10)
    np.testing.assert_allclose(s.centre_mm[full, 1], m[full, 0, 1] / m00[full], atol=1e-10)
    np.testing.assert_allclose(s.var_x_mm2[full], mu[full, 2, 0] / m00[full], rtol=1e-10)
    np.testing.assert_allclose(s.var_y_mm2[full], mu[full, 0, 2] / m00[full], rtol=1e-10)
    np.testing.assert_allclose(
        s.cov_xy_mm2[full], mu[full, 1, 1] / m00[full], rtol=1e-9, atol=1e-12
    )
    np.testing.assert_allclose(mu[full, 1, 0], 0.0, atol=1e-9)
    np.testing.assert_allclose(mu[full, 0, 1], 0.0, atol=1e-9)
    assert np.all(mu[~full] == 0.0)


def test_empty_frames() -> None:
    s = stats_of(blank(), blank())
    assert s.n_taxels.tolist() == [0, 0]
    assert s.area_mm2.tolist() == [0.0, 0.0]
    assert s.is_empty.tolist() == [True, True]
    for name in ("orientation_deg", "elongation", "var_x_mm2", "var_y_mm2", "cov_xy_mm2"):
        assert np.all(np.isnan(getattr(s, name))), name
    assert np.all(np.isnan(s.centre_mm))
    assert frame_stats(blank(), pitch_mm=PITCH).is_empty


def test_no_frames() -> None:
    s = image_stats(np.zeros((0, 4, 5), bool), pitch_mm=1.0)
    assert s.n_frames == 0
    assert s.centre_mm.shape == (0, 2)


# --------------------------------------------------------------------- invariances


@st.composite
def blobs(draw: st.DrawFn) -> Image:
    """A random binary image within an 8 x 8 window of a 16 x 16 array."""
    window = draw(arrays(np.bool_, (8, 8)))
    img = blank()
    img[4:12, 4:12] = window
    return img


@settings(max_examples=60, deadline=None)
@given(blobs(), st.integers(-4, 4), st.integers(-4, 4))
def test_translation(img: Image, di: int, dj: int) -> None:
    moved = np.roll(img, (di, dj), axis=(0, 1))  # stays inside: 4 rings of margin
    s0, s1 = stats_of(img, moved).frame(0), stats_of(img, moved).frame(1)
    assert s1.n_taxels == s0.n_taxels
    same(s1.area_mm2, s0.area_mm2)
    same(s1.elongation, s0.elongation)
    same(s1.orientation_deg, s0.orientation_deg)
    same((s1.var_x_mm2, s1.var_y_mm2, s1.cov_xy_mm2), (s0.var_x_mm2, s0.var_y_mm2, s0.cov_xy_mm2))
    if not s0.is_empty:
        np.testing.assert_allclose(
            np.subtract(s1.centre_mm, s0.centre_mm), (dj * PITCH, di * PITCH), atol=1e-12
        )


@settings(max_examples=60, deadline=None)
@given(blobs())
def test_quarter_turn_and_transpose(img: Image) -> None:
    # np.rot90: b[i, j] = a[j, n - 1 - i], i.e. (x, y) -> (y, -x): -90 deg in the sensor frame
    s = stats_of(img, np.rot90(img), img.T)
    a, r, t = s.frame(0), s.frame(1), s.frame(2)
    if a.is_empty:
        return
    for other in (r, t):
        assert other.area_mm2 == a.area_mm2
        assert other.elongation == pytest.approx(a.elongation, rel=1e-12)
    np.testing.assert_allclose(r.centre_mm, (a.centre_mm[1], -a.centre_mm[0]), atol=1e-12)
    np.testing.assert_allclose(t.centre_mm, (a.centre_mm[1], a.centre_mm[0]), atol=1e-12)
    if a.elongation > 1.0 + 1e-9:  # the axis is defined
        assert angle_diff_mod_180(r.orientation_deg, a.orientation_deg - 90.0) == pytest.approx(
            0.0, abs=1e-9
        )
        assert angle_diff_mod_180(t.orientation_deg, 90.0 - a.orientation_deg) == pytest.approx(
            0.0, abs=1e-9
        )


@settings(max_examples=60, deadline=None)
@given(arrays(np.bool_, st.tuples(st.integers(1, 9), st.integers(1, 9))))
def test_properties_of_random_images(img: Image) -> None:
    rows, cols = img.shape
    s = image_stats(img[None], pitch_mm=PITCH).frame(0)
    n = int(img.sum())
    assert s.n_taxels == n
    assert s.area_mm2 == pytest.approx(n * PITCH**2, rel=1e-14)
    if n == 0:
        assert math.isnan(s.elongation)
        return
    assert s.elongation >= 1.0
    assert -90.0 < s.orientation_deg <= 90.0
    assert abs(s.centre_mm[0]) <= (cols - 1) / 2 * PITCH + 1e-12
    assert abs(s.centre_mm[1]) <= (rows - 1) / 2 * PITCH + 1e-12
    # the cell term bounds each variance from below
    assert s.var_x_mm2 >= CELL_SECOND_MOMENT * PITCH**2 * (1 - 1e-12)
    assert s.var_y_mm2 >= CELL_SECOND_MOMENT * PITCH**2 * (1 - 1e-12)
    # lambda_max <= (projected extent)^2 / 4 <= hypot(rows, cols)^2 / 4 and
    # lambda_min >= 1/12 (pitch units), so elongation <= sqrt(3) hypot(rows, cols)
    assert s.elongation <= math.sqrt(3.0) * math.hypot(rows, cols) + 1e-9


def test_pitch_scaling() -> None:
    rng = np.random.default_rng(2)
    imgs = rng.random((10, N, N)) < 0.3
    a = image_stats(imgs, pitch_mm=1.0)
    b = image_stats(imgs, pitch_mm=PITCH)
    same(a.elongation, b.elongation)
    same(a.orientation_deg, b.orientation_deg)
    np.testing.assert_allclose(b.area_mm2, a.area_mm2 * PITCH**2, rtol=1e-14)
    np.testing.assert_allclose(b.centre_mm, a.centre_mm * PITCH, rtol=1e-14)


# --------------------------------------------------------------------- scikit-image


@settings(max_examples=80, deadline=None)
@given(arrays(np.bool_, st.tuples(st.integers(1, 12), st.integers(1, 12))))
def test_agrees_with_skimage_regionprops(img: Image) -> None:
    measure = pytest.importorskip("skimage.measure")
    if not img.any():
        return
    rows, cols = img.shape
    props = measure.regionprops(img.astype(np.uint8))[0]
    s = image_stats(img[None], pitch_mm=PITCH).frame(0)
    assert s.n_taxels == props.area
    r0, c0 = props.centroid  # (row, col) in pixel indices
    np.testing.assert_allclose(
        s.centre_mm, ((c0 - (cols - 1) / 2) * PITCH, (r0 - (rows - 1) / 2) * PITCH), atol=1e-10
    )
    # skimage: point pixels, eigenvalues of the covariance in pixel^2;
    # taxelkit adds the cell's 1/12 to each before the ratio
    lam1, lam2 = props.inertia_tensor_eigvals
    expected = math.sqrt((lam1 + CELL_SECOND_MOMENT) / (lam2 + CELL_SECOND_MOMENT))
    assert s.elongation == pytest.approx(expected, rel=1e-9)
    if lam1 - lam2 > 1e-3:
        # skimage: angle from the row axis (+y) to the major axis; ours from +x
        assert angle_diff_mod_180(s.orientation_deg, 90.0 - math.degrees(props.orientation)) == (
            pytest.approx(0.0, abs=1e-7)
        )


def test_central_moments_agree_with_skimage() -> None:
    measure = pytest.importorskip("skimage.measure")
    rng = np.random.default_rng(11)
    img = rng.random((9, 13)) < 0.4
    sk = measure.moments_central(img.astype(float), order=3)  # sk[p, q]: rows^p cols^q
    mu = moments_central(img[None], pitch_mm=PITCH, order=3)[0]  # mu[p, q]: x^p y^q
    n = img.sum()
    scale = {(p, q): PITCH ** (2 + p + q) for p in range(4) for q in range(4)}
    for p, q in [(0, 0), (1, 1), (2, 1), (1, 2), (3, 0), (0, 3)]:
        assert mu[p, q] == pytest.approx(sk[q, p] * scale[p, q], rel=1e-9, abs=1e-9)
    # second moments gain the cell term n / 12 (pitch units)
    assert mu[2, 0] == pytest.approx((sk[0, 2] + n / 12) * scale[2, 0], rel=1e-12)
    assert mu[0, 2] == pytest.approx((sk[2, 0] + n / 12) * scale[0, 2], rel=1e-12)


# --------------------------------------------------------------------- batching, input


def test_batch_equals_per_frame_exactly() -> None:
    rng = np.random.default_rng(7)
    imgs = rng.random((300, N, N)) < rng.uniform(0.0, 0.5, size=(300, 1, 1))
    imgs[::17] = False
    batch = image_stats(imgs, pitch_mm=PITCH)
    for t in range(imgs.shape[0]):
        one = frame_stats(imgs[t], pitch_mm=PITCH)
        ref = batch.frame(t)
        assert one.n_taxels == ref.n_taxels
        same(
            [one.area_mm2, *one.centre_mm, one.orientation_deg, one.elongation],
            [ref.area_mm2, *ref.centre_mm, ref.orientation_deg, ref.elongation],
        )
        same(
            [one.var_x_mm2, one.var_y_mm2, one.cov_xy_mm2],
            [ref.var_x_mm2, ref.var_y_mm2, ref.cov_xy_mm2],
        )
    # and the same frames inside a different batch
    same(image_stats(imgs[100:140], pitch_mm=PITCH).elongation, batch.elongation[100:140])


def test_threshold_and_recordings() -> None:
    disp = np.zeros((2, 4, 4))
    disp[1, 1, 2] = 0.05
    disp[1, 2, 2] = 0.03  # equal to the threshold: not in contact
    thr = BONNEVILLE_16X16.contact_threshold_mm
    assert binary_images(disp, thr).sum() == 1
    bools = disp > thr
    assert binary_images(bools) is bools
    s = image_stats(disp, pitch_mm=2.0, threshold=thr)
    assert s.n_taxels.tolist() == [0, 1]
    rec = TactileFrames(disp, pitch_mm=2.0)
    same(image_stats(rec, threshold=thr).centre_mm, s.centre_mm)
    rec_bool = TactileFrames(bools, pitch_mm=2.0)
    same(image_stats(rec_bool).area_mm2, s.area_mm2)
    assert image_stats(rec_bool, pitch_mm=1.0).area_mm2[1] == 1.0


@pytest.mark.parametrize(
    ("call", "words"),
    [
        (lambda: image_stats(np.zeros((2, 3, 3), bool)), "pitch_mm"),
        (lambda: image_stats(np.zeros((2, 3, 3)), pitch_mm=1.0), "threshold"),
        (lambda: image_stats(np.zeros((3, 3), bool), pitch_mm=1.0), "(T, rows, cols)"),
        (lambda: image_stats(np.zeros((1, 3, 3), bool), pitch_mm=0.0), "pitch_mm"),
        (lambda: image_stats(np.full((1, 2, 2), np.nan), pitch_mm=1.0, threshold=0.1), "finite"),
        (lambda: image_stats(TactileFrames(np.zeros((1, 2, 2)))), "threshold"),
        (lambda: binary_images(np.zeros((2, 2)), float("nan")), "threshold"),
        (lambda: binary_images(np.zeros(3), 0.0), "rows, cols"),
        (lambda: binary_images(np.array([["a"]]), 0.0), "dtype"),
        (lambda: frame_stats(np.zeros((1, 2, 2), bool), pitch_mm=1.0), "frame"),
        (lambda: moments_of_area(np.zeros((1, 2, 2), bool), pitch_mm=1.0, order=-1), "order"),
        (lambda: stats_of(blank()).frame(1), "t must be"),
    ],
)
def test_bad_input_is_named(call: Any, words: str) -> None:
    with pytest.raises(InputError, match=None) as err:
        call()
    assert words in str(err.value)


def test_result_is_read_only() -> None:
    s = stats_of(blank())
    with pytest.raises(ValueError, match="read-only"):
        s.area_mm2[0] = 1.0
    with pytest.raises(AttributeError):
        s.pitch_mm = 2.0  # type: ignore[misc]


def test_docstring_examples() -> None:
    result = doctest.testmod(moments_module, optionflags=doctest.ELLIPSIS)
    assert result.attempted >= 3
    assert result.failed == 0


@pytest.mark.parametrize("shape", [(64, 64), (40, 128), (128, 128), (20, 255)])
def test_large_arrays_sum_by_rows_exactly(shape: tuple[int, int]) -> None:
    """Arrays from 64 x 64 up sum rows first; the sums are exact, as the one-product path's."""

    rng = np.random.default_rng(shape[1])
    images = rng.random((30, *shape)) < 0.3
    images[::4] = False
    u = np.arange(shape[1]) - (shape[1] - 1) / 2.0
    v = np.arange(shape[0]) - (shape[0] - 1) / 2.0
    uu, vv = np.meshgrid(u, v)
    f = images.reshape(30, -1).astype(np.float64)
    expected = np.stack(
        [f.sum(axis=1)] + [f @ w.ravel() for w in (uu, vv, uu * uu, vv * vv, uu * vv)]
    )
    np.testing.assert_array_equal(index_sums(images), expected)


@pytest.mark.parametrize("taxels", [1, 64, 256, 1024, 3600, 100_000])
def test_products_stay_within_one_blas_thread(taxels: int) -> None:
    """Every piece's product is within the bound (at least one row, at most 512)."""
    rows = product_rows(taxels, 6)
    assert 1 <= rows <= 512
    assert rows == 1 or rows * taxels * 6 <= ONE_THREAD_PRODUCT
    assert (rows + 1) * taxels * 6 > ONE_THREAD_PRODUCT or rows == 512
    assert product_rows(taxels, 6, most=3) == min(3, rows)


@pytest.mark.parametrize("bound", [1, 44, 5_000, 2**62])
def test_piece_size_changes_no_bit(bound: int, monkeypatch: pytest.MonkeyPatch) -> None:
    """The index sums and the network's outputs are those of one product, in any pieces."""
    rng = np.random.default_rng(bound % 97)
    images = rng.random((700, 16, 16)) < 0.4
    x = rng.normal(size=(3331, 2))  # 3331 = 10 x 333 + 1: a last piece of one row avoided
    want_sums, (want_h, want_p) = index_sums(images), _forward(HAND_SET, x)
    monkeypatch.setattr(index_sums_module, "ONE_THREAD_PRODUCT", bound)
    np.testing.assert_array_equal(index_sums(images), want_sums)
    h, p = _forward(HAND_SET, x)
    np.testing.assert_array_equal(h, want_h)
    np.testing.assert_array_equal(p, want_p)
    assert _forward(HAND_SET, x[:0])[1].shape == (0, 3)


def test_index_sums_docstring_examples() -> None:
    result = doctest.testmod(index_sums_module, optionflags=doctest.ELLIPSIS)
    assert result.attempted >= 1
    assert result.failed == 0
