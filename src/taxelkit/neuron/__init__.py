"""The mechanoreceptive neuron model of paper 000 (Eq. 1-6, 9)."""

from taxelkit.neuron.mechanoreceptor import (
    NeuronParams,
    direction_output,
    membrane_potential,
    pulse_density,
    receptor_output,
    spatial_summation,
    temporal_summation,
)
from taxelkit.neuron.quantisers import ramp, ternary
from taxelkit.neuron.streaming import StreamingNeuron

__all__ = [
    "NeuronParams",
    "StreamingNeuron",
    "direction_output",
    "membrane_potential",
    "pulse_density",
    "ramp",
    "receptor_output",
    "spatial_summation",
    "temporal_summation",
    "ternary",
]
