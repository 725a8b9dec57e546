"""What the recogniser's Levels 1-2 make of a flat face pressed on the array.

A face's contact class depends on the sensor: a 5.5 x 13 mm rectangle is an
area to a fine array and a line to the Bonneville 16 x 16 (3 x 7 taxels,
elongation 2.4); and the skin rounds a face's corners, so a triangle reads
less triangular than its outline. So the body is pressed face down on the
simulated sensor (:func:`~taxelkit.sensors.press.displacement_from_solid`,
noise included) at :data:`N_PLACEMENTS` seeded positions, yaws and depths,
and each image goes through the same Level 1 (:func:`~taxelkit.smart.moments.image_stats`),
Level 2 (hand-set network and :data:`~taxelkit.smart.levels12.DEFAULT_LIMITS`)
and face-shape rules (:func:`~taxelkit.smart.face_shapes.face_masks`) as a
recording. The union over the placements is what the face can produce.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit.motion.rolling import DEFAULT_DEPTH_MM, E_Z
from taxelkit.sensors.presets import BONNEVILLE_16X16, Sensor
from taxelkit.sensors.press import displacement_from_solid
from taxelkit.smart.contact_classes import (
    DEFAULT_CONFIDENCE,
    HAND_SET,
    ContactClass,
    classify_contacts,
)
from taxelkit.smart.contact_limits import apply_limits
from taxelkit.smart.face_shapes import face_limits, face_masks, triangularity
from taxelkit.smart.levels12 import DEFAULT_LIMITS, half_length
from taxelkit.smart.moments import image_stats
from taxelkit.smart.tacteme_config import TactemeConfig
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.world.mesh_features import FlatFace
from taxelkit.world.mesh_solid import MeshSolid
from taxelkit.world.pose import matrix_from_axis_angle

__all__ = ["N_PLACEMENTS", "FaceReading", "face_images", "read_face", "rest_rotation"]

#: Placements (position within a taxel, yaw) each face is drawn at.
N_PLACEMENTS = 48


def rest_rotation(normal: NDArray[np.float64]) -> NDArray[np.float64]:
    """A rotation that turns the body-frame ``normal`` straight down."""
    n = np.asarray(normal, dtype=np.float64) / np.linalg.norm(normal)
    axis = np.cross(n, -E_Z)
    s, c = float(np.linalg.norm(axis)), float(-n[2])
    if s < 1e-9:
        return np.eye(3) if c > 0 else matrix_from_axis_angle([1.0, 0.0, 0.0], np.pi)
    out: NDArray[np.float64] = matrix_from_axis_angle(axis / s, math.atan2(s, c))
    return out


@dataclass(frozen=True)
class FaceReading:
    """What a face reads as.

    Attributes
    ----------
    classes : frozenset of ContactClass
        Level 2 classes over the placements.
    shapes : frozenset of Tacteme
        Face-shape tactemes of the placements read as an area.
    """

    classes: frozenset[ContactClass]
    shapes: frozenset[Tacteme]

    @property
    def area(self) -> bool:
        """Read as an area contact at some placement."""
        return ContactClass.AREA in self.classes

    @property
    def line(self) -> bool:
        """Read as a line contact at some placement."""
        return ContactClass.LINE in self.classes


def face_images(
    solid: MeshSolid,
    face: FlatFace,
    *,
    sensor: Sensor = BONNEVILLE_16X16,
    depth_mm: float = DEFAULT_DEPTH_MM,
    rng: int = 0,
) -> NDArray[np.bool_]:
    """The face pressed on the simulated array at :data:`N_PLACEMENTS` placements.

    Returns
    -------
    (N, rows, cols) bool
        Contact images (the sensor's threshold), the face centred on the
        array within half a pitch, at a random yaw, pressed ``depth_mm`` x
        ``1 +- 0.3``, with the sensor's noise.
    """
    gen = np.random.default_rng(rng)
    down = rest_rotation(face.normal)
    yaws = gen.uniform(0.0, 2.0 * np.pi, N_PLACEMENTS)
    rots = matrix_from_axis_angle(E_Z, yaws) @ down
    centre = np.einsum("nij,j->ni", rots, face.centroid_mm)[:, :2]
    pos = gen.uniform(-0.5, 0.5, (N_PLACEMENTS, 2)) * sensor.array.pitch_mm - centre
    depth = depth_mm * gen.uniform(0.7, 1.3, N_PLACEMENTS)
    disp = displacement_from_solid(
        sensor, solid, rots, pos, indent_mm=depth, add_noise=True, rng=gen
    )
    out: NDArray[np.bool_] = np.asarray(disp > sensor.contact_threshold_mm)
    return out


def read_face(
    solid: MeshSolid,
    face: FlatFace,
    *,
    config: TactemeConfig,
    sensor: Sensor = BONNEVILLE_16X16,
    rng: int = 0,
) -> FaceReading:
    """Levels 1-2 and the face-shape rules on the face's images (see the module docstring)."""
    pitch_mm = sensor.array.pitch_mm
    images = face_images(solid, face, sensor=sensor, rng=rng)
    stats = image_stats(images, pitch_mm=pitch_mm)
    classes = classify_contacts(stats, HAND_SET, confidence=DEFAULT_CONFIDENCE)
    half = half_length(stats)
    classes = apply_limits(
        classes,
        stats.n_taxels,
        2.0 * half,
        stats.elongation,
        DEFAULT_LIMITS,
        area_mm2=stats.area_mm2,
    )
    area = classes == ContactClass.AREA
    tau = triangularity(stats.area_mm2, stats.elongation, half)
    shapes = {
        tac
        for tac, mask in face_masks(
            stats.area_mm2, stats.elongation, tau, area, **face_limits(config)
        )
        if np.any(mask)
    }
    return FaceReading(
        frozenset(ContactClass(int(c)) for c in np.unique(classes)), frozenset(shapes)
    )
