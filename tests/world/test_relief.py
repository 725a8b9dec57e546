"""Relief classes: height queries, boundary and edge conventions, distances, invariance."""

from __future__ import annotations

import dataclasses
import doctest
import math
import pickle

import numpy as np
import pytest
import shapely
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from taxelkit.errors import InputError
from taxelkit.sensors.presets import OPTICAL_3AXIS
from taxelkit.sensors.press import displacement_from_relief
from taxelkit.world import _planar, edge, heightmap, relief
from taxelkit.world.base import Relief
from taxelkit.world.relief import (
    SHAPE_NAMES,
    CircleRelief,
    EdgeRelief,
    PolygonRelief,
    ShapeRelief,
    relief_shape,
)

#: Query points closer than this to a contour are skipped in invariance tests,
#: where rounding of the transform could move them across it, mm.
BOUNDARY_GUARD_MM = 1e-6

coord = st.floats(-80.0, 80.0)


def _shape_relief(draw_name: str) -> PolygonRelief | CircleRelief | EdgeRelief:
    if draw_name == "edge":
        return EdgeRelief((3.0, -2.0), 30.0, step_height_um=120.0)
    return relief_shape(draw_name, diameter_mm=80.0, step_height_um=120.0)


# ----------------------------------------------------------------- heights and shapes


@pytest.mark.parametrize("name", [*SHAPE_NAMES, "edge"])
def test_heights_broadcast_to_any_shape(name: str) -> None:
    r = _shape_relief(name)
    rng = np.random.default_rng(0)
    x = rng.uniform(-50.0, 50.0, (7, 30, 40))
    y = rng.uniform(-50.0, 50.0, (7, 30, 40))
    h = r.height_mm(x, y)
    assert h.shape == (7, 30, 40)
    assert h.dtype == np.float64
    np.testing.assert_array_equal(h.ravel(), r.height_mm(x.ravel(), y.ravel()))
    grid = r.height_mm(np.linspace(-50, 50, 11)[None, :], np.linspace(-50, 50, 9)[:, None])
    assert grid.shape == (9, 11)
    assert np.asarray(r.height_mm(0.0, 0.0)).shape == ()


def test_mismatched_query_shapes_raise() -> None:
    with pytest.raises(InputError, match="broadcast"):
        relief_shape("square").height_mm(np.zeros(3), np.zeros(4))


def test_relief_is_closed_points_on_the_contour_are_raised() -> None:
    square = relief_from_square_10()
    assert float(square.height_mm(10.0, 5.0)) == square.step_height_mm  # edge midpoint
    assert float(square.height_mm(10.0, 10.0)) == square.step_height_mm  # vertex
    circle = CircleRelief((1.0, 2.0), 3.0)
    assert float(circle.height_mm(4.0, 2.0)) == circle.step_height_mm
    assert float(circle.height_mm(4.0 + 1e-9, 2.0)) == 0.0
    edge = EdgeRelief((1.0, 1.0), 90.0)
    assert float(edge.height_mm(1.0, -7.0)) == edge.step_height_mm


def relief_from_square_10() -> PolygonRelief:
    return PolygonRelief(np.array([(0.0, 0.0), (10.0, 0.0), (10.0, 10.0), (0.0, 10.0)]))


@pytest.mark.parametrize(
    ("angle_deg", "raised", "flat"),
    [
        (0.0, (0.0, 1.0), (0.0, -1.0)),  # direction +x: left is +y
        (90.0, (-1.0, 0.0), (1.0, 0.0)),  # direction +y: left is -x
        (180.0, (0.0, -1.0), (0.0, 1.0)),
        (270.0, (1.0, 0.0), (-1.0, 0.0)),
        (45.0, (-1.0, 1.0), (1.0, -1.0)),
    ],
)
def test_edge_raises_the_left_of_its_direction(
    angle_deg: float, raised: tuple[float, float], flat: tuple[float, float]
) -> None:
    edge = EdgeRelief((2.0, 3.0), angle_deg, step_height_um=50.0)
    assert float(edge.height_mm(2.0 + raised[0], 3.0 + raised[1])) == pytest.approx(0.05)
    assert float(edge.height_mm(2.0 + flat[0], 3.0 + flat[1])) == 0.0


