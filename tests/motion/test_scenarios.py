"""Randomised scripts: determinism, kinematics, ground truth, staying on the array, images.

The kinematic checks use only the poses a scenario records, against the
solid's own geometry: the resting height the script claims must be the one at
which the body's lowest point touches the plane (so the body never goes
through the sensor); material contact points may move horizontally by at most
``D (1 - cos dtheta)`` per step (``D`` the body's diameter, ``dtheta`` the
rotation between the frames), which holds for tipping about a fixed edge or
rim point and, with room to spare, for rolling; sliding breaks it.
"""

from __future__ import annotations

import functools
import itertools
import math

import numpy as np
import pytest
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.motion.contact_truth import contact_points_body_mm, contact_state
from taxelkit.motion.rolling import DEFAULT_DEPTH_MM, E_Z, Scenario, frames_from_scenario
from taxelkit.motion.scenarios import (
    EDGE_MARGIN_MM,
    SCENARIO_NAMES,
    SLIDING_OBJECTS,
    cylinder_fig3_scenario,
    make_scenario,
)
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.world.solids import SOLID_NAMES, make_solid, solid_size_names

Arr = NDArray[np.float64]
SEEDS = (0, 1, 2, 3)
CASES = [(name, seed) for name in SCENARIO_NAMES for seed in SEEDS]
HOLD_FRAMES_MIN = 8  # 0.4 s at 20 Hz

#: Phase label -> geometric contact it must have (round "side"/"rolling" per object).
EXPECTED_CONTACT = {
    "lifted": {"none"},
    "face": {"area"},
    "edge": {"line"},
    "vertex": {"point"},
    "rim": {"point"},
    "apex": {"point"},
    "tipping": {"point", "line"},
    "sliding": {"area"},
    "spinning": {"area"},
}


@functools.cache
def scenario(name: str, seed: int) -> Scenario:
    return make_scenario(name, rng=seed)


@functools.cache
def contact_images(name: str, seed: int) -> NDArray[np.bool_]:
    rec = frames_from_scenario(BONNEVILLE_16X16, scenario(name, seed), add_noise=False)
    return BONNEVILLE_16X16.contact_from_displacement(rec.frames)


def image_stats(img: NDArray[np.bool_]) -> tuple[int, float, float]:
    """Area (taxels), elongation (sqrt of the principal second-moment ratio), orientation (rad)."""
    ys, xs = np.nonzero(img)
    if xs.size == 0:
        return 0, 0.0, 0.0
    x, y = xs - xs.mean(), ys - ys.mean()
    cov = np.array([[np.mean(x * x), np.mean(x * y)], [np.mean(x * y), np.mean(y * y)]])
    ev, vec = np.linalg.eigh(cov + np.eye(2) / 12.0)  # + one taxel's own spread
    return int(xs.size), float(np.sqrt(ev[1] / ev[0])), float(np.arctan2(vec[1, 1], vec[0, 1]))


def rotation_steps(rots: Arr) -> Arr:
    """Angle turned between consecutive rotations, (T - 1,) rad (atan2: exact near 0)."""
    rel = rots[1:] @ np.swapaxes(rots[:-1], 1, 2)
    skew = rel - np.swapaxes(rel, 1, 2)
    sin = 0.5 * np.linalg.norm(skew[:, [2, 0, 1], [1, 2, 0]], axis=1)
    return np.arctan2(sin, (np.trace(rel, axis1=1, axis2=2) - 1.0) / 2.0)


def diameter_mm(sc: Scenario) -> float:
    pts = contact_points_body_mm(sc.solid, sc.rotations[:1])[0]
    if pts.shape[0] == 1:  # a sphere
        return 2.0 * float(np.linalg.norm(pts[0]))
    return float(np.max(np.linalg.norm(pts[:, None] - pts[None], axis=-1)))


def world_contacts(sc: Scenario, t: int) -> Arr:
    """Points touching the plane in frame ``t``, sensor frame, indentation 0."""
    state = contact_state(sc.solid, sc.rotations[t : t + 1])
    centre = np.array([*sc.positions_mm[t], sc.rest_height_mm[t]])
    out: Arr = state.relative_mm[0][state.touching[0]] + centre
    return out


