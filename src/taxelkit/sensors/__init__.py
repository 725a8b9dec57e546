"""Taxel arrays, the elastic skin, noise, presets and the press simulator."""

from taxelkit.sensors.array_geometry import ActiveRegion, TaxelArray
from taxelkit.sensors.noise import NoiseModel, apply_noise
from taxelkit.sensors.presets import BONNEVILLE_16X16, OPTICAL_3AXIS, SENSORS, Sensor, get_sensor
from taxelkit.sensors.skin import SkinModel, coupling_margin_taxels, displacement_from_penetration

__all__ = [
    "BONNEVILLE_16X16",
    "OPTICAL_3AXIS",
    "SENSORS",
    "ActiveRegion",
    "NoiseModel",
    "Sensor",
    "SkinModel",
    "TaxelArray",
    "apply_noise",
    "coupling_margin_taxels",
    "displacement_from_penetration",
    "get_sensor",
]