def test_edge_along_y_is_exact_on_the_line() -> None:
    # cos(90 deg) must be exactly 0, or points on x = 0 with y < 0 would drop off the edge.
    edge = EdgeRelief((0.0, 0.0), 90.0)
    y = np.linspace(-1e3, 1e3, 101)
    np.testing.assert_array_equal(edge.height_mm(np.zeros_like(y), y), edge.step_height_mm)


def test_step_height_is_given_in_um_and_returned_in_mm() -> None:
    r = relief_shape("hexagon", step_height_um=50.0)
    assert r.step_height_mm == 0.05
    assert float(r.height_mm(0.0, 0.0)) == 0.05


# ----------------------------------------------------------------- outlines and distances


def test_outlines_are_closed_and_on_the_contour() -> None:
    star = relief_shape("star")
    out = star.outline_mm()
    assert out.shape == (11, 2)
    np.testing.assert_array_equal(out[0], out[-1])
    np.testing.assert_array_equal(out[:-1], star.vertices_mm)
    circle = CircleRelief((1.0, -1.0), 5.0)
    ring = circle.outline_mm(n_vertices=12)
    assert ring.shape == (13, 2)
    np.testing.assert_array_equal(ring[0], ring[-1])
    np.testing.assert_allclose(np.hypot(ring[:, 0] - 1.0, ring[:, 1] + 1.0), 5.0)
    with pytest.raises(InputError, match="n_vertices"):
        circle.outline_mm(n_vertices=2)
    seg = EdgeRelief((1.0, 2.0), 90.0).outline_mm(half_length_mm=10.0)
    np.testing.assert_allclose(seg, [[1.0, -8.0], [1.0, 12.0]])


@pytest.mark.parametrize("name", [n for n in SHAPE_NAMES if n != "circle"])
def test_distance_of_vertices_is_zero(name: str) -> None:
    poly = relief_shape(name, rotation_deg=12.0, offset_mm=(4.0, 5.0))
    assert isinstance(poly, PolygonRelief)
    np.testing.assert_array_equal(poly.distance_to_edge_mm(poly.vertices_mm), 0.0)


def test_distance_closed_forms() -> None:
    square = relief_from_square_10()
    d = square.distance_to_edge_mm(np.array([(5.0, 5.0), (13.0, 14.0), (5.0, -2.0)]))
    np.testing.assert_allclose(d, [5.0, 5.0, 2.0])
    signed = square.distance_to_edge_mm(np.array([(5.0, 5.0), (5.0, -2.0)]), signed=True)
    np.testing.assert_allclose(signed, [5.0, -2.0])
    circle = CircleRelief((0.0, 0.0), 10.0)
    np.testing.assert_allclose(circle.distance_to_edge_mm([(0.0, 0.0), (0.0, 13.0)]), [10.0, 3.0])
    np.testing.assert_allclose(circle.distance_to_edge_mm([(0.0, 13.0)], signed=True), [-3.0])
    edge = EdgeRelief((0.0, 0.0), 0.0)
    np.testing.assert_allclose(edge.distance_to_edge_mm([(7.0, 2.0), (-3.0, -4.0)]), [2.0, 4.0])
    np.testing.assert_allclose(edge.distance_to_edge_mm([(-3.0, -4.0)], signed=True), [-4.0])


def test_distance_accepts_any_leading_shape_and_rejects_bad_points() -> None:
    star = relief_shape("star")
    pts = np.random.default_rng(1).uniform(-60.0, 60.0, (3, 4, 2))
    assert star.distance_to_edge_mm(pts).shape == (3, 4)
    for bad, match in (([1.0, 2.0, 3.0], r"\(N, 2\)"), ([(0.0, np.nan)], "finite")):
        with pytest.raises(InputError, match=match):
            star.distance_to_edge_mm(bad)


