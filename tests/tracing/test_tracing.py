"""Edge estimation and tracing on the simulated paper-000 sensor."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import taxelkit
from taxelkit.errors import InputError
from taxelkit.motion.probe import MotionNoise, SimulatedProbe, TactileProbe
from taxelkit.tracing.edge_estimate import EdgeDetectorConfig, estimate_edge
from taxelkit.tracing.line_fit import fit_edge_lines, line_intersection
from taxelkit.tracing.tracer import TracerConfig, find_edge, trace_edge
from taxelkit.world.relief import SHAPE_NAMES, EdgeRelief, relief_shape


def _edge_error_deg(theta_deg: float, estimator: str, n: int = 6) -> tuple[float, float]:
    rng = np.random.default_rng(int(theta_deg))
    t = np.deg2rad(theta_deg)
    along, normal = np.array([np.cos(t), np.sin(t)]), np.array([-np.sin(t), np.cos(t)])
    relief = EdgeRelief((0.0, 0.0), theta_deg, step_height_um=50.0)
    cfg = EdgeDetectorConfig(estimator=estimator)  # type: ignore[arg-type]
    errs, offs = [], []
    for k in range(n):
        probe = SimulatedProbe(relief, rng=k)
        off = rng.uniform(-1.5, 1.5)
        c = off * normal + rng.uniform(-3, 3) * along
        e = estimate_edge(probe.scan(c, 0), probe.scan(c, 1), probe.element_offsets_mm, cfg)
        assert e.found
        ang = np.rad2deg(np.arctan2(e.tangent[1], e.tangent[0]))
        errs.append(abs((ang - theta_deg + 180) % 360 - 180))
        offs.append(float(np.hypot(*(c + e.error_mm - (c - off * normal)))))
    return float(np.mean(errs)), float(np.mean(offs))


@pytest.mark.parametrize("theta_deg", [0, 15, 30, 45, 60, 75, 90])
def test_crossings_estimator_finds_50um_edges_within_one_degree(theta_deg: float) -> None:
    err_deg, err_mm = _edge_error_deg(theta_deg, "crossings")
    assert err_deg < 1.0
    assert err_mm < 0.3  # the error vector lands on the edge


@pytest.mark.parametrize("theta_deg", [15, 45, 75])
def test_eq8_estimator_points_along_the_edge(theta_deg: float) -> None:
    """The paper's Eq. 8 reading: right sense, but a bias of several degrees (measured)."""
    err_deg, _ = _edge_error_deg(theta_deg, "eq8")
    assert err_deg < 15.0


def test_no_edge_under_the_array_is_reported() -> None:
    probe = SimulatedProbe(EdgeRelief((0.0, 0.0), 0.0), rng=0)
    c = np.array([0.0, 40.0])  # far from the edge
    e = estimate_edge(probe.scan(c, 0), probe.scan(c, 1), probe.element_offsets_mm)
    assert not e.found and np.all(np.isnan(e.tangent))


def test_two_lines_at_a_corner_are_separated_and_oriented() -> None:
    s = np.linspace(1.0, 6, 8)  # within the inlier tolerance of the corner both fit
    a = np.stack([s, np.zeros_like(s)], 1)  # edge along +x, raised side +y
    b = np.stack([np.zeros_like(s), s], 1)  # edge along +y, raised side -x ... see votes
    pts = np.concatenate([a, b])
    axis = np.concatenate([np.ones(8, int), np.zeros(8, int)])  # a from y scans, b from x scans
    rising = np.concatenate([np.ones(8, bool), np.zeros(8, bool)])
    lines = fit_edge_lines(pts, rising, axis)
    assert len(lines) == 2
    normals = sorted(tuple(np.round(ln.normal, 6)) for ln in lines)
    assert normals == [(-1.0, 0.0), (0.0, 1.0)]
    q = line_intersection(*lines)
    assert q is not None and np.allclose(q, 0.0, atol=1e-9)


