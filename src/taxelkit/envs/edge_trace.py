"""``taxelkit/EdgeTrace-v0``: follow the edge of a relief plate with the optical array (paper 000).

The task of paper 000, Section IV, as a gymnasium environment:

- **specimen**: one of the named relief shapes (:data:`~taxelkit.world.relief.SHAPE_NAMES`)
  at a random rotation, drawn at every reset; 90 mm across, 200 um step;
- **start**: the array is placed on the edge, found from the centre of the plate
  along a random direction (:func:`~taxelkit.tracing.tracer.find_edge`);
- **observation**: what the robot senses at its position, the displacement
  frames of the two scan strokes of paper 000, Fig. 4 (along x, then y),
  ``(2, T, rows, cols)`` float32 mm (T = 31 positions, 6 x 6 active feelers);
- **action**: a planar move of the array centre, ``(dx, dy)`` in units of
  :data:`MAX_STEP_MM` (6 mm), each component in ``[-1, 1]`` (a normalised
  action space, as RL libraries prefer);
- **reward**: progress along the contour in the tracing direction (raised side
  on the left, i.e. counter-clockwise) as a fraction of the perimeter, so a
  whole loop earns 1 and going backwards is negative;
- **termination**: the loop closes (net progress reaches 1) or the array is
  lost (more than :data:`LOST_DISTANCE_MM` from the edge, where the scans can
  no longer feel it); **truncation** after ``max_steps`` moves.

``info`` holds ``progress`` (net fraction of the loop), ``distance_mm`` to the
edge, ``position_mm``, ``shape`` and ``closed``/``lost``. The policy never sees the
specimen: only the frames (and, if it keeps them, its own commanded moves).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium import Env, spaces
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.motion.probe import ScanConfig, SimulatedProbe
from taxelkit.sensors.presets import OPTICAL_3AXIS
from taxelkit.tracing.tracer import find_edge
from taxelkit.world.relief import DEFAULT_DIAMETER_MM, SHAPE_NAMES, relief_shape

__all__ = ["LOST_DISTANCE_MM", "MAX_STEP_MM", "EdgeTraceEnv", "progress_along"]

#: Largest move per step along x and along y, mm: two point-to-point sections
#: of paper 000 (3 mm each, Section VI.3), room for ``dv + de`` of Eq. 7.
MAX_STEP_MM = 6.0
#: The array is lost when its centre is farther than this from the edge, mm:
#: half the 6 x 6 block at 3 mm pitch (7.5 mm) plus half the 6 mm stroke is
#: the most any feeler reaches; 6 mm keeps the edge under the array's rim.
LOST_DISTANCE_MM = 6.0
#: Bound of the observation, mm: displacements are the 0.1 mm indentation
#: plus at most the 0.2 mm step and noise.
OBSERVATION_BOUND_MM = 1.0


def _arc_table(outline_mm: NDArray[np.float64]) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Counter-clockwise closed outline ``(V + 1, 2)`` and the arc length at each vertex."""
    pts = np.asarray(outline_mm, dtype=np.float64)
    if not np.allclose(pts[0], pts[-1]):
        pts = np.vstack([pts, pts[:1]])
    x, y = pts[:-1, 0], pts[:-1, 1]
    if float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)) < 0:
        pts = pts[::-1].copy()
    seg = np.hypot(*np.diff(pts, axis=0).T)
    return pts, np.concatenate([[0.0], np.cumsum(seg)])


def progress_along(
    outline_mm: NDArray[np.float64], arc_mm: NDArray[np.float64], point_mm: NDArray[np.float64]
) -> float:
    """Arc length of the point of a closed outline nearest to ``point_mm``, mm.

    Parameters
    ----------
    outline_mm : (V + 1, 2) float, mm
        Closed outline (first vertex repeated), counter-clockwise.
    arc_mm : (V + 1,) float, mm
        Cumulative length at each vertex (``arc_mm[0] = 0``).
    point_mm : (2,) float, mm

    Returns
    -------
    float
        In ``[0, arc_mm[-1]]``.

    Examples
    --------
    >>> square = np.array([[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]], float)
    >>> arc = np.array([0.0, 1.0, 2.0, 3.0, 4.0])
    >>> progress_along(square, arc, np.array([1.2, 0.5]))
    1.5
    """
    a, b = outline_mm[:-1], outline_mm[1:]
    d = b - a
    length2 = np.maximum(np.sum(d * d, axis=1), 1e-300)
    t = np.clip(np.sum((point_mm - a) * d, axis=1) / length2, 0.0, 1.0)
    nearest = a + t[:, None] * d
    k = int(np.argmin(np.sum((nearest - point_mm) ** 2, axis=1)))
    return float(arc_mm[k] + t[k] * np.sqrt(length2[k]))


