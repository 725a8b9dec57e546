"""The simulator demo: both papers' sensors touching their worlds.

Returns data only; :mod:`taxelkit.plotting.demo` draws it and the CLI writes it.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit.frames import TactileFrames
from taxelkit.sensors.noise import RngLike
from taxelkit.sensors.presets import BONNEVILLE_16X16, OPTICAL_3AXIS
from taxelkit.sensors.press import displacement_from_relief, displacement_from_solid
from taxelkit.world.pose import matrix_from_euler_xyz_deg
from taxelkit.world.relief import relief_shape
from taxelkit.world.solids import SOLID_NAMES, make_solid

__all__ = [
    "DEMO_POSES_DEG",
    "ReliefSlide",
    "SolidPresses",
    "relief_slide",
    "solid_presses",
]

#: Three poses per solid (extrinsic x-y-z Euler angles, deg) for the demo:
#: resting on a face or end, on an edge or side, and tilted onto a vertex or rim.
DEMO_POSES_DEG: dict[str, tuple[tuple[float, float, float], ...]] = {
    "cube": ((0, 0, 20), (45, 0, 20), (54.7356, 45, 0)),
    "sphere": ((0, 0, 0), (0, 0, 0), (0, 0, 0)),
    "cone": ((0, 0, 0), (90 + 23.2, 0, 30), (180, 0, 0)),
    "truncated-cone": ((0, 0, 0), (90 + 18.4, 0, -30), (180, 0, 0)),
    "cylinder": ((0, 0, 0), (90, 0, 30), (30, 0, 0)),
    "tetrahedron": ((0, 0, 20), (0, -54.7356, 20), (180, 0, 0)),
}
DEMO_POSE_LABELS = ("face / end", "edge / side", "vertex / rim")


@dataclass(frozen=True, eq=False)
class ReliefSlide:
    """The optical sensor of paper 000 sliding across a relief edge.

    Attributes
    ----------
    shape : str
        Relief shape name.
    outline_mm : (V, 2) float, mm
        Closed outline of the relief.
    positions_mm : (T, 2) float, mm
        Array centre for each frame.
    recording : TactileFrames
        The central 6 x 6 displacement frames, mm.
    footprint_mm : (2,) float, mm
        Width and height of the active block.
    """

    shape: str
    outline_mm: NDArray[np.float64]
    positions_mm: NDArray[np.float64]
    recording: TactileFrames
    footprint_mm: tuple[float, float]


@dataclass(frozen=True, eq=False)
class SolidPresses:
    """Each solid of paper 001 pressed onto the Bonneville array in three poses.

    Attributes
    ----------
    names : tuple of str
        Solid names, one per row.
    pose_labels : tuple of str
        One per column.
    displacement_mm : (S, K, 16, 16) float, mm
    contact : (S, K, 16, 16) bool
    recording : TactileFrames
        All presses as one recording of contact images (row-major order).
    """

    names: tuple[str, ...]
    pose_labels: tuple[str, ...]
    displacement_mm: NDArray[np.float64]
    contact: NDArray[np.bool_]
    recording: TactileFrames


def relief_slide(
    *, shape: str = "star", n_frames: int = 24, indent_mm: float = 0.1, rng: RngLike = None
) -> ReliefSlide:
    """Slide the optical three-axis sensor across the edge of a 200 um relief.

    Parameters
    ----------
    shape : str
        Relief shape (90 mm circumscribed diameter, 200 um step, paper 000 Sect. VI.3).
    n_frames : int
        Frames along the slide.
    indent_mm : float
        Indentation of the skin below the plate's base plane, mm.
    rng : int, Generator or None
        Seed for the sensor noise.
    """
    sensor = OPTICAL_3AXIS
    relief = relief_shape(shape, diameter_mm=90.0, step_height_um=200.0)
    start, stop = np.array([5.0, 2.0]), np.array([40.0, 2.0])
    positions = start + np.linspace(0.0, 1.0, n_frames)[:, None] * (stop - start)
    disp = displacement_from_relief(sensor, relief, positions, indent_mm=indent_mm, rng=rng)
    block = sensor.array.active_region
    rows, cols = block.slices
    rate = 10.0
    rec = TactileFrames(
        disp[:, rows, cols], np.arange(n_frames) / rate, sensor.array.pitch_mm, "mm", sensor.name
    )
    pitch = sensor.array.pitch_mm
    return ReliefSlide(
        shape=shape,
        outline_mm=np.asarray(relief.outline_mm()),
        positions_mm=positions,
        recording=rec,
        footprint_mm=(block.cols * pitch, block.rows * pitch),
    )


def solid_presses(
    *,
    indent_mm: float = 0.3,
    rng: RngLike = None,
    progress: Callable[[str], None] | None = None,
) -> SolidPresses:
    """Press each solid onto the Bonneville array in the :data:`DEMO_POSES_DEG` poses.

    Parameters
    ----------
    indent_mm : float
        Depth of the lowest point below the skin, mm.
    rng : int, Generator or None
        Seed for the sensor noise.
    progress : callable, optional
        Called with each solid's name as it is simulated.
    """
    sensor = BONNEVILLE_16X16
    gen = np.random.default_rng(rng)
    disp = []
    for name in SOLID_NAMES:
        if progress is not None:
            progress(name)
        rot = matrix_from_euler_xyz_deg(np.array(DEMO_POSES_DEG[name], dtype=float))
        pos = np.zeros((rot.shape[0], 2))
        disp.append(
            displacement_from_solid(
                sensor, make_solid(name), rot, pos, indent_mm=indent_mm, rng=gen
            )
        )
    d = np.stack(disp).astype(np.float64)
    contact = sensor.contact_from_displacement(d)
    flat = contact.reshape(-1, *sensor.array.shape)
    rec = TactileFrames(
        flat, np.arange(flat.shape[0], dtype=float), sensor.array.pitch_mm, sensor=sensor.name
    )
    return SolidPresses(tuple(SOLID_NAMES), DEMO_POSE_LABELS, d, contact, rec)
