"""Rolling without slip: pose operations, the Scenario record, and its tactile frames (paper 001).

Paper 001 lets objects roll over the sensor but never slide (Section 3). This
module holds the kinematics as small pure operations on one pose, vectorised
over the samples of a motion, and the :class:`Scenario` that records a whole
motion script; :mod:`~taxelkit.motion.scenarios` writes the randomised scripts.

Frames and conventions
----------------------
The sensor frame has the skin surface at ``z = 0``, ``+z`` up, the array
centred on the origin. A *pose* is a rotation ``R`` (body to sensor) and the
position ``c`` of the body's reference point (its centroid) with the body
*resting* on the plane: its lowest point at ``z = 0``. The simulator then
lowers the body by ``indent_mm`` into the skin
(:func:`~taxelkit.sensors.press.displacement_from_solid`), so only the xy of
``c`` and the rotation reach it; the resting height ``c_z`` is kept as ground
truth and equals ``-solid.lowest_z_mm(R)`` whenever the kinematics is right.

Rolling without slip
--------------------
The material point of the body at the contact has zero velocity, so the
instantaneous rotation axis passes through the contact:

* a sphere (or a cylinder on its side) of radius ``r`` rolled a distance ``s``
  along the horizontal unit ``d`` turns by ``s / r`` about ``e_z x d`` while its
  centre moves by ``s d`` (:func:`~taxelkit.motion.roll_paths.roll_straight`);
* a body tipping about a bottom edge, or tilting about a rim point, turns about
  that fixed horizontal line (:func:`~taxelkit.motion.roll_paths.rotate_about_line`);
* a cone on its side (half-angle ``alpha``) rolls about its apex, which stays
  fixed: the contact generator turns by ``phi`` about the vertical through the
  apex while the cone spins by ``-phi / sin(alpha)`` about its own axis, so the
  angular velocity ``phi' (e_z - a / sin(alpha))`` lies along the contact
  generator. A truncated cone does the same about its virtual apex, off the
  body (:func:`~taxelkit.motion.roll_paths.roll_cone`).

Sliding (:func:`~taxelkit.motion.roll_paths.translate`, and a spin about the vertical with
:func:`~taxelkit.motion.roll_paths.rotate_about_line`) violates the condition on purpose.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit import _fixed_order as fo
from taxelkit._arrays import readonly_copy
from taxelkit.errors import InputError, check_finite_array, check_ndim, check_positive
from taxelkit.frames import TactileFrames
from taxelkit.motion.contact_truth import (
    CONTACT_SPREAD_MM,
    CONTACT_TIE_MM,
    contact_types,
    slip_from_poses,
)
from taxelkit.sensors.noise import RngLike
from taxelkit.sensors.presets import Sensor
from taxelkit.sensors.press import displacement_from_solid
from taxelkit.world.base import Solid
from taxelkit.world.pose import check_rotations

__all__ = [
    "DEFAULT_DEPTH_MM",
    "DEFAULT_RATE_HZ",
    "E_Z",
    "PHASES",
    "Pose",
    "Scenario",
    "frames_from_scenario",
]

#: Frame rate of the simulated sensor, Hz (assumed). Paper 001 developed at
#: 1 Hz and expects "10 to 50 times faster" in practice (Section 3, Level 0);
#: 20 Hz sits in that range, well under the Bonneville's 240 scans/s, and with
#: the scripts' speeds every contact state lasts at least 8 frames (the
#: recogniser accepts a new class after k = 3 identical frames).
DEFAULT_RATE_HZ = 20.0

#: Depth of the body's lowest point below the skin while in contact, mm
#: (assumed; paper 001 gives none): 10x the 30 um contact threshold of
#: :data:`~taxelkit.sensors.presets.BONNEVILLE_16X16` and 50x its 6 um
#: resolution, small next to the 1.76 mm pitch. A sphere of radius 6 mm then
#: touches over a disc of radius ``sqrt(2 R d) = 1.9 mm``.
DEFAULT_DEPTH_MM = 0.3

#: Unit vertical of the sensor frame.
E_Z = np.array([0.0, 0.0, 1.0])

#: Phase labels of the frames (ground truth for tests and reports):
#: ``lifted`` no contact; ``placing``/``lifting`` the indentation ramps;
#: ``face``, ``edge``, ``vertex`` held still on a flat face (a polyhedron's, or
#: the end of a round body), an edge, a vertex; ``side`` a round body held
#: still on its curved surface (a sphere anywhere, a cylinder or cone lying on
#: its side); ``rim`` held tilted on a rim point; ``apex`` a cone held on its
#: apex; ``tipping`` turning about a fixed bottom edge, rim point, vertex or
#: apex; ``rolling`` rolling without slip; ``sliding`` dragged without
#: turning; ``spinning`` turned in place about the vertical. A motion's last
#: frame carries the label of the state it arrives in.
PHASES: tuple[str, ...] = (
    "lifted",
    "placing",
    "lifting",
    "face",
    "edge",
    "vertex",
    "side",
    "rim",
    "apex",
    "tipping",
    "rolling",
    "sliding",
    "spinning",
)


@dataclass(frozen=True, eq=False)
class Pose:
    """One pose of a rigid body resting on the sensor plane.

    Parameters
    ----------
    rotation : (3, 3) float
        Body-to-sensor rotation.
    centroid_mm : (3,) float, mm
        Reference point (centroid) in the sensor frame, body resting on ``z = 0``.
    """

    rotation: NDArray[np.float64]
    centroid_mm: NDArray[np.float64]

    def __post_init__(self) -> None:
        rot = check_rotations(self.rotation)[0].copy()
        cen = np.array(self.centroid_mm, dtype=np.float64)
        if cen.shape != (3,):
            raise InputError(f"centroid_mm must have shape (3,), got {cen.shape}")
        check_finite_array("centroid_mm", cen)
        rot.setflags(write=False)
        cen.setflags(write=False)
        object.__setattr__(self, "rotation", rot)
        object.__setattr__(self, "centroid_mm", cen)

    def world_mm(self, body_mm: ArrayLike) -> NDArray[np.float64]:
        """Body-frame points ``(..., 3)`` mm in the sensor frame, ``c + R p``."""
        p = np.asarray(body_mm, dtype=np.float64)
        return self.centroid_mm + fo.matvec(self.rotation, p)


@dataclass(frozen=True, eq=False)
class Scenario:
    """A solid moved over the sensor: poses per frame plus ground truth.

    Parameters
    ----------
    name : str
        Registry name of the script (``"cube"``, ``"sliding"``,
        ``"cylinder-fig3"``, ...).
    object_name : str
        Name of the solid (ground truth).
    solid : Solid
        The body.
    rotations : (T, 3, 3) float
        Body-to-sensor rotation per frame.
    positions_mm : (T, 2) float, mm
        xy of the centroid over the array (array centre = 0).
    rest_height_mm : (T,) float, mm
        Height of the centroid above the skin with the body resting on it
        (indentation 0), from the kinematics (ground truth).
    indent_mm : (T,) float, mm
        Depth of the lowest point below the skin; <= 0: lifted off.
    t_s : (T,) float, s
        Frame times, strictly increasing.
    phase : tuple of str, length T
        Phase label per frame, from :data:`PHASES` (ground truth).
    slides : bool
        True if the script slides (ground truth: a correct recogniser must not
        identify the object).
    contact_tie_mm, contact_spread_mm : float
        Tolerances of the ground-truth contact type (:attr:`contact`), mm:
        :func:`~taxelkit.motion.contact_truth.contact_types`' defaults for
        the exact poses of the kinematic scripts; a physics engine's poses,
        level only to micrometres on its soft contacts, carry wider ones
        (:data:`~taxelkit.motion.engines._sampling.PHYSICS_TIE_MM`), or a
        face that rests a few micrometres out of level reads as a line or a
        point.

    Notes
    -----
    ``phase``, ``slides``, ``object_name``, ``rest_height_mm`` and the derived
    :attr:`contact` are ground truth for tests and reports; recognisers see
    only the frames of :func:`frames_from_scenario`.
    """

    name: str
    object_name: str
    solid: Solid
    rotations: NDArray[np.float64]
    positions_mm: NDArray[np.float64]
    rest_height_mm: NDArray[np.float64]
    indent_mm: NDArray[np.float64]
    t_s: NDArray[np.float64]
    phase: tuple[str, ...]
    slides: bool = False
    contact_tie_mm: float = CONTACT_TIE_MM
    contact_spread_mm: float = CONTACT_SPREAD_MM

    def __post_init__(self) -> None:
        for tol in ("contact_tie_mm", "contact_spread_mm"):
            object.__setattr__(self, tol, check_positive(tol, getattr(self, tol)))
        rot = check_rotations(self.rotations)
        n = rot.shape[0]
        pos = np.asarray(self.positions_mm, dtype=np.float64)
        if pos.shape != (n, 2):
            raise InputError(f"positions_mm must have shape ({n}, 2), got {pos.shape}")
        arrays: dict[str, NDArray[Any]] = {"rotations": rot, "positions_mm": pos}
        for field in ("rest_height_mm", "indent_mm", "t_s"):
            v = check_ndim(field, getattr(self, field), 1, "(T,)").astype(np.float64)
            if v.shape != (n,):
                raise InputError(f"{field} must have shape ({n},), got {v.shape}")
            arrays[field] = v
        for field, v in arrays.items():
            check_finite_array(field, v)
            object.__setattr__(self, field, readonly_copy(v))
        if n > 1 and not np.all(np.diff(arrays["t_s"]) > 0):
            raise InputError("t_s must be strictly increasing")
        phase = tuple(str(p) for p in self.phase)
        if len(phase) != n:
            raise InputError(f"phase must have {n} labels (one per frame), got {len(phase)}")
        unknown = sorted(set(phase) - set(PHASES))
        if unknown:
            raise InputError(f"unknown phase label(s) {unknown}; known: {', '.join(PHASES)}")
        object.__setattr__(self, "phase", phase)
        object.__setattr__(self, "slides", bool(self.slides))

    @property
    def n_frames(self) -> int:
        """Number of frames ``T``."""
        return int(self.rotations.shape[0])

    @property
    def rate_hz(self) -> float | None:
        """Mean frame rate, Hz; ``None`` for fewer than two frames."""
        if self.n_frames < 2:
            return None
        return (self.n_frames - 1) / float(self.t_s[-1] - self.t_s[0])

    @property
    def in_contact(self) -> NDArray[np.bool_]:
        """(T,) bool: the body is pressed into the skin (``indent_mm > 0``)."""
        return np.asarray(self.indent_mm > 0.0)

    @property
    def centroids_mm(self) -> NDArray[np.float64]:
        """(T, 3) float, mm: the centroid with the indentation applied (``z = rest - indent``)."""
        z = self.rest_height_mm - self.indent_mm
        return np.column_stack([self.positions_mm, z])

    @functools.cached_property
    def contact(self) -> tuple[str, ...]:
        """Geometric contact type per frame: ``"none"`` when lifted, else point/line/area.

        See :func:`~taxelkit.motion.contact_truth.contact_types` (ground truth).
        """
        kinds = contact_types(
            self.solid,
            self.rotations,
            tie_mm=self.contact_tie_mm,
            spread_mm=self.contact_spread_mm,
        )
        return tuple(k if c else "none" for k, c in zip(kinds, self.in_contact, strict=True))

    def slip_mm(self, *, full: bool = False) -> NDArray[np.float64]:
        """Slip of the material contact points per step (ground truth).

        Parameters
        ----------
        full : bool
            3-D displacement instead of the horizontal one.

        Returns
        -------
        (T - 1,) float, mm
            See :func:`~taxelkit.motion.contact_truth.slip_from_poses`; NaN
            where frame ``t`` or ``t + 1`` is lifted.
        """
        slip = slip_from_poses(self.solid, self.rotations, self.centroids_mm, full=full)
        both = self.in_contact[:-1] & self.in_contact[1:]
        out: NDArray[np.float64] = np.where(both, slip, np.nan)
        return out

    def phase_runs(self) -> tuple[tuple[str, int, int], ...]:
        """Runs of equal phase labels as ``(label, start, stop)`` (stop exclusive)."""
        runs: list[tuple[str, int, int]] = []
        start = 0
        for t in range(1, self.n_frames + 1):
            if t == self.n_frames or self.phase[t] != self.phase[start]:
                runs.append((self.phase[start], start, t))
                start = t
        return tuple(runs)

    def equals(self, other: object) -> bool:
        """True if every field is identical (the solid compared with ``==``)."""
        if not isinstance(other, Scenario):
            return False
        return (
            self.name == other.name
            and self.object_name == other.object_name
            and self.solid == other.solid
            and self.phase == other.phase
            and self.slides == other.slides
            and all(
                np.array_equal(getattr(self, f), getattr(other, f))
                for f in ("rotations", "positions_mm", "rest_height_mm", "indent_mm", "t_s")
            )
        )


def frames_from_scenario(
    sensor: Sensor,
    scenario: Scenario,
    *,
    rng: RngLike = None,
    add_noise: bool = True,
    oversample: int = 1,
) -> TactileFrames:
    """Simulate the sensor's frames for a scenario, all poses in one batch.

    Parameters
    ----------
    sensor : Sensor
        For example :data:`~taxelkit.sensors.presets.BONNEVILLE_16X16`.
    scenario : Scenario
    rng : int, Generator or None
        Seed for the sensor noise.
    add_noise : bool
        Apply the sensor's noise model.
    oversample : int
        Samples per taxel along each axis for the area average (1: centres).

    Returns
    -------
    TactileFrames
        ``(T, rows, cols)`` displacement in mm (positive into the sensor), the
        scenario's ``t_s``, the sensor's pitch and name.

    Examples
    --------
    >>> from taxelkit.motion.scenarios import make_scenario
    >>> from taxelkit.sensors.presets import BONNEVILLE_16X16
    >>> sc = make_scenario("sphere", rng=1)
    >>> rec = frames_from_scenario(BONNEVILLE_16X16, sc, rng=1)
    >>> rec.shape[1:], rec.units
    ((16, 16), 'mm')
    """
    disp = displacement_from_solid(
        sensor,
        scenario.solid,
        scenario.rotations,
        scenario.positions_mm,
        indent_mm=scenario.indent_mm,
        oversample=oversample,
        add_noise=add_noise,
        rng=rng,
    )
    return TactileFrames(
        disp, t_s=scenario.t_s, pitch_mm=sensor.array.pitch_mm, units="mm", sensor=sensor.name
    )