def test_registry_and_validation() -> None:
    assert (*SOLID_NAMES, "sliding") == SCENARIO_NAMES
    with pytest.raises(InputError, match="known: cube"):
        make_scenario("donut", rng=0)
    with pytest.raises(InputError, match="size_jitter"):
        make_scenario("cube", rng=0, size_jitter=0.7)
    with pytest.raises(InputError, match="depth_mm"):
        make_scenario("cube", rng=0, depth_mm=-0.1)
    with pytest.raises(InputError, match="rate_hz"):
        make_scenario("cube", rng=0, rate_hz=0.0)


@pytest.mark.parametrize("name", SCENARIO_NAMES)
def test_same_seed_same_scenario(name: str) -> None:
    a, b = make_scenario(name, rng=11), make_scenario(name, rng=11)
    assert a.equals(b)
    assert not a.equals(make_scenario(name, rng=12))
    gen1, gen2 = np.random.default_rng(5), np.random.default_rng(5)
    assert make_scenario(name, rng=gen1).equals(make_scenario(name, rng=gen2))
    assert not make_scenario(name, rng=gen1).equals(
        make_scenario(name, rng=np.random.default_rng(5))
    )


@pytest.mark.parametrize(("name", "seed"), CASES)
def test_kinematics_rest_on_the_plane_and_keep_the_depth(name: str, seed: int) -> None:
    sc = scenario(name, seed)
    assert sc.name == name and sc.slides == (name == "sliding")
    assert sc.object_name == (name if name != "sliding" else sc.solid.name)
    # the claimed resting height is where the lowest point touches: never through the plane
    np.testing.assert_allclose(sc.rest_height_mm, -sc.solid.lowest_z_mm(sc.rotations), atol=1e-9)
    still = np.array([p not in ("lifted", "placing", "lifting") for p in sc.phase])
    depth = sc.indent_mm[still][0]
    assert DEFAULT_DEPTH_MM * 0.7 <= depth <= DEFAULT_DEPTH_MM * 1.3
    np.testing.assert_array_equal(sc.indent_mm[still], depth)  # constant working depth
    ramp = np.array([p in ("placing", "lifting") for p in sc.phase])
    assert np.all((sc.indent_mm[ramp] > 0) & (sc.indent_mm[ramp] < depth))
    assert np.all(sc.indent_mm[np.array(sc.phase) == "lifted"] < 0)
    assert sc.phase[0] == sc.phase[-1] == "lifted"
    assert [r[0] for r in sc.phase_runs()][:2] == ["lifted", "placing"]
    np.testing.assert_allclose(np.diff(sc.t_s), 1.0 / 20.0)


@pytest.mark.parametrize(("name", "seed"), CASES)
def test_phase_labels_match_the_geometric_contact(name: str, seed: int) -> None:
    sc = scenario(name, seed)
    round_side = {"point"} if sc.object_name == "sphere" else {"line"}
    for phase, contact in zip(sc.phase, sc.contact, strict=True):
        expected = EXPECTED_CONTACT.get(phase, round_side)
        if phase in ("placing", "lifting"):
            expected = {"point", "line", "area"}
        assert contact in expected, (phase, contact)


@pytest.mark.parametrize(("name", "seed"), CASES)
def test_every_contact_state_lasts_several_frames(name: str, seed: int) -> None:
    sc = scenario(name, seed)
    runs = []
    start = 0
    for t in range(1, sc.n_frames + 1):
        if t == sc.n_frames or sc.contact[t] != sc.contact[start]:
            runs.append(t - start)
            start = t
    assert min(runs) >= HOLD_FRAMES_MIN  # the recogniser needs k = 3
    holds = [b - a for p, a, b in sc.phase_runs() if p in ("face", "edge", "vertex", "rim")]
    assert all(n >= HOLD_FRAMES_MIN for n in holds)


