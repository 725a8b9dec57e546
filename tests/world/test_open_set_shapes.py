"""Out-of-set relief specimens: size, pose, centroid inside, twins of the stored shapes."""

from __future__ import annotations

import doctest

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.world import open_set_shapes
from taxelkit.world.open_set_shapes import OUT_OF_SET_SHAPES, open_set_outline_mm, open_set_relief


def test_docstring_examples() -> None:
    assert doctest.testmod(open_set_shapes).failed == 0


@pytest.mark.parametrize("name", OUT_OF_SET_SHAPES)
def test_outline_size_pose_and_raised_centre(name: str) -> None:
    base = open_set_outline_mm(name, diameter_mm=80.0)
    assert np.max(np.hypot(base[:, 0], base[:, 1])) == pytest.approx(40.0)
    moved = open_set_outline_mm(name, diameter_mm=80.0, rotation_deg=90.0, offset_mm=(5, -3))
    np.testing.assert_allclose(moved, base @ np.array([[0, 1], [-1, 0]]) + [5, -3], atol=1e-9)
    relief = open_set_relief(name, diameter_mm=80.0, offset_mm=(5, -3), step_height_um=150.0)
    assert float(relief.height_mm(5.0, -3.0)) == pytest.approx(0.15)  # centroid inside
    assert float(relief.height_mm(60.0, 60.0)) == 0.0


def test_at_least_ten_kinds_and_clear_errors() -> None:
    assert len(OUT_OF_SET_SHAPES) >= 10
    with pytest.raises(InputError, match="known: ellipse"):
        open_set_outline_mm("blob")
    with pytest.raises(InputError, match="diameter_mm"):
        open_set_outline_mm("cross", diameter_mm=-1.0)
