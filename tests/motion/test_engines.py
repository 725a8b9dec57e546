"""MuJoCo scenes: determinism, contact and slip physics, rate independence, lift gaps, CLI."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip(
    "mujoco",
    reason='the MuJoCo engine is an optional extra: pip install "taxelkit[mujoco]"',
)

from taxelkit.cli import run
from taxelkit.errors import InputError
from taxelkit.io.recordings import read_recording
from taxelkit.motion.engines import scenario_from_engine
from taxelkit.motion.engines._sampling import contact_footprint_mm
from taxelkit.motion.engines.mujoco_scenes import MujocoScene, mujoco_scene
from taxelkit.motion.rolling import Scenario, frames_from_scenario
from taxelkit.motion.scenarios import SCENARIO_NAMES
from taxelkit.sensors.presets import BONNEVILLE_16X16

ROLLING = ("sphere", "cylinder", "cone", "truncated-cone")
#: A resting body sinks a few micrometres into the plate (soft contacts); a
#: landing vertex briefly up to about 0.2 mm.
TYPICAL_GAP_MM = 0.03
WORST_GAP_MM = 0.25


@pytest.fixture(scope="module")
def scenes() -> dict[str, MujocoScene]:
    return {name: mujoco_scene(name, rng=0) for name in SCENARIO_NAMES}


@pytest.mark.parametrize("name", SCENARIO_NAMES)
def test_scene_starts_and_ends_lifted(scenes: dict[str, MujocoScene], name: str) -> None:
    sc = scenes[name].scenario
    assert sc.phase[0] == "lifted" and sc.phase[-1] == "lifted"
    assert sc.indent_mm[0] < 0.0 and sc.indent_mm[-1] < 0.0
    assert sc.in_contact.sum() > 20
    # the body touches in one stretch (no lift gap asked for)
    runs = [p for p, _, _ in sc.phase_runs() if p == "lifted"]
    assert len(runs) == 2
    np.testing.assert_array_equal(sc.in_contact, np.array([p != "lifted" for p in sc.phase]))


@pytest.mark.parametrize("name", SCENARIO_NAMES)
def test_scene_stays_on_the_array(scenes: dict[str, MujocoScene], name: str) -> None:
    sc = scenes[name].scenario
    touch = sc.in_contact
    depth = float(sc.indent_mm.max())
    xy, margin = contact_footprint_mm(sc.solid, sc.rotations[touch], sc.positions_mm[touch], depth)  # type: ignore[arg-type]
    half = 0.5 * BONNEVILLE_16X16.array.width_mm
    assert np.all(np.abs(xy) + margin[:, None] <= half + 0.1)
    if name == "cone":  # the apex it rolls about is on the array
        apex = sc.centroids_mm + sc.solid.profile.vertex_z_mm * sc.rotations[:, :, 2]  # type: ignore[union-attr]
        assert np.all(np.abs(apex[touch, :2]) <= half)
    frames = frames_from_scenario(BONNEVILLE_16X16, sc, add_noise=False)
    threshold = BONNEVILLE_16X16.contact_threshold_mm
    touching = frames.frames > threshold
    pressed = sc.indent_mm > 2.0 * threshold  # the ends of the press ramps may not show
    assert touching[pressed].any(axis=(1, 2)).all()
    assert not touching[~sc.in_contact].any()


@pytest.mark.parametrize("name", SCENARIO_NAMES)
def test_poses_are_physical(scenes: dict[str, MujocoScene], name: str) -> None:
    ms = scenes[name]
    sc = ms.scenario
    eye = np.einsum("tij,tkj->tik", sc.rotations, sc.rotations)
    np.testing.assert_allclose(eye, np.broadcast_to(np.eye(3), eye.shape), atol=1e-12)
    np.testing.assert_allclose(sc.rest_height_mm, -sc.solid.lowest_z_mm(sc.rotations))
    gap = np.abs(ms.gap_mm[sc.in_contact])
    assert np.quantile(gap, 0.95) < TYPICAL_GAP_MM
    assert gap.max() < WORST_GAP_MM
    assert np.all(ms.gap_mm[~sc.in_contact] >= -0.005)
    assert ms.mujoco_version and ms.n_steps > 1000
    assert 0.0 < ms.friction <= (0.15 if name == "sliding" else 1.2)
    assert 950.0 <= ms.density_kg_m3 <= 1400.0


@pytest.mark.parametrize("name", SCENARIO_NAMES)
def test_slip_only_in_the_sliding_scene(scenes: dict[str, MujocoScene], name: str) -> None:
    ms = scenes[name]
    sc = ms.scenario
    slip = sc.slip_mm()
    slip = slip[np.isfinite(slip)]
    path = np.linalg.norm(np.diff(sc.positions_mm, axis=0), axis=1)[sc.in_contact[1:]].sum()
    if name == "sliding":
        assert sc.slides
        assert {"sliding", "spinning"} & set(sc.phase)
        assert slip.max() > 0.1  # mm per 50 ms frame: 2 mm/s and more
    else:
        assert not sc.slides
        assert not {"sliding", "spinning"} & set(sc.phase)
        assert np.quantile(slip, 0.99) < 0.02
        assert slip.sum() < 0.05 * max(path, 1.0)


@pytest.mark.parametrize(
    ("name", "expected"),
    [
        ("sphere", {"rolling", "side"}),
        ("cylinder", {"rolling", "side"}),
        ("cone", {"rolling", "side"}),
        ("truncated-cone", {"rolling", "side"}),
        ("cube", {"tipping", "edge", "face"}),
        ("tetrahedron", {"tipping", "edge", "face"}),
    ],
)
def test_scene_shows_its_motion(
    scenes: dict[str, MujocoScene], name: str, expected: set[str]
) -> None:
    sc = scenes[name].scenario
    assert expected <= set(sc.phase)
    kinds = {k for k in scenes[name].contact if k != "none"}
    if name in ("cube", "tetrahedron"):
        assert kinds == {"area", "line"} or kinds == {"area", "line", "point"}
    elif name != "sphere":
        assert "line" in kinds


def test_same_seed_same_scene(scenes: dict[str, MujocoScene]) -> None:
    again = mujoco_scene("tetrahedron", rng=0)
    assert again.scenario.equals(scenes["tetrahedron"].scenario)
    other = mujoco_scene("tetrahedron", rng=1)
    assert not other.scenario.equals(scenes["tetrahedron"].scenario)


def test_rate_does_not_change_the_motion(scenes: dict[str, MujocoScene]) -> None:
    slow = scenes["cylinder"].scenario
    fast = scenario_from_engine("mujoco", "cylinder", rng=0, rate_hz=100.0)
    assert len(range(0, fast.n_frames, 5)) == slow.n_frames
    picked = Scenario(
        name=fast.name,
        object_name=fast.object_name,
        solid=fast.solid,
        rotations=fast.rotations[::5],
        positions_mm=fast.positions_mm[::5],
        rest_height_mm=fast.rest_height_mm[::5],
        indent_mm=fast.indent_mm[::5],
        t_s=fast.t_s[::5],
        phase=fast.phase[::5],
        slides=fast.slides,
    )
    assert picked.equals(slow)


def test_lift_gap_loses_contact_once_mid_script() -> None:
    ms = mujoco_scene("sphere", rng=2, rate_hz=200.0, lift_gap_s=0.1)
    sc = ms.scenario
    runs = sc.phase_runs()
    lifted = [(a, b) for p, a, b in runs if p == "lifted"]
    assert len(lifted) == 3
    a, b = lifted[1]
    assert 0.05 <= (b - a) / 200.0 <= 0.15  # about lift_gap_s without contact
    assert sc.indent_mm[a:b].max() < 0.0
    assert sc.phase[a - 1] not in ("placing", "lifting")  # abrupt: no press ramp


def test_bad_parameters() -> None:
    with pytest.raises(InputError, match="rate_hz"):
        mujoco_scene("sphere", rate_hz=2000.0)
    with pytest.raises(InputError, match="unknown scenario"):
        mujoco_scene("pyramid")
    with pytest.raises(InputError, match="lift_gap_s"):
        mujoco_scene("sphere", lift_gap_s=-1.0)


def test_cli_writes_a_mujoco_recording(tmp_path: Path, scenes: dict[str, MujocoScene]) -> None:
    out = tmp_path / "cyl.npz"
    args = ["simulate", "roll", "--object", "cylinder", "--engine", "mujoco", "--seed", "0"]
    assert run([*args, "--contact", "--out", str(out)]) == 0
    rec = read_recording(out)
    assert rec.n_frames == scenes["cylinder"].scenario.n_frames
    assert rec.frames.dtype == np.bool_ and rec.frames.shape[1:] == (16, 16)


@pytest.mark.parametrize("seed", range(4))
def test_a_slid_face_is_a_face_in_the_ground_truth(seed: int) -> None:
    """The sliding script drags or spins a body on a face; its scenario says so.

    MuJoCo's resting face is level only to micrometres: with the exact poses'
    tolerances it read as a line or a point (and the ``slip`` experiment
    counted a spinning disc as a line's slip).
    """
    scene = mujoco_scene("sliding", rng=seed)
    sc = scene.scenario
    slid = [c for p, c in zip(sc.phase, sc.contact, strict=True) if p in ("sliding", "spinning")]
    assert slid and set(slid) == {"area"}
    assert scene.contact == sc.contact
