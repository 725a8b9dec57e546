"""The gymnasium environments: registration, env checker, determinism, baselines."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

gym = pytest.importorskip("gymnasium", reason="the environments need the gym extra")

from gymnasium.utils.env_checker import check_env  # noqa: E402

import taxelkit.envs  # noqa: E402
from taxelkit.envs.active_touch import TOUCH_COST, ActiveTouchEnv, move_boundaries  # noqa: E402
from taxelkit.envs.baselines import (  # noqa: E402
    RandomPolicy,
    ScriptedRollPolicy,
    TracerPolicy,
    evaluate,
)
from taxelkit.envs.edge_trace import EdgeTraceEnv, progress_along  # noqa: E402
from taxelkit.errors import InputError  # noqa: E402


@pytest.mark.parametrize("env_id", sorted(taxelkit.envs.ENV_IDS))
def test_registered_and_passes_the_env_checker(env_id: str) -> None:
    env = gym.make(env_id)
    check_env(env.unwrapped, skip_render_check=True)
    env.close()


def test_make_with_module_prefix() -> None:
    env = gym.make("taxelkit.envs:taxelkit/ActiveTouch-v0")
    assert isinstance(env.unwrapped, ActiveTouchEnv)


def _rollout(env: Any, actions: list[Any], seed: int) -> list[Any]:
    obs, _ = env.reset(seed=seed)
    out = [obs]
    for a in actions:
        obs, reward, terminated, truncated, _ = env.step(a)
        out.append((obs, reward, terminated, truncated))
        if terminated or truncated:
            break
    return out


def _same(a: Any, b: Any) -> bool:
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, tuple | list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    return bool(np.array_equal(a, b))


@pytest.mark.parametrize(
    ("make", "actions"),
    [
        (lambda: EdgeTraceEnv(max_steps=5), [np.array([0.5, 0.1], np.float32)] * 5),
        (ActiveTouchEnv, [0, 0, 0, 2]),
    ],
)
def test_same_seed_same_trajectory(make: Any, actions: list[Any]) -> None:
    first, second = _rollout(make(), actions, 7), _rollout(make(), actions, 7)
    assert _same(first, second)
    other = _rollout(make(), actions, 8)
    assert not _same(first, other)


def test_progress_along_a_square() -> None:
    square = np.array([[0, 0], [2, 0], [2, 2], [0, 2], [0, 0]], float)
    arc = np.array([0.0, 2.0, 4.0, 6.0, 8.0])
    assert progress_along(square, arc, np.array([1.0, -0.5])) == pytest.approx(1.0)
    assert progress_along(square, arc, np.array([-0.3, 1.5])) == pytest.approx(6.5)


def test_edge_trace_reward_is_progress_and_lost_terminates() -> None:
    env = EdgeTraceEnv(shapes=("circle",), max_steps=50)
    _, info = env.reset(seed=3)
    assert info["distance_mm"] < 1.0
    # Straight out of the plate: the array loses the edge and the episode ends.
    position = info["position_mm"]
    outward = position / np.hypot(*position)
    total, terminated, steps = 0.0, False, 0
    while not terminated and steps < 10:
        _, reward, terminated, _, info = env.step(outward.astype(np.float32))
        total += reward
        steps += 1
    assert terminated and info["lost"] and not info["closed"]
    assert abs(total) < 0.01  # moving along the normal makes no progress


def test_tracer_closes_the_loop_and_random_does_not() -> None:
    env = EdgeTraceEnv(shapes=("square",))
    tracer = evaluate(env, TracerPolicy(env), episodes=2, success=lambda i: i["closed"])
    assert tracer.success_rate == 1.0
    assert tracer.mean_return == pytest.approx(1.0, abs=0.05)
    rand = evaluate(env, RandomPolicy(env), episodes=2, success=lambda i: i["closed"])
    assert rand.success_rate == 0.0 and rand.mean_return < 0.2


def test_move_boundaries_split_at_moves() -> None:
    runs = (
        ("lifted", 0, 3),
        ("placing", 3, 5),
        ("side", 5, 9),
        ("rolling", 9, 20),
        ("side", 20, 30),
    )
    assert move_boundaries(runs, 30) == [9, 30]


def test_active_touch_rewards() -> None:
    env = ActiveTouchEnv()
    _, info = env.reset(seed=4)
    _, reward, terminated, truncated, info = env.step(0)
    assert reward == -TOUCH_COST and not terminated and not truncated
    right = 1 + env.objects.index(info["object"])
    _, reward, terminated, _, info = env.step(right)
    assert reward == 1.0 and terminated and info["correct"]
    env.reset(seed=4)
    wrong = 1 + (right % len(env.objects))
    assert env.step(wrong)[1] == -1.0


def test_active_touch_truncates_and_refuses_bad_actions() -> None:
    env = ActiveTouchEnv(max_steps=3)
    env.reset(seed=0)
    results = [env.step(0) for _ in range(3)]
    assert [r[3] for r in results] == [False, False, True]
    with pytest.raises(InputError, match=r"action must be in 0\.\.6"):
        env.step(7)


def test_scripted_roll_beats_random() -> None:
    env = ActiveTouchEnv()

    def correct(info: dict[str, Any]) -> bool:
        return bool(info.get("correct", False))

    scripted = evaluate(env, ScriptedRollPolicy(env), episodes=24, success=correct)
    rand = evaluate(env, RandomPolicy(env), episodes=24, success=correct)
    assert scripted.success_rate >= 0.8
    assert scripted.mean_return > rand.mean_return + 0.3


def test_bad_parameters() -> None:
    with pytest.raises(InputError, match="shapes must be among"):
        EdgeTraceEnv(shapes=("hexgon",))
    with pytest.raises(InputError, match="max_steps"):
        ActiveTouchEnv(max_steps=0)
