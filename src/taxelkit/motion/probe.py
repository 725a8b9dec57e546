"""The manipulator carrying a tactile array: point-to-point moves and scans (paper 000).

A tracer talks to a :class:`TactileProbe`: it commands moves and scans and
gets back frames. :class:`SimulatedProbe` implements it on the simulator (it
alone knows the specimen); a driver for a real robot implements the same two
methods. Recognition code therefore never sees the world's geometry.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.sensors.noise import RngLike
from taxelkit.sensors.presets import OPTICAL_3AXIS, Sensor
from taxelkit.sensors.press import displacement_from_relief
from taxelkit.world.base import Relief

__all__ = [
    "DEFAULT_INDENT_MM",
    "MotionNoise",
    "Scan",
    "ScanConfig",
    "SimulatedProbe",
    "TactileProbe",
]

#: Depth the skin is pressed below the specimen's base plane while tracing, mm
#: (assumed; the paper gives none). Deep enough that the 50-200 um steps are
#: felt by every element, shallow next to the 3 mm feeler pitch.
DEFAULT_INDENT_MM = 0.1


@dataclass(frozen=True)
class ScanConfig:
    """One scan stroke at a point (paper 000, Fig. 4).

    Parameters
    ----------
    length_mm : float
        Stroke length, centred on the commanded point, mm. Default 6 mm = two
        pitches: every element passes over any edge within 3 mm of it.
    speed_mm_s : float
        Scanning velocity ``V`` of Eq. 8, mm/s.
    dt_s : float
        Frame interval during the scan, s.
    indent_mm : float
        Indentation below the specimen's base plane, mm.
    touch_down : bool
        False (the default): the manipulator holds the height of the base
        plane ``z = 0``, so a tilted plate lifts off the skin where it falls
        away by more than ``indent_mm``. True: before each stroke it lowers
        the array at the commanded point until every active element touches
        (a guarded move on the elements' contact signals) and presses
        ``indent_mm`` further, i.e. ``indent_mm`` below the lowest surface
        point under the element centres; the height is held during the stroke.
    """

    length_mm: float = 6.0
    speed_mm_s: float = 10.0
    dt_s: float = 0.02
    indent_mm: float = DEFAULT_INDENT_MM
    touch_down: bool = False

    def __post_init__(self) -> None:
        check_positive("length_mm", self.length_mm)
        check_positive("speed_mm_s", self.speed_mm_s)
        check_positive("dt_s", self.dt_s)
        check_positive("indent_mm", self.indent_mm)

    @property
    def step_mm(self) -> float:
        """Distance travelled between frames, ``V dt``, mm."""
        return self.speed_mm_s * self.dt_s

    def offsets_mm(self) -> NDArray[np.float64]:
        """Commanded positions along the stroke, relative to its centre, ``(T,)`` mm."""
        n = max(2, round(self.length_mm / self.step_mm) + 1)
        out = np.asarray((np.arange(n) - (n - 1) / 2.0) * self.step_mm, dtype=np.float64)
        return out


@dataclass(frozen=True)
class MotionNoise:
    """Imperfections of the manipulator (documented, seeded).

    Parameters
    ----------
    positioning_sigma_mm : float
        Standard deviation of the error of each point-to-point move, per axis, mm.
        The error persists during the scans at that point.
    vibration_mm : float
        Standard deviation of a random jitter of the sensor, per frame and axis,
        during scans, mm.
    """

    positioning_sigma_mm: float = 0.0
    vibration_mm: float = 0.0

    def __post_init__(self) -> None:
        check_positive("positioning_sigma_mm", self.positioning_sigma_mm, allow_zero=True)
        check_positive("vibration_mm", self.vibration_mm, allow_zero=True)


@dataclass(frozen=True, eq=False)
class Scan:
    """The frames of one scan stroke, as the robot knows them.

    Attributes
    ----------
    centre_mm : (2,) float, mm
        Commanded centre of the stroke.
    axis : int
        0 for a stroke along +x, 1 along +y.
    offsets_mm : (T,) float, mm
        Commanded positions along the axis, relative to the centre.
    frames_mm : (T, rows, cols) float, mm
        Displacement of the active elements.
    dt_s : float
        Frame interval, s.
    speed_mm_s : float
        Scanning velocity, mm/s.
    """

    centre_mm: NDArray[np.float64]
    axis: int
    offsets_mm: NDArray[np.float64]
    frames_mm: NDArray[np.float64]
    dt_s: float
    speed_mm_s: float


@runtime_checkable
class TactileProbe(Protocol):
    """What a tracer may ask of the robot: scan at a point, and the array layout."""

    @property
    def element_offsets_mm(self) -> NDArray[np.float64]:
        """Centres of the active elements relative to the array centre, ``(rows, cols, 2)`` mm."""
        ...

    def scan(self, centre_mm: ArrayLike, axis: int) -> Scan:
        """Move to ``centre_mm`` and scan one stroke along ``axis`` (0 = x, 1 = y)."""
        ...


class SimulatedProbe:
    """A simulated manipulator pressing a sensor on a relief specimen.

    Parameters
    ----------
    relief : Relief
        The specimen; only this class sees it.
    sensor : Sensor
        Default: the optical three-axis sensor of paper 000; its active block is used.
    scan : ScanConfig
    noise : MotionNoise
    oversample : int
        Samples per element along each axis for the area average.
    rng : int, Generator or None
        Seed for sensor noise and motion noise.
    """

    def __init__(
        self,
        relief: Relief,
        *,
        sensor: Sensor = OPTICAL_3AXIS,
        scan: ScanConfig | None = None,
        noise: MotionNoise | None = None,
        oversample: int = 3,
        rng: RngLike = None,
    ) -> None:
        self.relief = relief
        self.sensor = sensor
        self.config = ScanConfig() if scan is None else scan
        self.noise = MotionNoise() if noise is None else noise
        self.oversample = int(oversample)
        self._rng = np.random.default_rng(rng)
        self.frames_simulated = 0
        region = sensor.array.active_region
        rows, cols = region.slices
        self._offsets = sensor.array.centres_mm()[rows, cols]

    @property
    def element_offsets_mm(self) -> NDArray[np.float64]:
        """Centres of the active elements relative to the array centre, ``(rows, cols, 2)`` mm."""
        return self._offsets

    def scan(self, centre_mm: ArrayLike, axis: int) -> Scan:
        """Scan one stroke along ``axis`` centred on the commanded ``centre_mm``.

        Returns
        -------
        Scan
            Commanded positions and the simulated frames of the active block.
        """
        if axis not in (0, 1):
            raise InputError(f"axis must be 0 (x) or 1 (y), got {axis!r}")
        c = np.asarray(centre_mm, dtype=np.float64)
        if c.shape != (2,) or not np.all(np.isfinite(c)):
            raise InputError(f"centre_mm must be two finite numbers, got {centre_mm!r}")
        cfg = self.config
        offsets = cfg.offsets_mm()
        actual = c + self._rng.normal(0.0, 1.0, 2) * self.noise.positioning_sigma_mm
        pos: Any = np.repeat(actual[None], offsets.size, axis=0)
        pos[:, axis] += offsets
        if self.noise.vibration_mm > 0:
            pos += self._rng.normal(0.0, self.noise.vibration_mm, pos.shape)
        indent = cfg.indent_mm
        if cfg.touch_down:
            under = actual + self._offsets.reshape(-1, 2)
            indent -= float(np.min(self.relief.height_mm(under[:, 0], under[:, 1])))
        frames: Any = displacement_from_relief(
            self.sensor,
            self.relief,
            pos,
            indent_mm=indent,
            oversample=self.oversample,
            active_only=True,
            rng=self._rng,
            dtype=np.float64,
        )
        self.frames_simulated += offsets.size
        return Scan(c, axis, offsets, frames, cfg.dt_s, cfg.speed_mm_s)
