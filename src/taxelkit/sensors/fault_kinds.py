"""The single imperfections of a taxel array, each a frozen, seeded dataclass.

:mod:`taxelkit.sensors.faults` describes them, chains them
(:class:`~taxelkit.sensors.faults.FaultModel`) and names the presets; this
module holds the models themselves (all re-exported there).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError, check_in_range, check_positive

__all__ = [
    "FLICKER_ON_LEVEL",
    "ContactLoss",
    "Crosstalk",
    "DeadTaxels",
    "Fault",
    "Flicker",
    "OffsetDrift",
    "StuckTaxels",
    "ThresholdSpread",
]

#: Reading of a taxel flickered on, in units of the contact threshold (clearly in contact).
FLICKER_ON_LEVEL = 2.0


class Fault(Protocol):
    """One imperfection: a seeded map from frames to frames."""

    def apply(
        self,
        frames: NDArray[Any],
        t_s: NDArray[np.float64],
        *,
        threshold: float,
        rng: np.random.Generator,
    ) -> NDArray[Any]:
        """Return the frames as the imperfect sensor reports them (a new array)."""
        ...


Frames = NDArray[Any]
Times = NDArray[np.float64]
Gen = np.random.Generator


class _FrameFault:
    """The shared ``apply`` of the fault models; each defines ``_change``."""

    def apply(
        self, frames: Frames, t_s: Times, *, threshold: float, rng: np.random.Generator
    ) -> Frames:
        """Return the frames ``(T, rows, cols)`` as the imperfect sensor reports them.

        Parameters
        ----------
        frames : (T, rows, cols) bool or float
            The true frames (not changed).
        t_s : (T,) float, s
        threshold : float
            Contact threshold of analog frames, in their units.
        rng : numpy.random.Generator
            The source of every random choice.

        Returns
        -------
        (T, rows, cols)
            A new array of the same dtype.
        """
        return self._change(frames, t_s, threshold, rng)

    def _change(self, frames: Frames, t_s: Times, threshold: float, rng: Gen) -> Frames:
        raise NotImplementedError


def _pick_taxels(shape: tuple[int, ...], count: int, rng: np.random.Generator) -> NDArray[np.intp]:
    rows, cols = shape[-2], shape[-1]
    if count > rows * cols:
        raise InputError(f"count must be at most {rows * cols} taxels, got {count}")
    return rng.choice(rows * cols, size=count, replace=False)


def _check_analog(name: str, frames: NDArray[Any]) -> None:
    if frames.dtype == bool:
        raise InputError(f"{name} needs analog frames (float), got bool contact images")


@dataclass(frozen=True)
class DeadTaxels(_FrameFault):
    """``count`` random taxels that never report contact.

    Parameters
    ----------
    count : int
        Number of dead taxels, >= 0.
    """

    count: int = 2

    def __post_init__(self) -> None:
        if int(self.count) < 0:
            raise InputError(f"count must be >= 0, got {self.count!r}")

    def _change(self, frames: Frames, t_s: Times, threshold: float, rng: Gen) -> Frames:
        """Set the dead taxels to 0 (False) in every frame."""
        out = frames.copy()
        flat = out.reshape(out.shape[0], -1)
        flat[:, _pick_taxels(out.shape, int(self.count), rng)] = 0
        return out


@dataclass(frozen=True)
class StuckTaxels(_FrameFault):
    """``count`` random taxels that always report contact.

    Parameters
    ----------
    count : int
        Number of stuck taxels, >= 0.
    level : float
        Their analog reading, in units of the contact threshold (> 1: in contact).
    """

    count: int = 1
    level: float = 10.0

    def __post_init__(self) -> None:
        if int(self.count) < 0:
            raise InputError(f"count must be >= 0, got {self.count!r}")
        if not self.level > 1.0:
            raise InputError(f"level must be > 1 (above the threshold), got {self.level!r}")

    def _change(self, frames: Frames, t_s: Times, threshold: float, rng: Gen) -> Frames:
        """Set the stuck taxels to ``level x threshold`` (True) in every frame."""
        out = frames.copy()
        flat = out.reshape(out.shape[0], -1)
        value: Any = True if out.dtype == bool else self.level * threshold
        flat[:, _pick_taxels(out.shape, int(self.count), rng)] = value
        return out


@dataclass(frozen=True)
class Flicker(_FrameFault):
    """Random flips across the threshold, independent per taxel and frame.

    Parameters
    ----------
    rate : float
        Probability that a taxel reads the opposite of the truth in one frame,
        in [0, 1]. 0.005 flips 1.3 of the 256 Bonneville taxels per frame.
    """

    rate: float = 0.005

    def __post_init__(self) -> None:
        check_in_range("rate", self.rate, 0.0, 1.0)

    def _change(self, frames: Frames, t_s: Times, threshold: float, rng: Gen) -> Frames:
        """Flip taxels: bool by negation, analog to 0 or ``FLICKER_ON_LEVEL x threshold``."""
        flip = rng.random(frames.shape) < self.rate
        if frames.dtype == bool:
            out_b: NDArray[Any] = frames ^ flip
            return out_b
        on = frames > threshold
        high = frames.dtype.type(FLICKER_ON_LEVEL * threshold)
        out: NDArray[Any] = np.where(flip, np.where(on, frames.dtype.type(0), high), frames)
        return out


@dataclass(frozen=True)
class ThresholdSpread(_FrameFault):
    """Per-taxel sensitivity spread (analog frames only).

    Parameters
    ----------
    sigma : float
        Relative spread: taxel ``i`` reads ``u / (1 + sigma z_i)``, ``z_i``
        standard normal (clipped to +-3), so its effective threshold is
        ``threshold x (1 + sigma z_i)``. In [0, 0.3].
    """

    sigma: float = 0.2

    def __post_init__(self) -> None:
        check_in_range("sigma", self.sigma, 0.0, 0.3)

    def _change(self, frames: Frames, t_s: Times, threshold: float, rng: Gen) -> Frames:
        """Scale each taxel by its own gain."""
        _check_analog("ThresholdSpread", frames)
        z = np.clip(rng.standard_normal(frames.shape[1:]), -3.0, 3.0)
        gain = (1.0 / (1.0 + self.sigma * z)).astype(frames.dtype)
        out: NDArray[Any] = frames * gain
        return out


@dataclass(frozen=True)
class Crosstalk(_FrameFault):
    """Row/column leakage of a resistive array (ghosting).

    Parameters
    ----------
    rows, cols : int
        Number of random rows (columns) that also read their next row
        (column; the last one its previous).
    coupling : float
        Fraction of the neighbour's reading added, in (0, 1]. With bool
        frames any coupling lights the taxel where its neighbour is on.
    """

    rows: int = 1
    cols: int = 0
    coupling: float = 0.5

    def __post_init__(self) -> None:
        if int(self.rows) < 0 or int(self.cols) < 0:
            raise InputError(f"rows and cols must be >= 0, got {self.rows!r}, {self.cols!r}")
        check_in_range("coupling", self.coupling, 1e-6, 1.0)

    def _change(self, frames: Frames, t_s: Times, threshold: float, rng: Gen) -> Frames:
        """Add the coupled neighbour's reading to the chosen rows and columns."""
        out = frames.copy()
        for axis, count in ((1, int(self.rows)), (2, int(self.cols))):
            n = frames.shape[axis]
            if count > n:
                raise InputError(f"crosstalk on {count} lines but the array has {n}")
            for line in rng.choice(n, size=count, replace=False).tolist():
                other = line + 1 if line + 1 < n else line - 1
                src = np.take(frames, other, axis=axis)
                dst = [slice(None)] * 3
                dst[axis] = line
                if frames.dtype == bool:
                    out[tuple(dst)] |= src
                else:
                    out[tuple(dst)] += frames.dtype.type(self.coupling) * src
        return out


