"""A stateful, frame-at-a-time form of the mechanoreceptive unit.

:class:`StreamingNeuron` keeps the previous frame and the last ``n`` receptor
outputs in a ring buffer; for the same frames it returns exactly what the batch
functions of :mod:`taxelkit.neuron.mechanoreceptor` return.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_positive
from taxelkit.neuron.mechanoreceptor import NeuronParams, spatial_summation, window_samples
from taxelkit.neuron.quantisers import ramp, ternary

__all__ = ["StreamingNeuron"]


class StreamingNeuron:
    """Feed frames one at a time; get the neuron outputs for each.

    Parameters
    ----------
    shape : (rows, cols)
        Frame shape.
    dt_s : float
        Sample interval, s.
    params : NeuronParams, optional
    signed : bool
        Signed receptor and ternary output (direction mode, Section IV).
    epsilon : float
        Dead zone of the ternary output (direction mode only).

    Examples
    --------
    >>> import numpy as np
    >>> n = StreamingNeuron((1, 1), 0.01, signed=True, epsilon=0.01)
    >>> [int(n.push(np.array([[h]]))[0, 0]) for h in (0.0, 0.0, 0.05, 0.05)]
    [0, 0, 1, 1]
    """

    def __init__(
        self,
        shape: tuple[int, int],
        dt_s: float,
        params: NeuronParams | None = None,
        *,
        signed: bool = False,
        epsilon: float = 0.0,
    ) -> None:
        self.params = NeuronParams() if params is None else params
        self.dt_s = check_positive("dt_s", dt_s)
        self.signed = signed
        self.epsilon = check_positive("epsilon", epsilon, allow_zero=True)
        self.shape = (int(shape[0]), int(shape[1]))
        self._n = window_samples(self.params.tau_s, self.dt_s)
        self.reset()

    def reset(self) -> None:
        """Forget the history (as before the first frame)."""
        self._buffer = np.zeros((self._n, *self.shape))
        self._sum = np.zeros(self.shape)
        self._previous: NDArray[np.float64] | None = None
        self._count = 0

    def push(self, frame_mm: ArrayLike) -> NDArray[Any]:
        """Process one frame.

        Parameters
        ----------
        frame_mm : (rows, cols) float, mm

        Returns
        -------
        (rows, cols) float pulse density, or int8 in {-1, 0, 1} in direction mode.
        """
        f = np.asarray(frame_mm, dtype=np.float64)
        if f.shape != self.shape:
            raise InputError(f"frame_mm must have shape {self.shape}, got {f.shape}")
        if self._previous is None:
            s = np.zeros(self.shape)
        else:
            s = (f - self._previous) / self.dt_s * self.params.gain_a
            if not self.signed:
                s = np.abs(s)
        self._previous = f
        slot = self._count % self._n
        self._sum += s - self._buffer[slot]
        self._buffer[slot] = s
        self._count += 1
        # The running sum drifts by rounding; recompute it once per window.
        if slot == self._n - 1:
            self._sum = self._buffer.sum(axis=0)
        u = spatial_summation((self._sum * self.dt_s)[None], self.params.receptive_field)[0]
        if self.signed:
            return ternary(u, self.epsilon)
        return ramp(u - self.params.threshold_h)
