"""Sensor presets: the two arrays of the papers.

Numbers marked "paper" come from the papers; numbers marked "assumed" are
choices where the papers are silent, named here so they can be changed.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.sensors.array_geometry import ActiveRegion, TaxelArray
from taxelkit.sensors.noise import NoiseModel
from taxelkit.sensors.skin import SkinModel

__all__ = [
    "BONNEVILLE_16X16",
    "OPTICAL_3AXIS",
    "SENSORS",
    "Sensor",
    "get_sensor",
]


@dataclass(frozen=True)
class Sensor:
    """A simulated tactile sensor: array geometry, skin, noise and read-out.

    Parameters
    ----------
    name : str
        Registry name.
    array : TaxelArray
        Geometry.
    skin : SkinModel
        Lateral coupling of the skin.
    noise : NoiseModel
        Read-out noise and quantisation.
    contact_threshold_mm : float
        Fixed threshold turning displacement into binary contact images, mm.
    max_rate_hz : float
        Highest frame rate the hardware supports, Hz.
    description : str
        One line for listings.
    """

    name: str
    array: TaxelArray
    skin: SkinModel
    noise: NoiseModel
    contact_threshold_mm: float
    max_rate_hz: float
    description: str = ""

    def __post_init__(self) -> None:
        check_positive("contact_threshold_mm", self.contact_threshold_mm)
        check_positive("max_rate_hz", self.max_rate_hz)

    def contact_from_displacement(self, displacement_mm: NDArray[Any]) -> NDArray[np.bool_]:
        """Binary contact images, ``displacement_mm > contact_threshold_mm``.

        Parameters
        ----------
        displacement_mm : (..., rows, cols) float, mm

        Returns
        -------
        (..., rows, cols) bool
        """
        return np.asarray(displacement_mm) > self.contact_threshold_mm


#: Optical three-axis tactile sensor of paper 000 (Section VI.1): 10 x 13
#: elements at 3 mm pitch (paper); the vertical displacement of the central
#: 6 x 6 elements is used (paper). With 13 columns the central block cannot be
#: exactly centred: it starts at column 3 (assumed). Feeler tip 1.0 mm square,
#: skin spread 1.0 mm, noise 1 um rms, read-out resolution 1 um (all assumed:
#: the paper resolves 50 um steps, so the noise must sit well below that).
OPTICAL_3AXIS = Sensor(
    name="optical-3axis",
    array=TaxelArray(
        rows=10, cols=13, pitch_mm=3.0, element_size_mm=1.0, active=ActiveRegion(2, 3, 6, 6)
    ),
    skin=SkinModel(spread_mm=1.0, coupling=1.0),
    noise=NoiseModel(sigma_mm=0.001, resolution_mm=0.001),
    contact_threshold_mm=0.01,
    max_rate_hz=100.0,
    description="Optical three-axis sensor, 10 x 13 at 3 mm, central 6 x 6 used (paper 000)",
)

#: Bonneville Scientific 300-16x16B of paper 001 (Section 2): 16 x 16 taxels
#: over 1.11 in = 28.2 mm, so 1.7625 mm pitch (paper); 6 um deflection
#: resolution (paper); 240 scans/s maximum (paper). Element 1.5 mm square,
#: rubber-sheet spread 0.8 mm, noise 2 um rms and the fixed contact threshold of
#: 30 um = 5 resolution steps (assumed).
BONNEVILLE_16X16 = Sensor(
    name="bonneville-16x16",
    array=TaxelArray(rows=16, cols=16, pitch_mm=28.2 / 16, element_size_mm=1.5),
    skin=SkinModel(spread_mm=0.8, coupling=1.0),
    noise=NoiseModel(sigma_mm=0.002, resolution_mm=0.006),
    contact_threshold_mm=0.03,
    max_rate_hz=240.0,
    description="Bonneville Scientific 300-16x16B, 16 x 16 over 28.2 mm (paper 001)",
)

#: Registry of presets by name.
SENSORS: dict[str, Sensor] = {s.name: s for s in (OPTICAL_3AXIS, BONNEVILLE_16X16)}


def get_sensor(name: str) -> Sensor:
    """Return the preset called ``name``.

    Raises
    ------
    InputError
        Listing the known names.
    """
    try:
        return SENSORS[name]
    except KeyError:
        known = ", ".join(sorted(SENSORS))
        raise InputError(f"unknown sensor {name!r}; known sensors: {known}") from None