@dataclass(frozen=True)
class OffsetDrift(_FrameFault):
    """Per-taxel offsets and a common drift of analog outputs.

    Parameters
    ----------
    offset : float
        Standard deviation of the per-taxel offset, in units of the threshold.
    drift_per_s : float
        Common drift, in units of the threshold per second (may be negative).
    """

    offset: float = 0.2
    drift_per_s: float = 0.02

    def __post_init__(self) -> None:
        check_positive("offset", self.offset, allow_zero=True)
        if not np.isfinite(self.drift_per_s):
            raise InputError(f"drift_per_s must be finite, got {self.drift_per_s!r}")

    def _change(self, frames: Frames, t_s: Times, threshold: float, rng: Gen) -> Frames:
        """Add the offsets and the drift (relative to the first timestamp)."""
        _check_analog("OffsetDrift", frames)
        off = rng.standard_normal(frames.shape[1:]) * self.offset * threshold
        drift = (t_s - t_s[0]) * self.drift_per_s * threshold
        out: NDArray[Any] = (frames + off[None] + drift[:, None, None]).astype(frames.dtype)
        return out


@dataclass(frozen=True)
class ContactLoss(_FrameFault):
    """A short loss of the whole image, once, while something touches the array.

    Parameters
    ----------
    duration_s : float
        How long every taxel reads 0 (False), s (> 0).
    """

    duration_s: float = 0.07

    def __post_init__(self) -> None:
        check_positive("duration_s", self.duration_s)

    def _change(self, frames: Frames, t_s: Times, threshold: float, rng: Gen) -> Frames:
        """Blank the frames of one window that starts at a random frame in contact."""
        out = frames.copy()
        on = frames if frames.dtype == bool else frames > threshold
        touching = np.flatnonzero(on.reshape(on.shape[0], -1).any(axis=1))
        fits = touching[t_s[touching] + self.duration_s <= t_s[-1]]
        if fits.size == 0:
            return out
        start = float(t_s[int(fits[rng.integers(fits.size)])])
        out[(t_s >= start) & (t_s < start + self.duration_s)] = 0
        return out