@pytest.fixture(scope="module")
def traces() -> dict[str, tuple[object, object]]:
    out = {}
    for name in SHAPE_NAMES:
        relief = relief_shape(name, diameter_mm=90.0, step_height_um=200.0)
        probe = SimulatedProbe(relief, rng=1)
        out[name] = (relief, trace_edge(probe, find_edge(probe, (0.0, 0.0))))
    return out


@pytest.mark.parametrize("name", SHAPE_NAMES)
def test_every_paper_shape_is_traced_closed_within_half_a_pitch(
    name: str, traces: dict[str, tuple[object, object]]
) -> None:
    relief, tr = traces[name]
    assert tr.closed, tr.stop_reason  # type: ignore[attr-defined]
    err = relief.distance_to_edge_mm(tr.points_mm)  # type: ignore[attr-defined]
    assert err.mean() <= 1.5  # fig8 acceptance: half the 3 mm pitch
    perimeter = np.sum(np.hypot(*np.diff(relief.outline_mm(), axis=0).T))  # type: ignore[attr-defined]
    assert tr.arc_length_mm[-1] == pytest.approx(perimeter, rel=0.1)  # type: ignore[attr-defined]


def test_tracing_is_deterministic_and_noise_tolerant() -> None:
    relief = relief_shape("hexagon", diameter_mm=90.0, rotation_deg=17.0, offset_mm=(5.0, -8.0))
    noise = MotionNoise(positioning_sigma_mm=0.1, vibration_mm=0.02)
    runs = []
    for _ in range(2):
        probe = SimulatedProbe(relief, noise=noise, rng=42)
        runs.append(trace_edge(probe, find_edge(probe, (5.0, -8.0))))
    np.testing.assert_array_equal(runs[0].points_mm, runs[1].points_mm)
    assert runs[0].closed
    assert relief.distance_to_edge_mm(runs[0].points_mm).mean() < 0.6


def test_straight_edge_trace_is_straight() -> None:
    relief = EdgeRelief((0.0, 0.0), 30.0, step_height_um=50.0)
    probe = SimulatedProbe(relief, rng=3)
    tr = trace_edge(probe, (0.0, 0.0), TracerConfig(max_sections=20))
    r = tr.straightness()
    assert r is not None and r >= 0.99
    axis_aligned = trace_edge(
        SimulatedProbe(EdgeRelief((0.0, 0.0), 0.0), rng=3), (0.0, 0.0), TracerConfig(max_sections=5)
    )
    assert axis_aligned.straightness() is None  # r undefined along an axis


def test_find_edge_fails_clearly_on_a_flat_plate() -> None:
    probe = SimulatedProbe(relief_shape("circle", diameter_mm=10.0), rng=0)
    with pytest.raises(InputError, match="no edge found"):
        find_edge(probe, (30.0, 30.0), max_distance_mm=30.0)


def test_simulated_probe_is_a_tactile_probe() -> None:
    assert isinstance(SimulatedProbe(EdgeRelief()), TactileProbe)


def _imports(path: Path) -> set[str]:
    tree = ast.parse(path.read_text())
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module:
            names.add(node.module)
        elif isinstance(node, ast.Import):
            names.update(a.name for a in node.names)
    return names


def test_recognisers_never_import_the_world() -> None:
    """Recognition sees frames, not geometry: tracing/memory/neuron/smart import no world module.

    The smart sensor imports no simulated motion either: its Level 2 training
    contacts are made on the simulator side (:mod:`taxelkit.motion.contact_samples`).
    (The tracer drives the probe of :mod:`taxelkit.motion.probe`: its own trajectory.)
    """
    root = Path(taxelkit.__file__).parent
    for package in ("tracing", "neuron", "memory", "smart"):
        banned = (
            ("taxelkit.world", "taxelkit.motion") if package == "smart" else ("taxelkit.world",)
        )
        for path in (root / package).glob("*.py"):
            bad = {m for m in _imports(path) if m.startswith(banned)}
            assert not bad, f"{path.name} imports {bad}"
