"""Imperfections of real taxel arrays: dead, stuck and flickering taxels, threshold spread,
row/column crosstalk, offset drift. Composable and seeded.

A real Bonneville-type array is not the ideal sensor of the simulator: some
taxels never report contact (dead), some always do (stuck), some flip at
random (flicker), thresholds differ from taxel to taxel, rows or columns of
resistive arrays leak into their neighbours (ghosting), and analog outputs
drift. Each imperfection here is a frozen dataclass with a seeded
``apply``; :class:`FaultModel` chains them. The faults act on the sensor's
output, so they work on analog frames (mm, kPa, counts: compared with
``threshold``) and, where that makes sense, on bool contact images.

============================ ============================================================
model                        what the frames show
============================ ============================================================
:class:`DeadTaxels`          ``count`` random taxels read 0 (False) in every frame
:class:`StuckTaxels`         ``count`` random taxels read ``level x threshold`` (True)
                             in every frame
:class:`Flicker`             every taxel flips across the threshold with probability
                             ``rate`` in each frame, independently
:class:`ThresholdSpread`     per-taxel gain ``1 / (1 + sigma z)``, ``z`` standard normal
                             (equivalently a threshold spread by ``sigma``); analog only
:class:`Crosstalk`           ``rows`` random rows (and ``cols`` columns) also read
                             ``coupling`` times their next row (column)
:class:`OffsetDrift`         per-taxel offset ``N(0, offset)`` plus a common drift
                             ``drift_per_s x t``; analog only
:class:`ContactLoss`         every taxel reads 0 for ``duration_s`` once, at a random
                             moment of contact (a bounce, a lost read-out)
============================ ============================================================

The flip of :class:`Flicker` on analog frames sets a taxel to 0 or to
``FLICKER_ON_LEVEL x threshold``. All random choices come from the generator
handed to :meth:`FaultModel.apply`: the same seed gives the same frames.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.frames import TactileFrames
from taxelkit.sensors.fault_kinds import (  # the models, re-exported here
    FLICKER_ON_LEVEL,
    ContactLoss,
    Crosstalk,
    DeadTaxels,
    Fault,
    Flicker,
    OffsetDrift,
    StuckTaxels,
    ThresholdSpread,
)
from taxelkit.sensors.noise import RngLike

__all__ = [
    "FAULT_PRESETS",
    "FLICKER_ON_LEVEL",
    "ContactLoss",
    "Crosstalk",
    "DeadTaxels",
    "Fault",
    "FaultModel",
    "Flicker",
    "OffsetDrift",
    "StuckTaxels",
    "ThresholdSpread",
    "fault_model",
]


@dataclass(frozen=True)
class FaultModel:
    """Imperfections applied in order (put dead and stuck taxels last so that they win).

    Parameters
    ----------
    faults : sequence of Fault
        Applied left to right.
    name : str
        A label for reports.

    Examples
    --------
    >>> import numpy as np
    >>> from taxelkit.frames import TactileFrames
    >>> rec = TactileFrames(np.zeros((5, 16, 16)), pitch_mm=1.76)
    >>> bad = FaultModel((StuckTaxels(1),)).apply(rec, threshold=0.03, rng=0)
    >>> int((bad.frames > 0.03).sum(axis=(1, 2))[0])
    1
    """

    faults: tuple[Fault, ...] = field(default_factory=tuple)
    name: str = "custom"

    def __post_init__(self) -> None:
        object.__setattr__(self, "faults", tuple(self.faults))
        for f in self.faults:
            if not callable(getattr(f, "apply", None)):
                raise InputError(f"faults must have an apply method, got {type(f).__name__}")

    def apply_frames(
        self,
        frames: NDArray[Any],
        t_s: NDArray[np.float64],
        *,
        threshold: float,
        rng: RngLike = None,
    ) -> NDArray[Any]:
        """The frames ``(T, rows, cols)`` as the imperfect sensor reports them.

        Parameters
        ----------
        frames : (T, rows, cols) bool or float
        t_s : (T,) float, s
        threshold : float
            Contact threshold of analog frames, in their units (> 0).
        rng : int, Generator or None
            Seed: the same seed gives the same frames.
        """
        arr = np.asarray(frames)
        if arr.ndim != 3:
            raise InputError(f"frames must have shape (T, rows, cols), got {arr.shape}")
        thr = check_positive("threshold", threshold)
        gen = np.random.default_rng(rng)
        out = arr.copy()
        ts = np.asarray(t_s, dtype=np.float64)
        for f in self.faults:
            out = f.apply(out, ts, threshold=thr, rng=gen)
        return out

    def apply(
        self, recording: TactileFrames, *, threshold: float, rng: RngLike = None
    ) -> TactileFrames:
        """A recording as the imperfect sensor reports it (see :meth:`apply_frames`)."""
        frames = self.apply_frames(recording.frames, recording.t_s, threshold=threshold, rng=rng)
        return TactileFrames(
            frames,
            t_s=recording.t_s,
            pitch_mm=recording.pitch_mm,
            units=recording.units,
            sensor=recording.sensor,
        )


def _presets() -> dict[str, tuple[Fault, ...]]:
    return {
        "none": (),
        "dead": (DeadTaxels(2),),
        "stuck": (StuckTaxels(1),),
        "flicker": (Flicker(0.005),),
        "crosstalk": (Crosstalk(rows=1),),
        "threshold-spread": (ThresholdSpread(0.2),),
        "drift": (OffsetDrift(),),
        "contact-loss": (ContactLoss(0.07),),
        "all": (
            ThresholdSpread(0.2),
            OffsetDrift(),
            Crosstalk(rows=1),
            Flicker(0.005),
            DeadTaxels(2),
            StuckTaxels(1),
        ),
    }


#: Names of the fault presets of the robustness experiment, ``"none"`` first.
FAULT_PRESETS: tuple[str, ...] = tuple(_presets())


def fault_model(name: str | Sequence[Fault]) -> FaultModel:
    """A named preset of :data:`FAULT_PRESETS`, or a model of the given faults.

    Raises
    ------
    InputError
        For an unknown name (listing the known ones).
    """
    if isinstance(name, str):
        presets = _presets()
        if name not in presets:
            raise InputError(f"unknown fault model {name!r}; known: {', '.join(presets)}")
        return FaultModel(presets[name], name=name)
    return FaultModel(tuple(name))
