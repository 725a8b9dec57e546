"""Frame rate of a recording: what a slower (or faster) scanner of the same motion reports."""

from __future__ import annotations

import math

import numpy as np

from taxelkit.errors import InputError, check_positive
from taxelkit.frames import TactileFrames

__all__ = ["frames_at_rate"]


def frames_at_rate(recording: TactileFrames, rate_hz: float) -> TactileFrames:
    """Sample a recording at another frame rate by sample-and-hold.

    A scanner running at ``rate_hz`` reports, at each of its times
    ``t_0 + j / rate_hz``, the newest frame of the recording taken at or
    before that time (the array is scanned, not interpolated). Rates above
    the recording's repeat frames; the usual use is to slow a fast recording
    down.

    Parameters
    ----------
    recording : TactileFrames
    rate_hz : float
        New frame rate, Hz (> 0).

    Returns
    -------
    TactileFrames
        Frames at ``t_0 + j / rate_hz`` for ``j = 0 .. floor(duration x rate_hz)``.

    Raises
    ------
    InputError
        For a non-positive rate.

    Examples
    --------
    >>> import numpy as np
    >>> rec = TactileFrames(np.zeros((241, 4, 4), bool), t_s=np.arange(241) / 240.0)
    >>> frames_at_rate(rec, 5.0).n_frames
    6
    """
    rate = check_positive("rate_hz", rate_hz)
    t = np.asarray(recording.t_s, dtype=np.float64)
    n = math.floor((t[-1] - t[0]) * rate + 1e-9) + 1
    if n > 100 * max(recording.n_frames, 1) + 1:
        raise InputError(f"rate_hz={rate} would repeat each frame over 100 times")
    times = t[0] + np.arange(n) / rate
    idx = np.searchsorted(t, times + 1e-9, side="right") - 1
    return TactileFrames(
        recording.frames[idx],
        t_s=times,
        pitch_mm=recording.pitch_mm,
        units=recording.units,
        sensor=recording.sensor,
    )
