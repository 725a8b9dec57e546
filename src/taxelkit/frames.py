"""A sequence of tactile frames with its timestamps and metadata."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit._arrays import readonly_copy
from taxelkit.errors import (
    InputError,
    check_finite_array,
    check_ndim,
    check_positive,
    check_threshold,
)

__all__ = [
    "CONTACT_UNITS",
    "DEFAULT_FRAME_INTERVAL_S",
    "DEFAULT_PITCH_MM",
    "DEFAULT_UNITS",
    "TactileFrames",
]

#: Units string of boolean contact images (1 = taxel in contact).
CONTACT_UNITS = "contact"
#: Units string of float deflection frames.
DEFAULT_UNITS = "mm"
#: Frame interval assumed when a recording has no ``t_s``: 1 s, the
#: development sample rate of the smart sensor in paper 001 (Section 3, Level 0).
DEFAULT_FRAME_INTERVAL_S = 1.0
#: Pitch assumed when a recording has no ``pitch_mm``: 1 mm, so that physical
#: quantities read as taxel units. Override it wherever the true pitch is known.
DEFAULT_PITCH_MM = 1.0


@dataclass(frozen=True, eq=False)
class TactileFrames:
    """Tactile frames from one sensor over time.

    Parameters
    ----------
    frames : (T, rows, cols) bool or float
        ``frames[t, i, j]`` is taxel ``(i, j)`` at time ``t_s[t]``: float
        deflection in ``units`` (usually mm of skin displacement, positive
        into the sensor) or bool contact (``units == "contact"``).
    t_s : (T,) float, s, optional
        Strictly increasing timestamps. Default: ``arange(T) *
        DEFAULT_FRAME_INTERVAL_S``.
    pitch_mm : float, optional
        Taxel pitch, mm. Default :data:`DEFAULT_PITCH_MM`.
    units : str, optional
        ``"contact"`` for bool frames (forced), else a unit such as ``"mm"``.
    sensor : str, optional
        Name of the sensor or preset that produced the frames.

    Raises
    ------
    InputError
        On a wrong number of dimensions, NaN/Inf, non-increasing or mismatched
        timestamps, or a non-positive pitch.

    Notes
    -----
    Arrays are copied and made read-only so that a frozen instance cannot be
    changed through them.

    Examples
    --------
    >>> import numpy as np
    >>> rec = TactileFrames(np.zeros((3, 16, 16), bool))
    >>> rec.shape, rec.duration_s, rec.units
    ((3, 16, 16), 2.0, 'contact')
    """

    frames: NDArray[Any]
    t_s: NDArray[np.float64]
    pitch_mm: float = DEFAULT_PITCH_MM
    units: str = DEFAULT_UNITS
    sensor: str = "unknown"

    def __init__(
        self,
        frames: ArrayLike,
        t_s: ArrayLike | None = None,
        pitch_mm: float = DEFAULT_PITCH_MM,
        units: str | None = None,
        sensor: str = "unknown",
    ) -> None:
        self._fill(frames, t_s, pitch_mm, units, sensor, copy=True)

    @classmethod
    def adopt(
        cls,
        frames: NDArray[Any],
        t_s: NDArray[Any] | None = None,
        pitch_mm: float = DEFAULT_PITCH_MM,
        units: str | None = None,
        sensor: str = "unknown",
    ) -> TactileFrames:
        """As the constructor, holding arrays that the caller made and hands over (no copy).

        For readers that have just created ``frames`` (and ``t_s``) and keep
        no reference to them: the arrays are checked as by the constructor
        and made read-only in place, rather than copied (a chunk of a long
        recording is read once). Arrays that are converted (integer frames,
        timestamps of another dtype) are copied as by the constructor.

        Parameters
        ----------
        frames : (T, rows, cols) bool or float
        t_s : (T,) float, s, optional
        pitch_mm, units, sensor
            As the constructor.

        Returns
        -------
        TactileFrames
        """
        out = cls.__new__(cls)
        out._fill(frames, t_s, pitch_mm, units, sensor, copy=False)
        return out

    def _fill(
        self,
        frames: ArrayLike,
        t_s: ArrayLike | None,
        pitch_mm: float,
        units: str | None,
        sensor: str,
        *,
        copy: bool,
    ) -> None:
        f = check_ndim("frames", frames, 3, "(T, rows, cols)")
        if f.dtype.kind not in "biuf":
            raise InputError(f"frames must be bool or numeric, got dtype {f.dtype}")
        if f.dtype.kind in "iu":
            f = f.astype(np.float64)
        check_finite_array("frames", f)
        n = f.shape[0]
        if t_s is None:
            t = np.arange(n, dtype=np.float64) * DEFAULT_FRAME_INTERVAL_S
        else:
            t = check_ndim("t_s", t_s, 1, "(T,)").astype(np.float64)
            if t.shape[0] != n:
                raise InputError(f"t_s must have {n} entries (one per frame), got {t.shape[0]}")
            check_finite_array("t_s", t)
            if n > 1 and not np.all(np.diff(t) > 0):
                k = int(np.argmin(np.diff(t) > 0))
                raise InputError(
                    f"t_s must be strictly increasing, got t_s[{k}]={float(t[k])!r} "
                    f">= t_s[{k + 1}]={float(t[k + 1])!r}"
                )
        pitch = check_positive("pitch_mm", pitch_mm)
        if f.dtype == bool:
            u = CONTACT_UNITS
        else:
            u = DEFAULT_UNITS if units is None else str(units)
            if u == CONTACT_UNITS:
                raise InputError("units 'contact' requires bool frames")
        object.__setattr__(self, "frames", readonly_copy(f) if copy else _readonly(f))
        object.__setattr__(self, "t_s", readonly_copy(t) if copy else _readonly(t))
        object.__setattr__(self, "pitch_mm", pitch)
        object.__setattr__(self, "units", u)
        object.__setattr__(self, "sensor", str(sensor))

    @property
    def n_frames(self) -> int:
        """Number of frames ``T``."""
        return int(self.frames.shape[0])

    @property
    def shape(self) -> tuple[int, int, int]:
        """``(T, rows, cols)``."""
        t, r, c = self.frames.shape
        return (int(t), int(r), int(c))

    @property
    def is_contact(self) -> bool:
        """True for boolean contact images."""
        return bool(self.frames.dtype == bool)

    @property
    def duration_s(self) -> float:
        """``t_s[-1] - t_s[0]`` (0 for fewer than two frames), s."""
        return float(self.t_s[-1] - self.t_s[0]) if self.n_frames > 1 else 0.0

    @property
    def rate_hz(self) -> float | None:
        """Mean frame rate, Hz; ``None`` for fewer than two frames."""
        if self.n_frames < 2:
            return None
        return (self.n_frames - 1) / self.duration_s

    def contact(self, threshold: float) -> NDArray[np.bool_]:
        """Binary contact images ``frames > threshold`` (bool frames are returned as is).

        Parameters
        ----------
        threshold : float
            Fixed threshold in ``units`` (paper 001, Section 3, Level 1).

        Returns
        -------
        (T, rows, cols) bool
        """
        if self.is_contact:
            return np.asarray(self.frames)
        return np.asarray(self.frames > check_threshold("threshold", threshold))

    def equals(self, other: object) -> bool:
        """True if frames, timestamps, pitch, units and sensor are all identical."""
        if not isinstance(other, TactileFrames):
            return False
        return (
            self.frames.dtype == other.frames.dtype
            and np.array_equal(self.frames, other.frames)
            and np.array_equal(self.t_s, other.t_s)
            and self.pitch_mm == other.pitch_mm
            and self.units == other.units
            and self.sensor == other.sensor
        )


def _readonly(a: NDArray[Any]) -> NDArray[Any]:
    """``a`` itself, made read-only."""
    if a.flags.writeable:
        a.setflags(write=False)
    return a