@pytest.mark.parametrize(("name", "seed"), CASES)
def test_contact_points_move_only_to_second_order_unless_sliding(name: str, seed: int) -> None:
    sc = scenario(name, seed)
    slip = sc.slip_mm()
    both = ~np.isnan(slip)
    bound = diameter_mm(sc) * (1.0 - np.cos(rotation_steps(sc.rotations))) + 1e-9
    if not sc.slides:
        assert np.all(slip[both] <= bound[both])
        rolling = np.array(sc.phase[1:]) == "rolling"
        assert np.all(sc.slip_mm(full=True)[rolling] <= bound[rolling])
    else:
        moving = [p in ("sliding", "spinning") for p in sc.phase[1:]]
        assert np.any(moving)
        assert np.all(slip[moving] > 5.0 * bound[moving])
        assert np.all(slip[moving] > 0.1)  # at least 2 mm/s at 20 Hz


@pytest.mark.parametrize(("name", "seed"), CASES)
def test_contacts_stay_on_the_array(name: str, seed: int) -> None:
    sc = scenario(name, seed)
    limit = 0.5 * 28.2 - EDGE_MARGIN_MM + 1e-9
    for t in np.nonzero(sc.in_contact)[0]:
        assert np.abs(world_contacts(sc, int(t))[:, :2]).max() <= limit


@pytest.mark.parametrize("seed", SEEDS)
def test_sphere_turns_by_distance_over_radius_and_turns_orthogonally(seed: int) -> None:
    sc = scenario("sphere", seed)
    radius = sc.solid.radius_mm  # type: ignore[attr-defined]
    steps = np.diff(sc.positions_mm, axis=0)
    dist = np.linalg.norm(steps, axis=1)
    np.testing.assert_allclose(rotation_steps(sc.rotations), dist / radius, atol=1e-9)
    moving = dist > 1e-9
    heads = steps[moving] / dist[moving, None]
    cos = np.einsum("ij,ij->i", heads[1:], heads[:-1])
    assert np.all(np.isclose(cos, 1.0) | np.isclose(cos, 0.0, atol=1e-9))  # straight or 90 deg
    assert np.any(np.isclose(cos, 0.0, atol=1e-9))  # at least one orthogonal turn


def edge_lines(sc: Scenario) -> list[tuple[Arr, Arr]]:
    """(midpoint, direction) of the edge of every 'edge' hold that follows a 'face' hold."""
    lines = []
    runs = sc.phase_runs()
    for (p0, _, _), (p1, a, _) in zip(runs[:-2], runs[2:], strict=True):
        if p1 == "edge" and p0 == "face":
            pts = world_contacts(sc, a)
            assert pts.shape[0] == 2
            lines.append((pts.mean(axis=0), (pts[1] - pts[0]) / np.linalg.norm(pts[1] - pts[0])))
    return lines


@pytest.mark.parametrize("name", ["cube", "tetrahedron"])
@pytest.mark.parametrize("seed", SEEDS)
def test_polyhedra_tip_about_fixed_edges_at_the_face_angles(name: str, seed: int) -> None:
    sc = scenario(name, seed)
    for phase, a, b in sc.phase_runs():
        if phase != "tipping":
            continue
        # the pivot (the contact of the tipping frames) stays where it is
        ref = world_contacts(sc, a)
        for t in range(a + 1, b):
            np.testing.assert_allclose(world_contacts(sc, t), ref, atol=1e-9)
    lines = edge_lines(sc)
    assert len(lines) >= 2
    # lines of a square face: parallel or 90 deg; of a triangle: 60 (= 120) deg
    allowed = (0.0, 90.0) if name == "cube" else (60.0,)
    edge = sc.solid.edge_mm  # type: ignore[attr-defined]
    for (m0, d0), (m1, d1) in itertools.pairwise(lines):
        angle = math.degrees(math.acos(min(1.0, abs(float(d0 @ d1)))))  # between lines, 0-90
        assert min(abs(angle - a) for a in allowed) < 1e-6
        assert np.linalg.norm((m1 - m0)[:2]) > 0.25 * edge  # never the same line twice


