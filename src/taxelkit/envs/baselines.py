"""Baseline policies for the taxelkit environments, and a seeded evaluation loop.

``taxelkit/EdgeTrace-v0``
    :class:`RandomPolicy` (uniform moves) and :class:`TracerPolicy`, the
    edge-tracing controller of paper 000 (Eq. 7 with the crossing-line edge
    estimate) run on the observation alone: it rebuilds the two scans from the
    frames and the robot's own scan settings, and dead-reckons its position
    from its own commanded moves.
``taxelkit/ActiveTouch-v0``
    :class:`RandomPolicy` (uniform actions) and :class:`ScriptedRollPolicy`,
    the strategy of paper 001: keep rolling the object (touch) until the smart
    sensor identifies it or the script is over, then answer its verdict (or
    the first candidate left).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from gymnasium import Env
from numpy.typing import NDArray

from taxelkit.envs.edge_trace import MAX_STEP_MM, EdgeTraceEnv
from taxelkit.motion.probe import Scan
from taxelkit.tracing.edge_estimate import estimate_edge
from taxelkit.tracing.tracer import TracerConfig, plan_move

__all__ = [
    "EpisodeStats",
    "Policy",
    "RandomPolicy",
    "ScriptedRollPolicy",
    "TracerPolicy",
    "evaluate",
]


class Policy(Protocol):
    """What :func:`evaluate` runs: ``reset(seed)`` per episode, then ``act(obs)``."""

    def reset(self, seed: int) -> None:
        """Start an episode."""
        ...

    def act(self, observation: Any) -> Any:
        """The action for an observation."""
        ...


#: Mixed into the episode seed for :class:`RandomPolicy`, so that its actions
#: are independent of the environment's own draws from the same seed.
_POLICY_SEED_SALT = 0x5EED


class RandomPolicy:
    """Uniformly random actions from the environment's action space (seeded per episode).

    The space is seeded from ``(seed, salt)`` through :class:`numpy.random.SeedSequence`,
    never with the episode seed itself: the environment draws its object from
    that seed, and the same stream would correlate the answers with it.
    """

    def __init__(self, env: Env[Any, Any]) -> None:
        self.space = env.action_space

    def reset(self, seed: int) -> None:
        """Seed the action space from the episode seed."""
        state = np.random.SeedSequence([int(seed), _POLICY_SEED_SALT]).generate_state(1)
        self.space.seed(int(state[0]))

    def act(self, observation: Any) -> Any:
        """A uniform sample, whatever the observation."""
        del observation
        return self.space.sample()


class TracerPolicy:
    """The edge tracer of paper 000 as a policy for ``EdgeTrace-v0``.

    Parameters
    ----------
    env : EdgeTraceEnv
        The (unwrapped) environment, for the robot's own scan settings and
        feeler layout; never its specimen.
    config : TracerConfig, optional
    """

    def __init__(self, env: EdgeTraceEnv, config: TracerConfig | None = None) -> None:
        self.config = TracerConfig() if config is None else config
        self.offsets_mm = env.scan_config.offsets_mm()
        self.dt_s = env.scan_config.dt_s
        self.speed_mm_s = env.scan_config.speed_mm_s
        self.element_offsets_mm = env.element_offsets_mm
        self.position_mm = np.zeros(2)
        self.heading: NDArray[np.float64] | None = None

    def reset(self, seed: int) -> None:
        """Forget the position and heading (the tracer is deterministic)."""
        del seed
        self.position_mm = np.zeros(2)
        self.heading = None

    def act(self, observation: NDArray[np.float32]) -> NDArray[np.float32]:
        """``dr = dv + de`` (Eq. 7) from the two scans, as a normalised action."""
        frames = np.asarray(observation, dtype=np.float64)
        scans = [
            Scan(self.position_mm, axis, self.offsets_mm, frames[axis], self.dt_s, self.speed_mm_s)
            for axis in (0, 1)
        ]
        est = estimate_edge(scans[0], scans[1], self.element_offsets_mm, self.config.detector)
        if est.found:
            dv, de, self.heading = plan_move(est, self.position_mm, self.config)
            move = dv + de
        elif self.heading is not None:  # coast one section, as the tracer does at a miss
            move = self.config.section_mm * self.heading
        else:
            move = np.zeros(2)
        action = np.clip(move / MAX_STEP_MM, -1.0, 1.0)
        self.position_mm = self.position_mm + action * MAX_STEP_MM
        return action.astype(np.float32)


class ScriptedRollPolicy:
    """Paper 001's strategy for ``ActiveTouch-v0``: roll until identified, then answer."""

    def __init__(self, env: Env[Any, Any]) -> None:
        del env

    def reset(self, seed: int) -> None:
        """Nothing to reset."""
        del seed

    def act(self, observation: dict[str, NDArray[Any]]) -> int:
        """Touch while undecided and moves are left; else answer the verdict or a candidate."""
        identified = np.flatnonzero(observation["identified"])
        if identified.size:
            return 1 + int(identified[0])
        if float(observation["script_left"][0]) > 0.0:
            return 0
        left = np.flatnonzero(observation["candidates"])
        return 1 + int(left[0]) if left.size else 1


@dataclass(frozen=True)
class EpisodeStats:
    """Summary of :func:`evaluate`.

    Attributes
    ----------
    episodes : int
    mean_return, std_return : float
        Over episodes (``std`` with ``ddof = 0``).
    mean_length : float
        Steps per episode.
    success_rate : float
        Fraction of episodes where ``success(info)`` held at the end.
    """

    episodes: int
    mean_return: float
    std_return: float
    mean_length: float
    success_rate: float


def evaluate(
    env: Env[Any, Any],
    policy: Policy,
    *,
    episodes: int,
    seed: int = 0,
    success: Callable[[dict[str, Any]], bool],
) -> EpisodeStats:
    """Run ``episodes`` seeded episodes (seeds ``seed, seed + 1, ...``) and summarise them.

    Parameters
    ----------
    env : gymnasium.Env
    policy : Policy
    episodes : int
    seed : int, optional
        First episode seed; the same seeds give the same statistics.
    success : callable
        Reads the last step's ``info``: did the episode succeed?

    Returns
    -------
    EpisodeStats
    """
    returns, lengths, wins = [], [], 0
    for k in range(int(episodes)):
        obs, info = env.reset(seed=seed + k)
        policy.reset(seed + k)
        total, steps, done = 0.0, 0, False
        while not done:
            obs, reward, terminated, truncated, info = env.step(policy.act(obs))
            total += float(reward)
            steps += 1
            done = terminated or truncated
        returns.append(total)
        lengths.append(steps)
        wins += bool(success(info))
    r = np.asarray(returns)
    return EpisodeStats(
        episodes=int(episodes),
        mean_return=float(r.mean()),
        std_return=float(r.std()),
        mean_length=float(np.mean(lengths)),
        success_rate=wins / int(episodes),
    )
