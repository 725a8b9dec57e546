"""Named specimens of paper 000: geometry against closed forms, orientation, validation."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from taxelkit.errors import InputError
from taxelkit.world.relief import (
    DEFAULT_DIAMETER_MM,
    SHAPE_NAMES,
    STAR_INNER_RADIUS_RATIO,
    CircleRelief,
    PolygonRelief,
    relief_from_vertices,
    relief_shape,
)

POLYGON_NAMES = tuple(n for n in SHAPE_NAMES if n != "circle")
R = DEFAULT_DIAMETER_MM / 2.0


def _polygon(name: str, **options: Any) -> PolygonRelief:
    relief = relief_shape(name, **options)
    assert isinstance(relief, PolygonRelief)
    return relief


def _outer_vertices(relief: PolygonRelief, name: str) -> np.ndarray:
    v = relief.vertices_mm
    return v[::2] if name == "star" else v


def test_registry_lists_the_five_shapes_and_each_builds() -> None:
    assert SHAPE_NAMES == ("circle", "square", "triangle", "star", "hexagon")
    for name in SHAPE_NAMES:
        relief = relief_shape(name)
        expected = CircleRelief if name == "circle" else PolygonRelief
        assert isinstance(relief, expected)


def test_unknown_name_lists_known_names() -> None:
    with pytest.raises(InputError, match="unknown shape 'pentagon'") as info:
        relief_shape("pentagon")
    for name in SHAPE_NAMES:
        assert name in str(info.value)


@pytest.mark.parametrize("name", POLYGON_NAMES)
def test_outer_vertices_lie_on_the_circumscribed_circle(name: str) -> None:
    relief = _polygon(name, diameter_mm=70.0, offset_mm=(3.0, -4.0), rotation_deg=17.0)
    outer = _outer_vertices(relief, name)
    np.testing.assert_allclose(np.hypot(outer[:, 0] - 3.0, outer[:, 1] + 4.0), 35.0, rtol=1e-12)


@pytest.mark.parametrize(
    ("name", "n_vertices"), [("square", 4), ("triangle", 3), ("star", 10), ("hexagon", 6)]
)
def test_vertex_counts_and_counter_clockwise_order(name: str, n_vertices: int) -> None:
    relief = _polygon(name)
    assert relief.vertices_mm.shape == (n_vertices, 2)
    assert relief.area_mm2 > 0.0
    angles = np.unwrap(np.arctan2(relief.vertices_mm[:, 1], relief.vertices_mm[:, 0]))
    assert np.all(np.diff(angles) > 0.0)


def test_star_ratio_is_the_regular_pentagram_ratio() -> None:
    ratio = STAR_INNER_RADIUS_RATIO
    assert abs(ratio - 0.382) < 5e-4
    golden = (1.0 + math.sqrt(5.0)) / 2.0
    assert ratio == pytest.approx(1.0 / golden**2, rel=1e-12)
    assert ratio == pytest.approx(math.cos(math.radians(72.0)) / math.cos(math.radians(36.0)))


def test_star_inner_vertices_at_ratio_and_on_the_pentagram_chords() -> None:
    star = relief_shape("star")
    v = star.vertices_mm
    np.testing.assert_allclose(np.hypot(v[1::2, 0], v[1::2, 1]), STAR_INNER_RADIUS_RATIO * R)
    outer = v[::2]
    for k in range(5):
        # Inner vertex between outer k and k+1 lies on the chord from outer k to outer k+2
        # (and on the chord from outer k+1 to outer k-1): the regular pentagram's crossings.
        inner = v[2 * k + 1]
        for a, b in ((outer[k], outer[(k + 2) % 5]), (outer[(k + 1) % 5], outer[(k - 1) % 5])):
            d, w = b - a, inner - a
            assert abs(d[0] * w[1] - d[1] * w[0]) / np.linalg.norm(d) < 1e-9


def test_canonical_orientations() -> None:
    for name in ("triangle", "star", "hexagon"):
        np.testing.assert_allclose(relief_shape(name).vertices_mm[0], [0.0, R], atol=1e-12)
    square = relief_shape("square").vertices_mm
    half = R / math.sqrt(2.0)
    np.testing.assert_allclose(np.abs(square), half, rtol=1e-12)  # axis-aligned sides
    triangle = relief_shape("triangle").vertices_mm
    assert triangle[1, 1] == pytest.approx(triangle[2, 1])  # base parallel to x
    assert triangle[1, 1] == pytest.approx(-R / 2.0)


@pytest.mark.parametrize(
    ("name", "area_over_r2"),
    [
        ("circle", math.pi),
        ("square", 2.0),
        ("triangle", 3.0 * math.sqrt(3.0) / 4.0),
        ("hexagon", 3.0 * math.sqrt(3.0) / 2.0),
        ("star", 5.0 * STAR_INNER_RADIUS_RATIO * math.sin(math.radians(36.0))),
    ],
)
def test_areas_against_closed_forms(name: str, area_over_r2: float) -> None:
    relief = relief_shape(name)
    assert relief.area_mm2 == pytest.approx(area_over_r2 * R**2, rel=1e-12)
    # Independent check through the height query: count raised cells of a fine grid.
    cell = 0.1
    axis = np.arange(-R - 1.0, R + 1.0, cell) + cell / 2.0
    heights = relief.height_mm(axis[None, :], axis[:, None])
    assert set(np.unique(heights)) <= {0.0, relief.step_height_mm}
    raised_area = np.count_nonzero(heights > 0.0) * cell**2
    assert raised_area == pytest.approx(area_over_r2 * R**2, rel=2e-3)


@pytest.mark.parametrize(
    ("name", "inside", "outside"),
    [
        ("circle", [(0.0, 0.0), (0.0, R - 0.01), (-R + 0.01, 0.0)], [(0.0, R + 0.01), (R, R)]),
        (
            "square",
            [(0.0, 0.0), (R / math.sqrt(2) - 0.01, R / math.sqrt(2) - 0.01)],
            [(0.0, R / math.sqrt(2) + 0.01), (R, 0.0)],
        ),
        ("triangle", [(0.0, 0.0), (0.0, -R / 2 + 0.01), (0.0, R - 0.01)], [(0.0, -R / 2 - 0.01)]),
        (
            "hexagon",
            [(R * math.cos(math.pi / 6) - 0.01, 0.0), (0.0, R - 0.01)],
            [(R * math.cos(math.pi / 6) + 0.01, 0.0), (0.0, R + 0.01)],
        ),
        (
            "star",
            [(0.0, 0.0), (0.0, R - 0.01), (0.0, -0.99 * STAR_INNER_RADIUS_RATIO * R)],
            [(0.0, -1.01 * STAR_INNER_RADIUS_RATIO * R), (0.0, R + 0.01)],
        ),
    ],
)
def test_points_inside_read_the_step_and_outside_zero(
    name: str, inside: list[tuple[float, float]], outside: list[tuple[float, float]]
) -> None:
    relief = relief_shape(name, step_height_um=50.0)
    pin, pout = np.array(inside), np.array(outside)
    np.testing.assert_array_equal(relief.height_mm(pin[:, 0], pin[:, 1]), 0.05)
    np.testing.assert_array_equal(relief.height_mm(pout[:, 0], pout[:, 1]), 0.0)


@settings(max_examples=40, deadline=None)
@given(
    name=st.sampled_from(POLYGON_NAMES),
    rotation_deg=st.floats(-360.0, 360.0),
    dx=st.floats(-100.0, 100.0),
    dy=st.floats(-100.0, 100.0),
    scale=st.floats(0.2, 3.0),
)
def test_factory_pose_equals_transforming_the_canonical_shape(
    name: str, rotation_deg: float, dx: float, dy: float, scale: float
) -> None:
    placed = _polygon(
        name, rotation_deg=rotation_deg, offset_mm=(dx, dy), scale=scale, diameter_mm=60.0
    )
    canonical = _polygon(name, diameter_mm=60.0)
    t = math.radians(rotation_deg)
    rot = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
    expected = scale * canonical.vertices_mm @ rot.T + [dx, dy]
    np.testing.assert_allclose(placed.vertices_mm, expected, atol=1e-9)
    moved = canonical.transformed(rotation_deg=rotation_deg, offset_mm=(dx, dy), scale=scale)
    np.testing.assert_allclose(moved.vertices_mm, placed.vertices_mm, atol=1e-9)


def test_circle_factory_places_and_scales() -> None:
    c = relief_shape("circle", diameter_mm=20.0, scale=1.5, offset_mm=(5.0, 6.0), step_height_um=80)
    assert isinstance(c, CircleRelief)
    assert c.centre_mm == (5.0, 6.0)
    assert c.radius_mm == 15.0
    assert c.step_height_mm == pytest.approx(0.08)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"diameter_mm": 0.0},
        {"diameter_mm": -5.0},
        {"scale": 0.0},
        {"scale": float("nan")},
        {"rotation_deg": float("inf")},
        {"offset_mm": (1.0,)},
        {"offset_mm": (1.0, float("nan"))},
        {"step_height_um": 0.0},
        {"step_height_um": -10.0},
    ],
)
def test_factory_rejects_bad_parameters(kwargs: dict[str, Any]) -> None:
    with pytest.raises(InputError, match=next(iter(kwargs))):
        relief_shape("square", **kwargs)


def test_relief_from_vertices_accepts_lists_closed_lists_and_clockwise_order() -> None:
    ccw = [(0.0, 0.0), (10.0, 0.0), (10.0, 5.0), (0.0, 5.0)]
    cw = [(0.0, 0.0), (0.0, 5.0), (10.0, 5.0), (10.0, 0.0)]
    a = relief_from_vertices(ccw, step_height_um=100.0)
    b = relief_from_vertices([*cw, cw[0]], step_height_um=100.0)
    np.testing.assert_array_equal(a.vertices_mm, b.vertices_mm)  # reversed, first kept first
    assert b.area_mm2 == pytest.approx(50.0)
    assert not b.vertices_mm.flags.writeable


def test_non_convex_polygon_notch_is_not_raised() -> None:
    l_shape = relief_from_vertices([(0, 0), (10, 0), (10, 4), (4, 4), (4, 10), (0, 10)])
    assert float(l_shape.height_mm(2.0, 8.0)) > 0.0
    assert float(l_shape.height_mm(8.0, 8.0)) == 0.0  # inside the convex hull, outside the L
    assert l_shape.area_mm2 == pytest.approx(64.0)


@pytest.mark.parametrize(
    ("vertices", "match"),
    [
        ([(0, 0), (1, 0)], "at least 3"),
        ([(0, 0), (1, 0), (0, 0)], "at least 3"),
        ([(0, 0), (1, 0), (1, float("nan"))], "finite"),
        ([(0, 0, 0), (1, 0, 0), (1, 1, 0)], r"shape \(V, 2\)"),
        ([0.0, 1.0, 2.0], r"shape \(V, 2\)"),
        ([(0, 0), (2, 2), (2, 0), (0, 2)], "simple polygon"),  # bow-tie
        ([(0, 0), (1, 1), (2, 2)], "simple polygon"),  # collinear, zero area
        ([(0, 0), (1, 0), (1, 0), (0, 1)], "repeat"),
        ("abc", "numeric"),
    ],
)
def test_relief_from_vertices_rejects_invalid_polygons(vertices: object, match: str) -> None:
    with pytest.raises(InputError, match=match):
        relief_from_vertices(vertices)  # type: ignore[arg-type]