@pytest.mark.parametrize("seed", SEEDS)
def test_cone_apex_and_frustum_virtual_apex_stay_fixed_while_rolling(seed: int) -> None:
    for name in ("cone", "truncated-cone"):
        sc = scenario(name, seed)
        prof = sc.solid.profile  # type: ignore[attr-defined]
        centre = np.column_stack([sc.positions_mm, sc.rest_height_mm])
        apex = centre + prof.vertex_z_mm * sc.rotations[:, :, 2]
        n_rolls = 0
        for phase, a, b in sc.phase_runs():
            if phase != "rolling":
                continue
            n_rolls += 1
            run = apex[a - 1 : b + 1]  # the run plus the still frames around it
            np.testing.assert_allclose(run, np.broadcast_to(run[0], run.shape), atol=1e-9)
            np.testing.assert_allclose(run[:, 2], 0.0, atol=1e-9)  # on the sensor plane
            for t in range(a, b):  # the contact line points at the (virtual) apex
                pts = world_contacts(sc, t)
                far = pts[np.argmax(np.linalg.norm(pts - run[0], axis=1))]
                lateral = np.cross(pts - run[0], (far - run[0]) / np.linalg.norm(far - run[0]))
                assert np.abs(lateral).max() < 5e-3  # rim samples tie within 4e-3 mm
        assert n_rolls >= 1


@pytest.mark.parametrize("seed", SEEDS)
def test_cylinder_line_moves_parallel_to_itself(seed: int) -> None:
    sc = scenario("cylinder", seed)
    for phase, a, b in sc.phase_runs():
        if phase != "rolling":
            continue
        axis = sc.rotations[a - 1 : b, :, 2]
        np.testing.assert_allclose(axis, np.broadcast_to(axis[0], axis.shape), atol=1e-12)
        assert abs(axis[0, 2]) < 1e-12  # lying
        travel = sc.positions_mm[b - 1] - sc.positions_mm[a - 1]
        assert float(travel @ axis[0, :2]) == pytest.approx(0.0, abs=1e-9)
        assert np.linalg.norm(travel) > 1.0


@pytest.mark.parametrize("seed", SEEDS)
def test_sliding_scenarios_slide(seed: int) -> None:
    sc = scenario("sliding", seed)
    assert sc.slides and sc.object_name in SLIDING_OBJECTS
    assert set(sc.contact) == {"none", "area"}
    assert {"sliding", "spinning"} & set(sc.phase)


def test_sizes_and_depth_follow_the_jitter() -> None:
    for name in SOLID_NAMES:
        defaults = make_solid(name)
        sc = make_scenario(name, rng=4, size_jitter=0.0, depth_jitter=0.0)
        assert sc.solid == defaults
        assert sc.indent_mm.max() == pytest.approx(DEFAULT_DEPTH_MM)
        for seed in range(5):
            solid = make_scenario(name, rng=seed).solid
            for f in solid_size_names(name):
                ratio = getattr(solid, f) / getattr(defaults, f)
                assert 0.7 - 1e-12 <= ratio <= 1.3 + 1e-12


def test_rate_sets_the_sampling_of_the_same_motion() -> None:
    slow, fast = make_scenario("cube", rng=2), make_scenario("cube", rng=2, rate_hz=40.0)
    np.testing.assert_allclose(np.diff(fast.t_s), 0.025)
    assert [p for p, _, _ in slow.phase_runs()] == [p for p, _, _ in fast.phase_runs()]
    assert fast.n_frames == pytest.approx(2 * slow.n_frames, rel=0.1)
    assert fast.t_s[-1] == pytest.approx(slow.t_s[-1], abs=0.2)


