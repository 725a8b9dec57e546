"""The baseline scores in docs/gym.md are what the environments and policies give now.

``benchmarks/gym_baselines.py`` printed that table (episodes seeded 0, 1, 2, ...);
each row is re-run here with the same seeds and its deterministic columns
(episodes, mean return and its std, mean steps, success rate) must read the
same. The last column, wall time per episode, is not compared. The cheapest row
runs by default, the others under the ``slow`` marker.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest

pytest.importorskip("gymnasium", reason="the environments need the gym extra")

GYM_PAGE = Path(__file__).resolve().parents[2] / "docs" / "gym.md"
_ROW = re.compile(
    r"^\| `(taxelkit/[A-Za-z]+-v0)` \| ([^|]+) \| (\d+) \| ([^|]+) \| ([^|]+) \| ([^|]+) \|"
)


def documented() -> dict[tuple[str, str], list[str]]:
    """``(env id, policy) -> [episodes, return (std), steps, success]`` from docs/gym.md."""
    out = {}
    for line in GYM_PAGE.read_text(encoding="utf-8").splitlines():
        m = _ROW.match(line)
        if m:
            out[(m.group(1), m.group(2).strip())] = [g.strip() for g in m.groups()[2:]]
    return out


def measured(env_id: str, policy_name: str, episodes: int) -> list[str]:
    import gymnasium as gym

    import taxelkit.envs  # noqa: F401  (registers the ids)
    from taxelkit.envs.baselines import RandomPolicy, ScriptedRollPolicy, TracerPolicy, evaluate

    env: Any = gym.make(env_id).unwrapped
    policies = {"random": RandomPolicy, "tracer (paper 000)": TracerPolicy}
    policies["scripted roll (paper 001)"] = ScriptedRollPolicy
    if env_id.endswith("EdgeTrace-v0"):
        success = lambda info: bool(info["closed"])  # noqa: E731
    else:
        success = lambda info: bool(info.get("correct", False))  # noqa: E731
    s = evaluate(env, policies[policy_name](env), episodes=episodes, seed=0, success=success)
    return [
        str(s.episodes),
        f"{s.mean_return:.3f} ({s.std_return:.3f})",
        f"{s.mean_length:.1f}",
        f"{100 * s.success_rate:.1f} %",
    ]


ROWS = [
    ("taxelkit/EdgeTrace-v0", "random"),
    pytest.param("taxelkit/EdgeTrace-v0", "tracer (paper 000)", marks=pytest.mark.slow),
    pytest.param("taxelkit/ActiveTouch-v0", "random", marks=pytest.mark.slow),
    pytest.param("taxelkit/ActiveTouch-v0", "scripted roll (paper 001)", marks=pytest.mark.slow),
]


def test_the_page_has_the_four_rows() -> None:
    assert len(documented()) == 4


@pytest.mark.parametrize(("env_id", "policy"), ROWS)
def test_documented_baseline_is_what_the_code_gives(env_id: str, policy: str) -> None:
    row = documented()[(env_id, policy)]
    assert measured(env_id, policy, int(row[0])) == row
