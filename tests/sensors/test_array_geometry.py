"""Taxel array geometry and the paper presets."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.sensors import BONNEVILLE_16X16, OPTICAL_3AXIS, ActiveRegion, TaxelArray, get_sensor


def test_centres_are_symmetric_and_spaced_by_pitch() -> None:
    arr = TaxelArray(rows=4, cols=5, pitch_mm=2.0, element_size_mm=1.0)
    c = arr.centres_mm()
    assert c.shape == (4, 5, 2)
    np.testing.assert_allclose(c[..., 0].mean(), 0.0, atol=1e-12)
    np.testing.assert_allclose(c[..., 1].mean(), 0.0, atol=1e-12)
    np.testing.assert_allclose(np.diff(c[0, :, 0]), 2.0)
    np.testing.assert_allclose(np.diff(c[:, 0, 1]), 2.0)  # rows run along +y
    x, _ = arr.centre_offsets_mm(margin=2)
    assert x.shape == (9,) and x[0] == pytest.approx(-8.0)


def test_optical_preset_matches_paper_000() -> None:
    a = OPTICAL_3AXIS.array
    assert (a.rows, a.cols, a.pitch_mm) == (10, 13, 3.0)
    region = a.active_region
    assert (region.rows, region.cols) == (6, 6)
    frame = np.arange(130).reshape(10, 13)
    assert frame[region.slices].shape == (6, 6)


def test_bonneville_preset_matches_paper_001() -> None:
    s = get_sensor("bonneville-16x16")
    assert s is BONNEVILLE_16X16
    assert s.array.shape == (16, 16)
    assert s.array.width_mm == pytest.approx(28.2)
    assert s.noise.resolution_mm == pytest.approx(0.006)
    assert s.max_rate_hz == 240.0
    u = np.array([[0.0, 0.05]])
    np.testing.assert_array_equal(s.contact_from_displacement(u), [[False, True]])


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"rows": 0, "cols": 4, "pitch_mm": 1.0, "element_size_mm": 1.0}, "rows"),
        ({"rows": 4, "cols": 4, "pitch_mm": -1.0, "element_size_mm": 1.0}, "pitch_mm"),
        ({"rows": 4, "cols": 4, "pitch_mm": 1.0, "element_size_mm": 2.0}, "element_size_mm"),
        (
            {
                "rows": 4,
                "cols": 4,
                "pitch_mm": 1.0,
                "element_size_mm": 1.0,
                "active": ActiveRegion(2, 2, 3, 3),
            },
            "does not fit",
        ),
    ],
)
def test_invalid_arrays_raise(kwargs: dict[str, object], match: str) -> None:
    with pytest.raises(InputError, match=match):
        TaxelArray(**kwargs)  # type: ignore[arg-type]


def test_unknown_sensor_lists_known_names() -> None:
    with pytest.raises(InputError, match="bonneville-16x16"):
        get_sensor("nope")