class EdgeTraceEnv(Env[NDArray[np.float32], NDArray[np.float32]]):
    """Trace the edge of a relief plate with the optical three-axis array.

    Parameters
    ----------
    shapes : sequence of str, optional
        Shapes drawn at reset (default every name of :data:`SHAPE_NAMES`).
    max_steps : int, optional
        Moves before the episode is truncated.
    diameter_mm : float, optional
        Circumscribed diameter of the specimens, mm.
    render_mode : None
        No rendering; accepted for the gymnasium API.

    Examples
    --------
    >>> env = EdgeTraceEnv(shapes=("circle",), max_steps=3)
    >>> obs, info = env.reset(seed=1)
    >>> obs.shape, info["shape"]
    ((2, 31, 6, 6), 'circle')
    """

    metadata: dict[str, Any] = {"render_modes": []}  # noqa: RUF012 (gymnasium's API)

    def __init__(
        self,
        *,
        shapes: tuple[str, ...] | list[str] = SHAPE_NAMES,
        max_steps: int = 200,
        diameter_mm: float = DEFAULT_DIAMETER_MM,
        render_mode: str | None = None,
    ) -> None:
        unknown = [s for s in shapes if s not in SHAPE_NAMES]
        if unknown or not shapes:
            raise InputError(f"shapes must be among {', '.join(SHAPE_NAMES)}, got {shapes!r}")
        if int(max_steps) < 1:
            raise InputError(f"max_steps must be >= 1, got {max_steps!r}")
        if render_mode is not None:
            raise InputError(f"EdgeTrace-v0 has no render modes, got {render_mode!r}")
        self.shapes = tuple(shapes)
        self.max_steps = int(max_steps)
        self.diameter_mm = float(diameter_mm)
        self.render_mode = render_mode
        #: What the robot knows of its own scans (for policies that rebuild them).
        self.scan_config = ScanConfig()
        self.sensor = OPTICAL_3AXIS
        rows, cols = self.sensor.array.active_region.slices
        self.element_offsets_mm = self.sensor.array.centres_mm()[rows, cols]
        n = self.scan_config.offsets_mm().size
        shape = (2, n, *self.element_offsets_mm.shape[:2])
        self.observation_space = spaces.Box(
            -OBSERVATION_BOUND_MM, OBSERVATION_BOUND_MM, shape, np.float32
        )
        self.action_space = spaces.Box(-1.0, 1.0, (2,), np.float32)
        self._probe: SimulatedProbe | None = None
        self._position = np.zeros(2)
        self._outline = np.zeros((2, 2))
        self._arc = np.zeros(2)
        self._s = 0.0
        self._progress = 0.0
        self._steps = 0
        self._shape = ""

    def _observe(self) -> NDArray[np.float32]:
        assert self._probe is not None
        frames = [self._probe.scan(self._position, axis).frames_mm for axis in (0, 1)]
        obs = np.clip(np.stack(frames), -OBSERVATION_BOUND_MM, OBSERVATION_BOUND_MM)
        return obs.astype(np.float32)

    def _info(self, distance_mm: float) -> dict[str, Any]:
        return {
            "shape": self._shape,
            "progress": self._progress,
            "distance_mm": distance_mm,
            "position_mm": self._position.copy(),
            "closed": self._progress >= 1.0,
            "lost": distance_mm > LOST_DISTANCE_MM,
        }

    def _distance(self) -> float:
        assert self._probe is not None
        relief: Any = self._probe.relief
        return float(relief.distance_to_edge_mm(self._position[None])[0])

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[NDArray[np.float32], dict[str, Any]]:
        """Draw a specimen and place the array on its edge."""
        super().reset(seed=seed)
        del options
        rng = self.np_random
        self._shape = self.shapes[int(rng.integers(len(self.shapes)))]
        relief = relief_shape(
            self._shape, diameter_mm=self.diameter_mm, rotation_deg=float(rng.uniform(0, 360))
        )
        self._probe = SimulatedProbe(relief, rng=int(rng.integers(2**31)))
        heading = float(rng.uniform(0.0, 2.0 * np.pi))
        self._position = find_edge(
            self._probe, (0.0, 0.0), direction=(np.cos(heading), np.sin(heading))
        )
        self._outline, self._arc = _arc_table(relief.outline_mm())
        self._s = progress_along(self._outline, self._arc, self._position)
        self._progress = 0.0
        self._steps = 0
        return self._observe(), self._info(self._distance())

    def step(
        self, action: NDArray[np.float32]
    ) -> tuple[NDArray[np.float32], float, bool, bool, dict[str, Any]]:
        """Move the array by ``action * MAX_STEP_MM`` mm and scan there."""
        if self._probe is None:
            raise InputError("call reset() before step()")
        move = MAX_STEP_MM * np.clip(np.asarray(action, dtype=np.float64).reshape(2), -1.0, 1.0)
        self._position = self._position + move
        self._steps += 1
        perimeter = float(self._arc[-1])
        s = progress_along(self._outline, self._arc, self._position)
        ds = (s - self._s + perimeter / 2.0) % perimeter - perimeter / 2.0
        self._s = s
        reward = ds / perimeter
        self._progress += reward
        distance = self._distance()
        info = self._info(distance)
        terminated = bool(info["closed"] or info["lost"])
        truncated = not terminated and self._steps >= self.max_steps
        return self._observe(), float(reward), terminated, truncated, info