@settings(max_examples=30, deadline=None)
@given(name=st.sampled_from(["square", "triangle", "star", "hexagon"]), seed=st.integers(0, 2**31))
def test_polygon_distance_matches_shapely(name: str, seed: int) -> None:
    poly = relief_shape(name, rotation_deg=seed % 360)
    assert isinstance(poly, PolygonRelief)
    pts = np.random.default_rng(seed).uniform(-70.0, 70.0, (200, 2))
    exterior = shapely.LinearRing(poly.vertices_mm)
    expected = shapely.distance(exterior, shapely.points(pts))
    np.testing.assert_allclose(poly.distance_to_edge_mm(pts), expected, atol=1e-9)
    inside = shapely.contains_xy(shapely.Polygon(poly.vertices_mm), pts[:, 0], pts[:, 1])
    signed = poly.distance_to_edge_mm(pts, signed=True)
    np.testing.assert_array_equal(signed > 0, inside)


def test_distance_is_blocked_without_changing_results(monkeypatch: pytest.MonkeyPatch) -> None:
    star = relief_shape("star")
    pts = np.random.default_rng(2).uniform(-60.0, 60.0, (1001, 2))
    whole = star.distance_to_edge_mm(pts)
    monkeypatch.setattr(_planar, "DISTANCE_BLOCK_PAIRS", 70)  # 7 points per block
    np.testing.assert_array_equal(star.distance_to_edge_mm(pts), whole)


# ----------------------------------------------------------------- invariance


@settings(max_examples=60, deadline=None)
@given(
    name=st.sampled_from([*SHAPE_NAMES, "edge"]),
    rotation_deg=st.floats(-720.0, 720.0),
    dx=coord,
    dy=coord,
    scale=st.floats(0.25, 4.0),
    seed=st.integers(0, 2**31),
)
def test_transformed_relief_at_transformed_points_gives_identical_heights(
    name: str, rotation_deg: float, dx: float, dy: float, scale: float, seed: int
) -> None:
    base = _shape_relief(name)
    moved = base.transformed(rotation_deg=rotation_deg, offset_mm=(dx, dy), scale=scale)
    pts = np.random.default_rng(seed).uniform(-60.0, 60.0, (300, 2))
    keep = base.distance_to_edge_mm(pts) > BOUNDARY_GUARD_MM
    assume(np.count_nonzero(keep) > 0)
    pts = pts[keep]
    t = math.radians(rotation_deg)
    rot = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
    q = scale * pts @ rot.T + [dx, dy]
    np.testing.assert_array_equal(moved.height_mm(q[:, 0], q[:, 1]), base.height_mm(*pts.T))
    np.testing.assert_allclose(
        moved.distance_to_edge_mm(q, signed=True),
        scale * base.distance_to_edge_mm(pts, signed=True),
        rtol=1e-9,
        atol=1e-9,
    )


@settings(max_examples=40, deadline=None)
@given(name=st.sampled_from(SHAPE_NAMES), rotation_deg=st.floats(0.0, 360.0), dx=coord, dy=coord)
def test_factory_pose_moves_heights_with_the_shape(
    name: str, rotation_deg: float, dx: float, dy: float
) -> None:
    canonical = relief_shape(name)
    placed = relief_shape(name, rotation_deg=rotation_deg, offset_mm=(dx, dy))
    pts = np.random.default_rng(7).uniform(-50.0, 50.0, (300, 2))
    pts = pts[canonical.distance_to_edge_mm(pts) > BOUNDARY_GUARD_MM]
    t = math.radians(rotation_deg)
    q = pts @ np.array([[math.cos(t), math.sin(t)], [-math.sin(t), math.cos(t)]]) + [dx, dy]
    np.testing.assert_array_equal(placed.height_mm(*q.T), canonical.height_mm(*pts.T))


# ----------------------------------------------------------------- dataclass behaviour


