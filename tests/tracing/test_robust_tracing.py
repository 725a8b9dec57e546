"""Robust tracing: noise-adaptive edge test, plausible closure, partial traces, presets."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.motion.probe import ScanConfig, SimulatedProbe
from taxelkit.tracing.edge_estimate import EdgeDetectorConfig
from taxelkit.tracing.line_fit import EdgeLine, vote_agreement
from taxelkit.tracing.loop_closure import (
    enclosed_area_mm2,
    footprint_area_mm2,
    is_plausible_loop,
    isoperimetric_quotient,
)
from taxelkit.tracing.presets import FAITHFUL_TRACER, ROBUST_TRACER, TRACER_PRESETS
from taxelkit.tracing.tracer import TracerConfig, find_edge, trace_edge
from taxelkit.world.degraded import RoughRelief, TiltedRelief
from taxelkit.world.reentrant import reentrant_relief
from taxelkit.world.relief import relief_shape


def _trace(relief: object, cfg: TracerConfig, seed: int = 0, **scan: bool) -> object:
    probe = SimulatedProbe(relief, scan=ScanConfig(**scan), rng=seed)  # type: ignore[arg-type]
    return trace_edge(probe, find_edge(probe, (0.0, 0.0), config=cfg), cfg)


def test_the_defaults_are_the_robust_tracer_and_the_faithful_one_is_named() -> None:
    assert TracerConfig() == ROBUST_TRACER and EdgeDetectorConfig().dead_zone == "adaptive"
    assert FAITHFUL_TRACER.detector.dead_zone == "fixed" and not FAITHFUL_TRACER.confirm_edge
    assert set(TRACER_PRESETS) == {"faithful", "robust"}


def test_on_a_clean_plate_robust_and_faithful_traces_are_identical() -> None:
    star = relief_shape("star", scale=0.6, rotation_deg=11.0)
    a, b = _trace(star, FAITHFUL_TRACER, seed=4), _trace(star, ROBUST_TRACER, seed=4)
    assert a.closed and np.array_equal(a.points_mm, b.points_mm)  # type: ignore[attr-defined]


def test_a_rough_plate_stops_the_faithful_tracer_not_the_robust_one() -> None:
    """20 um rms roughness on a 200 um step (issue 9, point 6)."""
    clean = relief_shape("triangle", scale=0.7)
    rough = RoughRelief(clean, 20.0, rng=3)
    tr = _trace(rough, ROBUST_TRACER, seed=1)
    assert tr.closed  # type: ignore[attr-defined]
    assert clean.distance_to_edge_mm(tr.points_mm).mean() < 0.5  # type: ignore[attr-defined]
    short = dataclasses.replace(FAITHFUL_TRACER, max_sections=60)  # the closed loop needs ~55
    faithful = _trace(rough, short, seed=1)
    assert not faithful.closed  # type: ignore[attr-defined]


def test_a_tilted_plate_closes_with_touch_down() -> None:
    clean = relief_shape("square", scale=0.7)
    tr = _trace(TiltedRelief(clean, 2.0, azimuth_deg=40.0), ROBUST_TRACER, touch_down=True)
    assert tr.closed  # type: ignore[attr-defined]
    assert clean.distance_to_edge_mm(tr.points_mm).mean() < 0.5  # type: ignore[attr-defined]


def test_touch_down_keeps_a_falling_plate_in_contact() -> None:
    plate = TiltedRelief(relief_shape("circle", diameter_mm=20.0), 2.0)  # falls towards -x
    at = (-40.0, 0.0)  # 1.4 mm below the pivot: out of reach of a 0.1 mm indentation
    held = SimulatedProbe(plate, rng=0).scan(at, 0).frames_mm
    down = SimulatedProbe(plate, scan=ScanConfig(touch_down=True), rng=0).scan(at, 0).frames_mm
    assert np.abs(held).max() < 0.005
    middle = down[down.shape[0] // 2]  # at the touch-down point: >= 0.1 mm everywhere
    assert middle.min() > 0.09 and np.median(down) > 0.1


def test_a_small_loop_is_not_a_closed_contour() -> None:
    offsets = np.stack(np.meshgrid(np.arange(6) * 3.0 - 7.5, np.arange(6) * 3.0 - 7.5), -1)
    assert footprint_area_mm2(offsets) == pytest.approx(324.0)
    square = np.array([(0, 0), (30, 0), (30, 30), (0, 30)], float)
    assert enclosed_area_mm2(square) == 900.0 and enclosed_area_mm2(square[::-1]) == -900.0
    circle = np.c_[np.cos(np.linspace(0, 2 * np.pi, 400)), np.sin(np.linspace(0, 2 * np.pi, 400))]
    assert isoperimetric_quotient(circle) == pytest.approx(1.0, abs=1e-3)
    assert is_plausible_loop(square, min_area_mm2=324.0)
    assert not is_plausible_loop(square / 3, min_area_mm2=324.0)  # 10 mm: under the array
    wander = np.array([(0, 0), (100, 0), (100, 1), (0, 1), (0, 30)], float)
    assert not is_plausible_loop(wander, min_area_mm2=324.0)


def test_partial_traces_know_only_the_length_travelled_so_far() -> None:
    tr = _trace(relief_shape("hexagon", scale=0.7), ROBUST_TRACER)
    k = tr.n_sections // 3  # type: ignore[attr-defined]
    head = tr.head(k)  # type: ignore[attr-defined]
    assert head.n_sections == k and not head.closed and head.stop_reason == "partial"
    assert np.array_equal(head.arc_length_mm, tr.arc_length_mm[: k + 1])  # type: ignore[attr-defined]
    assert head.travelled_mm < tr.travelled_mm and tr.head(tr.n_sections) is tr  # type: ignore[attr-defined]
    with pytest.raises(InputError, match="n_sections"):
        tr.head(-1)  # type: ignore[attr-defined]


def test_vote_agreement_tells_a_step_from_a_bump() -> None:
    pts = np.c_[np.zeros(6), np.arange(6.0)]  # crossings on the line x = 0, found by x scans
    line = EdgeLine(np.zeros(2), np.array([1.0, 0.0]), np.array([0.0, -1.0]), np.ones(6, bool))
    axis = np.zeros(6, int)
    assert vote_agreement(line, pts, np.ones(6, bool), axis) == 1.0  # climbed towards +x
    bump = np.array([True, False] * 3)  # climbed and left at the same place
    assert vote_agreement(line, pts, bump, axis) == 0.5


def test_reentrant_shapes_have_their_closed_form_size() -> None:
    ell = reentrant_relief("l-shape", diameter_mm=90.0)
    side = 90.0 / np.sqrt(2.0)
    assert enclosed_area_mm2(ell.vertices_mm) == pytest.approx(side**2 * (1 - 0.6**2))
    star = reentrant_relief("deep-star", diameter_mm=90.0)
    assert np.hypot(*star.vertices_mm.T).round(6).tolist() == [45.0, 11.25] * 5
    with pytest.raises(InputError, match="known: l-shape, deep-star"):
        reentrant_relief("pentagon")


def test_rough_plates_are_seeded() -> None:
    base = relief_shape("circle")
    x = np.linspace(-30, 30, 301)
    a = RoughRelief(base, 10.0, rng=5).height_mm(x, 1.0)
    assert np.array_equal(a, RoughRelief(base, 10.0, rng=5).height_mm(x, 1.0))
    assert not np.array_equal(a, RoughRelief(base, 10.0, rng=6).height_mm(x, 1.0))
