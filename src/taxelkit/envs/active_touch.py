"""``taxelkit/ActiveTouch-v0``: identify an object on the 16 x 16 array in few touches (paper 001).

The smart sensor of paper 001 as a decision problem:

- **object**: one of the six solids (:data:`~taxelkit.smart.tacteme_table.OBJECTS`),
  with random sizes, pose and motion script, drawn at every reset exactly as
  ``taxelkit simulate roll`` draws them (:func:`~taxelkit.motion.scenarios.make_scenario`);
- **actions** (``Discrete(7)``): ``0`` *touch*: the object is pushed or tilted
  through the next move of its script (placed on the array, tipped over an
  edge, rolled, lifted off), ending in a still hold, and the smart sensor
  reads the frames; ``1 + k``: *answer* ``OBJECTS[k]``, which ends the episode;
- **observation** (``Dict``): ``contact``, the last contact image (16 x 16,
  1 = taxel deflected more than 0.03 mm); ``candidates``, the objects the
  sensor has not eliminated (6 flags); ``identified``, the sensor's verdict
  (one-hot, all 0 while undecided); ``script_left``, the fraction of the
  object's moves not yet played;
- **reward**: ``-`` :data:`TOUCH_COST` per touch, then ``+1`` for a right
  answer and ``-1`` for a wrong one;
- **truncation** after ``max_steps`` actions without an answer. Touching after
  the script's last move (the object is lifted off) only costs.

The frames, the tactemes and the eliminations are those of the batch
recogniser on the whole roll (the smart sensor is fed frame by frame). The
script's moves are fixed by the seed; the agent chooses when it has touched
enough and what to answer.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import Env, spaces
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.frames import TactileFrames
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import make_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart.recogniser import SmartSensor
from taxelkit.smart.tacteme_table import OBJECTS

__all__ = ["ANSWER_REWARD", "TOUCH_COST", "ActiveTouchEnv", "move_boundaries"]

#: Reward of one touch: a small cost, so that fewer touches score higher.
TOUCH_COST = 0.05
#: Reward of a right answer (its negative for a wrong one).
ANSWER_REWARD = 1.0
#: Contact threshold of the observation's contact image, mm (the recogniser's default).
CONTACT_THRESHOLD_MM = 0.03
#: Script phases that move the object; a touch plays one of them and the still
#: hold after it.
_MOVING_PHASES = frozenset({"tipping", "rolling", "lifting", "sliding", "spinning"})


def move_boundaries(phase_runs: tuple[tuple[str, int, int], ...], n_frames: int) -> list[int]:
    """Frame indices where each touch ends: before every move after the first contact.

    Parameters
    ----------
    phase_runs : tuple of (str, int, int)
        ``(phase, start, stop)`` runs of a scenario.
    n_frames : int
        Frames in the scenario.

    Returns
    -------
    list of int
        Increasing stop indices; the last is ``n_frames``.

    Examples
    --------
    >>> runs = (("lifted", 0, 5), ("placing", 5, 8), ("face", 8, 12),
    ...         ("tipping", 12, 15), ("edge", 15, 20), ("lifting", 20, 22), ("lifted", 22, 25))
    >>> move_boundaries(runs, 25)
    [12, 20, 25]
    """
    stops = [start for phase, start, _ in phase_runs if phase in _MOVING_PHASES and start > 0]
    return [*sorted(set(stops)), n_frames]


class ActiveTouchEnv(Env[dict[str, NDArray[Any]], np.int64]):
    """Identify a solid on the Bonneville array with as few touches as possible.

    Parameters
    ----------
    max_steps : int, optional
        Actions before the episode is truncated.
    render_mode : None
        No rendering; accepted for the gymnasium API.

    Examples
    --------
    >>> env = ActiveTouchEnv()
    >>> obs, info = env.reset(seed=0)
    >>> sorted(obs), obs["contact"].shape, env.action_space.n
    (['candidates', 'contact', 'identified', 'script_left'], (16, 16), 7)
    """

    metadata: dict[str, Any] = {"render_modes": []}  # noqa: RUF012 (gymnasium's API)

    def __init__(self, *, max_steps: int = 20, render_mode: str | None = None) -> None:
        if int(max_steps) < 1:
            raise InputError(f"max_steps must be >= 1, got {max_steps!r}")
        if render_mode is not None:
            raise InputError(f"ActiveTouch-v0 has no render modes, got {render_mode!r}")
        self.max_steps = int(max_steps)
        self.render_mode = render_mode
        self.objects = OBJECTS
        self.sensor = BONNEVILLE_16X16
        shape = (self.sensor.array.rows, self.sensor.array.cols)
        n = len(self.objects)
        self.observation_space = spaces.Dict(  # type: ignore[assignment]
            {
                "contact": spaces.MultiBinary(shape),
                "candidates": spaces.MultiBinary(n),
                "identified": spaces.MultiBinary(n),
                "script_left": spaces.Box(0.0, 1.0, (1,), np.float32),
            }
        )
        self.n_actions = 1 + n
        self.action_space = spaces.Discrete(self.n_actions)
        self._rec: TactileFrames | None = None
        self._smart: SmartSensor | None = None
        self._stops: list[int] = []
        self._next = 0
        self._frame = 0
        self._steps = 0
        self._object = ""
        self._candidates = self.objects
        self._identified: str | None = None

    def _flags(self, names: tuple[str, ...]) -> NDArray[np.int8]:
        return np.array([name in names for name in self.objects], dtype=np.int8)

    def _observe(self) -> dict[str, NDArray[Any]]:
        assert self._rec is not None
        last = self._rec.frames[max(self._frame - 1, 0)]
        contact = (last > CONTACT_THRESHOLD_MM) if self._frame else np.zeros_like(last, bool)
        left = 1.0 - self._next / len(self._stops)
        return {
            "contact": contact.astype(np.int8),
            "candidates": self._flags(self._candidates),
            "identified": self._flags(() if self._identified is None else (self._identified,)),
            "script_left": np.array([left], dtype=np.float32),
        }

    def _info(self) -> dict[str, Any]:
        return {
            "object": self._object,
            "touches": self._next,
            "moves": len(self._stops),
            "identified": self._identified,
            "candidates": self._candidates,
        }

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, NDArray[Any]], dict[str, Any]]:
        """Draw an object and its motion script; nothing touches the sensor yet."""
        super().reset(seed=seed)
        del options
        rng = self.np_random
        self._object = self.objects[int(rng.integers(len(self.objects)))]
        scenario = make_scenario(self._object, rng=int(rng.integers(2**31)), sensor=self.sensor)
        self._rec = frames_from_scenario(self.sensor, scenario, rng=int(rng.integers(2**31)))
        self._stops = move_boundaries(scenario.phase_runs(), self._rec.n_frames)
        self._smart = SmartSensor(self._rec.shape[1:], pitch_mm=self._rec.pitch_mm)
        self._next = self._frame = self._steps = 0
        self._candidates = self.objects
        self._identified = None
        return self._observe(), self._info()

    def _touch(self) -> None:
        assert self._rec is not None and self._smart is not None
        if self._next >= len(self._stops):
            return
        stop = self._stops[self._next]
        self._next += 1
        for j in range(self._frame, stop):
            for event in self._smart.push(self._rec.frames[j], float(self._rec.t_s[j])):
                if event.kind in ("candidates", "lifted") and isinstance(event.value, tuple):
                    self._candidates = event.value
                elif event.kind == "identified" and isinstance(event.value, str):
                    self._identified = event.value if event.value in self.objects else None
        self._frame = stop

    def step(
        self, action: np.int64 | int
    ) -> tuple[dict[str, NDArray[Any]], float, bool, bool, dict[str, Any]]:
        """Touch (``0``) or answer ``OBJECTS[action - 1]``."""
        if self._rec is None:
            raise InputError("call reset() before step()")
        a = int(action)
        if not 0 <= a < self.n_actions:
            raise InputError(f"action must be in 0..{self.n_actions - 1}, got {action!r}")
        self._steps += 1
        info = self._info()
        if a == 0:
            self._touch()
            info = self._info()
            truncated = self._steps >= self.max_steps
            return self._observe(), -TOUCH_COST, False, truncated, info
        answer = self.objects[a - 1]
        info["answer"] = answer
        info["correct"] = answer == self._object
        reward = ANSWER_REWARD if info["correct"] else -ANSWER_REWARD
        return self._observe(), reward, True, False, info