def test_reliefs_satisfy_the_protocols() -> None:
    for r in (relief_shape("star"), relief_shape("circle"), EdgeRelief()):
        assert isinstance(r, Relief)
        assert isinstance(r, ShapeRelief)


def test_reliefs_are_frozen_and_vertices_read_only() -> None:
    star = relief_shape("star")
    assert isinstance(star, PolygonRelief)
    with pytest.raises(dataclasses.FrozenInstanceError):
        star.step_height_um = 1.0  # type: ignore[misc]
    with pytest.raises(ValueError, match="read-only"):
        star.vertices_mm[0, 0] = 1.0
    with pytest.raises(dataclasses.FrozenInstanceError):
        CircleRelief((0.0, 0.0), 1.0).radius_mm = 2.0  # type: ignore[misc]
    assert CircleRelief((0, 0), 1.0) == CircleRelief((0.0, 0.0), 1.0)


@pytest.mark.parametrize("name", [*SHAPE_NAMES, "edge"])
def test_reliefs_survive_pickling_read_only(name: str) -> None:
    r = _shape_relief(name)
    copy = pickle.loads(pickle.dumps(r))
    assert type(copy) is type(r)
    pts = np.random.default_rng(4).uniform(-50.0, 50.0, (500, 2))
    np.testing.assert_array_equal(copy.height_mm(*pts.T), r.height_mm(*pts.T))
    if isinstance(copy, PolygonRelief):
        assert not copy.vertices_mm.flags.writeable


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda: CircleRelief((0.0, 0.0), 0.0), "radius_mm"),
        (lambda: CircleRelief((0.0, math.nan), 1.0), "centre_mm"),
        (lambda: CircleRelief((0.0, 0.0), 1.0, step_height_um=-1.0), "step_height_um"),
        (lambda: EdgeRelief((0.0, 0.0), math.inf), "angle_deg"),
        (lambda: EdgeRelief((0.0, 0.0, 0.0), 0.0), "point_mm"),  # type: ignore[arg-type]
        (lambda: EdgeRelief(step_height_um=0.0), "step_height_um"),
        (lambda: relief_from_square_10().transformed(scale=0.0), "scale"),
        (lambda: EdgeRelief().outline_mm(half_length_mm=-1.0), "half_length_mm"),
    ],
)
def test_constructors_reject_bad_values(build: object, match: str) -> None:
    with pytest.raises(InputError, match=match):
        build()  # type: ignore[operator]


@pytest.mark.parametrize("module", [edge, relief, heightmap])
def test_docstring_examples_run(module: object) -> None:
    result = doctest.testmod(module, raise_on_error=False)  # type: ignore[arg-type]
    assert result.attempted > 0
    assert result.failed == 0


# ----------------------------------------------------------------- through the sensor


def test_edge_under_half_the_optical_array_separates_the_halves_by_the_step() -> None:
    step_mm, indent_mm = 0.05, 0.1
    edge = EdgeRelief((0.0, 0.0), 90.0, step_height_um=step_mm * 1000.0)  # raises x <= 0
    frames = displacement_from_relief(
        OPTICAL_3AXIS, edge, (0.0, 0.0), indent_mm=indent_mm, add_noise=False
    )
    frame = frames[0]
    array = OPTICAL_3AXIS.array
    assert frame.shape == (array.rows, array.cols)
    x_mm = (np.arange(array.cols) - (array.cols - 1) / 2.0) * array.pitch_mm
    far = 2.0 * array.pitch_mm  # well beyond the skin spread of 1 mm
    raised, flat = frame[:, x_mm <= -far], frame[:, x_mm >= far]
    assert raised.size > 0 and flat.size > 0
    np.testing.assert_allclose(raised, indent_mm + step_mm, atol=1e-6)
    np.testing.assert_allclose(flat, indent_mm, atol=1e-6)
    assert raised.mean() - flat.mean() == pytest.approx(step_mm, abs=1e-6)
