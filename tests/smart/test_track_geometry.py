"""Level 3 track geometry: drawn line ends, pivots, and motion summed across re-anchors."""

from __future__ import annotations

import numpy as np

from taxelkit.smart.moments import image_stats
from taxelkit.smart.track_geometry import carried_shift, line_extents, pivot_ratios


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
