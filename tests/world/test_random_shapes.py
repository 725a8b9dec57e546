"""The shape generator: seeded, distinct, star-shaped, sized like the paper's specimens."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from taxelkit.errors import InputError
from taxelkit.world import generate_shapes
from taxelkit.world.random_shapes import DIFFERENCE_SAMPLES, MIN_SHAPE_DIFFERENCE, radial_difference


@pytest.fixture(scope="module")
def shapes() -> tuple:  # type: ignore[type-arg]
    return generate_shapes(40, rng=7)


def test_same_seed_same_shapes_other_seed_other_shapes(shapes: tuple) -> None:  # type: ignore[type-arg]
    again = generate_shapes(40, rng=7)
    assert [s.name for s in again] == [s.name for s in shapes]
    for a, b in zip(again, shapes, strict=True):
        np.testing.assert_array_equal(a.unit_vertices, b.unit_vertices)
    other = generate_shapes(3, rng=8)
    assert not np.array_equal(other[0].unit_vertices, shapes[0].unit_vertices)


def test_every_pair_differs_by_at_least_the_minimum_even_rotated(shapes: tuple) -> None:  # type: ignore[type-arg]
    radials = np.stack([s.radial for s in shapes])
    for i, s in enumerate(shapes):
        d = radial_difference(np.delete(radials, i, axis=0), s.radial)
        assert d.min() >= MIN_SHAPE_DIFFERENCE
    # a rotated copy is the same shape: distance 0
    assert radial_difference(shapes[3].radial, np.roll(shapes[3].radial, 41)) == pytest.approx(
        0.0, abs=1e-9
    )


def test_half_polygons_half_curves_simple_and_circumscribed(shapes: tuple) -> None:  # type: ignore[type-arg]
    assert [s.kind for s in shapes[:4]] == ["polygon", "curve", "polygon", "curve"]
    for s in shapes:
        outline = s.outline_mm(diameter_mm=90.0, rotation_deg=30.0, offset_mm=(5.0, -2.0))
        poly = shapely.Polygon(outline)
        assert poly.is_valid and poly.contains(shapely.Point(5.0, -2.0))  # star-shaped about it
        r = np.hypot(outline[:, 0] - 5.0, outline[:, 1] + 2.0)
        assert r.max() == pytest.approx(45.0, rel=1e-3)
        assert r.min() >= 0.5 * 45.0 * 0.99  # no notch deeper than half the radius


def test_the_radial_function_follows_the_outline(shapes: tuple) -> None:  # type: ignore[type-arg]
    for s in shapes[:6]:
        theta = 2 * np.pi * np.arange(DIFFERENCE_SAMPLES) / DIFFERENCE_SAMPLES
        ray_ends = np.column_stack([np.cos(theta), np.sin(theta)]) * 2.0
        ring = shapely.LinearRing(s.unit_vertices)
        hits = [ring.intersection(shapely.LineString([(0, 0), tuple(e)])) for e in ray_ends]
        r = np.array([np.hypot(*np.asarray(shapely.get_coordinates(h)).T).max() for h in hits])
        np.testing.assert_allclose(s.radial, r, atol=2e-3)


def test_impossible_requests_are_refused() -> None:
    with pytest.raises(InputError, match="n_shapes"):
        generate_shapes(0)
    with pytest.raises(InputError, match="no shape at least"):
        generate_shapes(3, rng=0, min_difference=5.0)
