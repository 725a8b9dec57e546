"""Scores of the baseline policies on the taxelkit gymnasium environments.

Run: ``python benchmarks/gym_baselines.py [--episodes-trace 50] [--episodes-touch 300]``.
Prints a Markdown table (pasted into ``docs/gym.md``). Episodes use seeds
0, 1, 2, ..., so the numbers are reproducible.
"""

from __future__ import annotations

import argparse
import time

import gymnasium as gym

import taxelkit.envs  # noqa: F401  (registers the ids)
from taxelkit.envs.baselines import (
    RandomPolicy,
    ScriptedRollPolicy,
    TracerPolicy,
    evaluate,
)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes-trace", type=int, default=50)
    parser.add_argument("--episodes-touch", type=int, default=300)
    args = parser.parse_args()
    header = (
        "| environment | policy | episodes | mean return (std) | mean steps | success | s/episode |"
    )
    trace = gym.make("taxelkit/EdgeTrace-v0").unwrapped
    touch = gym.make("taxelkit/ActiveTouch-v0").unwrapped
    n_trace = args.episodes_trace
    rows = [
        ("taxelkit/EdgeTrace-v0", "random", trace, RandomPolicy(trace), args.episodes_trace),
        ("taxelkit/EdgeTrace-v0", "tracer (paper 000)", trace, TracerPolicy(trace), n_trace),
        ("taxelkit/ActiveTouch-v0", "random", touch, RandomPolicy(touch), args.episodes_touch),
        (
            "taxelkit/ActiveTouch-v0",
            "scripted roll (paper 001)",
            touch,
            ScriptedRollPolicy(touch),
            args.episodes_touch,
        ),
    ]
    print(header)
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for env_id, name, env, policy, episodes in rows:
        if env_id.endswith("EdgeTrace-v0"):
            success = lambda info: bool(info["closed"])  # noqa: E731
        else:
            success = lambda info: bool(info.get("correct", False))  # noqa: E731
        start = time.perf_counter()
        stats = evaluate(env, policy, episodes=episodes, seed=0, success=success)
        per = (time.perf_counter() - start) / episodes
        print(
            f"| `{env_id}` | {name} | {stats.episodes} | {stats.mean_return:.3f} "
            f"({stats.std_return:.3f}) | {stats.mean_length:.1f} | "
            f"{100 * stats.success_rate:.1f} % | {per:.3f} |"
        )


if __name__ == "__main__":
    main()
