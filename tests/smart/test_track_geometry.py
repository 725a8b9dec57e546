"""Level 3 track geometry: drawn line ends, pivots, and motion summed across re-anchors."""

from __future__ import annotations

import numpy as np

from taxelkit.smart.line_extents import line_extents
from taxelkit.smart.moments import image_stats
from taxelkit.smart.pivot_limits import pivot_upper
from taxelkit.smart.pivots import pivot_fit, pivot_ratios, trailing_mean
from taxelkit.smart.track_geometry import carried_shift


def _tapered_line(length: int, rows: int = 16) -> np.ndarray:
    """A horizontal wedge: one taxel wide at the left end, three at the right."""
    img = np.zeros((rows, rows), dtype=bool)
    for i in range(length):
        half = (i * 3) // length  # 0, 1 or 2 extra rows as it widens
        img[8 - half // 2 : 9 + (half + 1) // 2, 2 + i] = True
    return img


def test_line_extents_are_the_drawn_ends_whatever_the_width_profile() -> None:
    pitch = 1.76
    img = _tapered_line(10)[None]
    s = image_stats(img, pitch_mm=pitch)
    ext = line_extents(img, s.centre_mm, s.orientation_deg, pitch)
    assert ext.shape == (1, 2)
    # ten columns wide: 10 pitches end to end
    assert np.isclose(ext[0, 1] - ext[0, 0], 10 * pitch, atol=0.05 * pitch)
    # the centroid lies towards the wide end, so the drawn middle is left of it
    assert 0.5 * (ext[0, 0] + ext[0, 1]) < 0.0


def test_pivot_of_lines_turning_about_their_end_is_one_half_length_away() -> None:
    angles = np.linspace(0.0, 40.0, 30)
    t = np.deg2rad(angles)
    half = 5.0
    centre = np.stack([half * np.cos(t), half * np.sin(t)], axis=-1)  # end fixed at 0
    ratio = pivot_ratios(angles, centre, np.full(angles.size, half))
    assert np.allclose(ratio[5:], 1.0, atol=1e-9)


def _turning_lines(noise_mm: float, seed: int = 0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Lines of half-length 5 mm turning 40 deg about their end, centres jittered across."""
    angles = np.linspace(0.0, 40.0, 60)
    t = np.deg2rad(angles)
    half = 5.0
    centre = np.stack([half * np.cos(t), half * np.sin(t)], axis=-1)
    normal = np.stack([-np.sin(t), np.cos(t)], axis=-1)
    jitter = np.random.default_rng(seed).normal(0.0, noise_mm, angles.size)
    return angles, centre + jitter[:, None] * normal, np.full(angles.size, half)


def test_pivot_error_is_zero_for_lines_through_one_point_and_grows_with_their_noise() -> None:
    ratio, error = pivot_fit(*_turning_lines(0.0))
    assert np.allclose(ratio[5:], 1.0, atol=1e-9)
    assert np.allclose(error[5:], 0.0, atol=1e-6)
    errors = [np.nanmedian(pivot_fit(*_turning_lines(s))[1][20:]) for s in (0.05, 0.2, 0.8)]
    assert 0.0 < errors[0] < errors[1] < errors[2]
    # the first result is pivot_ratios', float for float
    lines = _turning_lines(0.3)
    assert np.array_equal(pivot_fit(*lines)[0], pivot_ratios(*lines), equal_nan=True)


def test_pivot_error_does_not_shrink_with_the_frame_rate() -> None:
    # the same turn seen in 60 frames and in 600: the error is one line's, not a mean's
    angles, centre, half = _turning_lines(0.2)
    dense = np.linspace(0.0, 40.0, 600)
    t = np.deg2rad(dense)
    rng = np.random.default_rng(1)
    c = np.stack([5.0 * np.cos(t), 5.0 * np.sin(t)], axis=-1)
    c += rng.normal(0.0, 0.2, dense.size)[:, None] * np.stack([-np.sin(t), np.cos(t)], axis=-1)
    coarse = pivot_fit(angles, centre, half)[1][-1]
    fine = pivot_fit(dense, c, np.full(dense.size, 5.0))[1][-1]
    assert 0.5 < fine / coarse < 2.0


def test_pivot_error_is_nan_where_the_lines_are_parallel() -> None:
    angles = np.zeros(10)
    centre = np.stack([np.arange(10.0), np.zeros(10)], axis=-1)
    ratio, error = pivot_fit(angles, centre, np.full(10, 5.0))
    assert np.isnan(ratio).all() and np.isnan(error).all()


def test_pivot_upper_adds_the_allowance_only_when_asked() -> None:
    ratio, error = np.array([1.0, np.nan]), np.array([0.4, np.nan])
    assert np.array_equal(pivot_upper(ratio, error, 0.0), ratio, equal_nan=True)
    assert np.allclose(pivot_upper(ratio, error, 0.5)[0], 1.2)
    assert np.isnan(pivot_upper(ratio, error, 0.5)[1])


def test_carried_shift_keeps_what_earlier_stretches_moved() -> None:
    n = 20
    centre = np.stack([np.arange(n, dtype=float), np.zeros(n)], axis=-1)  # 1 mm a frame
    anchor = np.where(np.arange(n) < 10, 0, 10).astype(np.intp)
    ref = np.minimum(anchor + 2, n - 1)  # a 3-frame window after each anchor
    out = carried_shift(centre, anchor, ref)
    # first stretch: from frame 2 to 9 (7 mm), then from the new reference 12 on
    assert np.allclose(out[:2, 0], 0.0)
    assert np.isclose(out[9, 0], 7.0)
    assert np.allclose(out[10:13, 0], 7.0)  # the anchor-to-reference window is not motion
    assert np.isclose(out[-1, 0], 7.0 + (n - 1 - 12))


def test_carried_shift_without_re_anchors_is_the_shift_from_the_reference() -> None:
    rng = np.random.default_rng(0)
    centre = rng.normal(size=(15, 2))
    anchor = np.zeros(15, dtype=np.intp)
    ref = np.full(15, 2, dtype=np.intp)
    out = carried_shift(centre, anchor, ref)
    assert np.allclose(out[2:], centre[2:] - centre[2])
    assert np.allclose(out[:2], 0.0)


def test_trailing_mean_is_the_same_in_chunks_and_at_once() -> None:
    """The window's mean, float for float, however the rows are split; w = 1 is the rows."""
    rng = np.random.default_rng(3)
    values = rng.normal(size=(50, 2)) * 7.3
    for w in (1, 2, 6):
        whole = trailing_mean(values, w)
        expect = np.array([values[max(0, i - w + 1) : i + 1].mean(axis=0) for i in range(50)])
        assert np.allclose(whole, expect)
        for cuts in ((1, 2, 3), (5, 17, 40), (49,)):
            parts, before = [], values[:0]
            for piece in np.split(values, cuts):
                parts.append(trailing_mean(piece, w, before))
                before = np.concatenate([before, piece])
            assert np.array_equal(np.concatenate(parts), whole)
    assert np.array_equal(trailing_mean(values, 1), values)


def test_trailing_mean_of_runs_end_to_end_is_each_runs_own() -> None:
    """Runs laid end to end (``local``): each run's own means, bit for bit."""
    rng = np.random.default_rng(5)
    lengths = [1, 4, 9, 30, 2, 60]
    runs = [rng.normal(size=(n, 2)) * 5.0 for n in lengths]
    runs[3][7, 1] = -0.0
    values = np.concatenate(runs)
    local = np.concatenate([np.arange(n) for n in lengths])
    for w in (1, 3, 8, 36):
        got = trailing_mean(values, w, local=local)
        want = np.concatenate([trailing_mean(r, w) for r in runs])
        assert np.array_equal(got.view(np.int64), want.view(np.int64))