@pytest.mark.parametrize("seed", (0, 1))
def test_contact_images_look_like_the_phases(seed: int) -> None:
    checks = 0
    for name in SCENARIO_NAMES:
        sc, images = scenario(name, seed), contact_images(name, seed)
        for t, phase in enumerate(sc.phase):
            area, elong, _ = image_stats(images[t])
            if phase == "lifted":
                assert area == 0
            elif phase in ("vertex", "rim", "apex"):
                assert 1 <= area <= 5, (name, phase, area)
            elif sc.object_name == "sphere" and phase in ("side", "rolling"):
                assert 1 <= area <= 8, (name, phase, area)
            elif phase in ("side", "rolling") and sc.object_name in ("cylinder", "cone"):
                assert elong >= 1.9 and area >= 5, (name, phase, area, elong)
            elif phase == "face":
                assert area >= 9 and elong <= 1.6, (name, phase, area, elong)
                if sc.object_name in ("cube", "tetrahedron"):
                    assert area >= 20
            else:
                continue
            checks += 1
    assert checks > 500


def test_fig3_story_frame_by_frame() -> None:
    sc = cylinder_fig3_scenario()
    assert sc.equals(cylinder_fig3_scenario())
    assert sc.n_frames == 23 and sc.rate_hz == pytest.approx(1.0)
    assert sc.phase == (
        "lifted",
        "placing",
        *["face"] * 5,
        "tipping",
        *["rim"] * 6,
        *["side"] * 3,
        *["rolling"] * 6,
    )
    assert sc.contact == ("none", *["area"] * 6, *["point"] * 7, *["line"] * 9)
    rec = frames_from_scenario(BONNEVILLE_16X16, sc, rng=0)
    stats = [image_stats(img) for img in BONNEVILLE_16X16.contact_from_displacement(rec.frames)]
    area = np.array([s[0] for s in stats])
    elong = np.array([s[1] for s in stats])
    assert area[0] == 0
    assert np.all(area[2:7] >= 20) and np.all(elong[2:7] < 1.4)  # 3-7 area
    assert np.all(area[8:14] <= 4)  # 9-14 point
    assert np.all(area[14:] >= 15) and np.all(elong[14:] >= 2.5)  # 15-23 line
    # image 8: the face lifting about the rim, between the disc and the rim point
    assert area[8:14].max() < area[7] < area[2:7].min()
    assert elong[7] > elong[2:7].max()
    # 18-23: the line keeps its orientation and moves sideways
    angles = np.array([s[2] for s in stats[17:]])
    assert np.ptp(np.mod(angles, np.pi)) < 0.3
    centres = np.array([np.argwhere(img).mean(axis=0) for img in rec.frames[17:] > 0.03])
    travel = centres[-1] - centres[0]
    assert np.linalg.norm(travel) * rec.pitch_mm > 3.0


def test_fig3_motion_is_rolling_without_slip() -> None:
    sc = cylinder_fig3_scenario()
    np.testing.assert_allclose(sc.rest_height_mm, -sc.solid.lowest_z_mm(sc.rotations), atol=1e-9)
    slip = sc.slip_mm()
    bound = 16.0 * (1.0 - np.cos(rotation_steps(sc.rotations))) + 1e-9
    ok = ~np.isnan(slip)
    assert np.all(slip[ok] <= bound[ok])
    axis = sc.rotations[17:, :, 2]
    assert np.allclose(axis, axis[0]) and abs(float(axis[0] @ E_Z)) < 1e-12


def test_fit_on_array_turns_until_the_contact_fits() -> None:
    from taxelkit.motion.array_placement import fit_on_array

    half = np.array([10.0, 2.0])  # a 20 x 4 mm array
    xy = np.array([[0.0, -8.0], [0.0, 8.0]])  # a 16 mm line along y: fits only turned by pi / 2
    margin = np.zeros(2)
    fit = fit_on_array(xy, margin, half, np.array([0.5, 0.5]), tries=8)
    assert fit is not None
    turn, shift = fit
    assert turn == pytest.approx(math.pi / 2)
    c, s = math.cos(turn), math.sin(turn)
    placed = xy @ np.array([[c, s], [-s, c]]) + shift
    assert np.all(np.abs(placed) <= half + 1e-9)
    assert fit_on_array(xy * 2.0, margin, half, np.array([0.5, 0.5]), tries=8) is None
