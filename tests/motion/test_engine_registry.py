"""The engine registry and the pure-NumPy sampling of physics records (no MuJoCo needed)."""

from __future__ import annotations

import sys

import numpy as np
import pytest

from taxelkit.cli import run
from taxelkit.errors import InputError
from taxelkit.motion.engines import (
    ENGINE_NAMES,
    MUJOCO_INSTALL_HINT,
    engines_to_run,
    scenario_from_engine,
)
from taxelkit.motion.engines._sampling import (
    matrices_from_quats,
    motion_measures,
    sample_times,
    slerp,
)
from taxelkit.motion.scenarios import make_scenario
from taxelkit.world.pose import matrix_from_axis_angle


def test_engine_names() -> None:
    assert ENGINE_NAMES == ("kinematic", "mujoco")


def test_engines_to_run_skips_a_missing_mujoco(monkeypatch: pytest.MonkeyPatch) -> None:
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "mujoco" else real(name, *a)
    )
    assert engines_to_run(None) == (
        ["kinematic"],
        {"mujoco": f"not installed ({MUJOCO_INSTALL_HINT})"},
    )
    with pytest.raises(InputError, match="no engine available"):
        engines_to_run(["mujoco"])
    with pytest.raises(InputError, match="unknown engine 'bullet'; known: kinematic, mujoco"):
        engines_to_run(["kinematic", "bullet"])
    assert engines_to_run(["kinematic"]) == (["kinematic"], {})


def test_kinematic_engine_is_make_scenario() -> None:
    a = scenario_from_engine("kinematic", "cube", rng=5, rate_hz=30.0)
    assert a.equals(make_scenario("cube", rng=5, rate_hz=30.0))


def test_kinematic_refuses_lift_gap() -> None:
    with pytest.raises(InputError, match="not supported by the kinematic engine"):
        scenario_from_engine("kinematic", "cube", rng=1, lift_gap_s=0.1)


def test_unknown_engine() -> None:
    with pytest.raises(InputError, match="unknown engine 'bullet'; known: kinematic, mujoco"):
        scenario_from_engine("bullet", "cube")


def test_missing_mujoco_says_how_to_install(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "mujoco", None)  # import mujoco -> ImportError
    with pytest.raises(InputError) as err:
        scenario_from_engine("mujoco", "sphere", rng=0)
    assert MUJOCO_INSTALL_HINT in str(err.value)
    assert "\n" not in str(err.value)


def test_cli_without_mujoco_fails_in_one_line(
    monkeypatch: pytest.MonkeyPatch, tmp_path: pytest.TempPathFactory
) -> None:
    monkeypatch.setitem(sys.modules, "mujoco", None)
    lines: list[str] = []
    out = f"{tmp_path}/r.npz"
    code = run(
        ["simulate", "roll", "--object", "sphere", "--engine", "mujoco", "--out", out],
        echo_err=lines.append,
    )
    assert code == 2
    assert len(lines) == 1 and 'pip install "taxelkit[mujoco]"' in lines[0]


def test_sample_times_are_exact_at_common_times() -> None:
    t20, i20, f20 = sample_times(5001, 1000, 20.0)
    t100, i100, f100 = sample_times(5001, 1000, 100.0)
    assert t20.size == 101 and t100.size == 501
    np.testing.assert_array_equal(t100[::5], t20)
    np.testing.assert_array_equal(i100[::5], i20)
    np.testing.assert_array_equal(f100[::5], f20)
    assert np.all(f20[:-1] == 0.0)  # the last frame sits on the last step, as f = 1
    t240, i240, f240 = sample_times(5001, 1000, 240.0)
    assert t240[-1] <= 5.0 and np.all((f240 >= 0.0) & (f240 <= 1.0))
    np.testing.assert_allclose(i240 + f240, t240 * 1000.0, atol=1e-9)


def test_slerp_endpoints_and_midpoint() -> None:
    q0 = np.array([[1.0, 0.0, 0.0, 0.0]])
    half = np.sin(0.5)
    q1 = np.array([[np.cos(0.5), 0.0, 0.0, half]])  # 1 rad about z
    np.testing.assert_array_equal(slerp(q0, q1, np.array([0.0])), q0)
    mid = matrices_from_quats(slerp(q0, q1, np.array([0.5])))[0]
    np.testing.assert_allclose(mid, matrix_from_axis_angle([0.0, 0.0, 1.0], 0.5), atol=1e-12)


def test_motion_measures_closed_form() -> None:
    """A body turning at 1 rad/s about z, centroid still: speed = radius, all spin."""
    n = 200
    ang = np.arange(n) / 1000.0
    quats = np.column_stack([np.cos(ang / 2), np.zeros(n), np.zeros(n), np.sin(ang / 2)])
    speed, spin, slip = motion_measures(
        quats, np.zeros((n, 3)), np.full(n, 2.0), radius_mm=5.0, steps_per_s=1000
    )
    np.testing.assert_allclose(speed[50:150], 5.0, rtol=1e-9)
    np.testing.assert_allclose(spin[50:150], 1.0, rtol=1e-9)
    np.testing.assert_allclose(slip, 2.0)
