"""The image cleaning of :func:`~taxelkit.smart.cleaning.clean_images`, a chunk at a time.

:func:`~taxelkit.smart.cleaning.clean_images` cleans a whole recording at once;
:class:`ChunkCleaner` takes the same frames in consecutive chunks of any
length and returns, chunk by chunk, exactly the images the batch function
would (tested). The rules are those of :mod:`taxelkit.smart.cleaning`; only
their state crosses the chunk boundary:

* the running AND of rule 1 (taxels on since the stream began), one frame;
* the last ``n_stuck - 1`` frames of "isolated and on" (rule 1's hold test
  looks that far back), at most ``stuck_s`` of frames;
* for each taxel still armed by rule 1 (seeded and not yet released), the
  frames at which it was last on, last seeded and last released;
* the previous bridged frame (rule 3's persistence looks one frame back).

None of it grows with the recording, so an out-of-core recogniser holds one
chunk of images at a time.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError
from taxelkit.smart.cleaning import (
    CleaningConfig,
    _backend,
    _bits_of,
    _bridged,
    _clean,
    _held,
    _neighbours8,
    release_frames_for,
    stuck_frames_for,
)

__all__ = ["ChunkCleaner"]

#: Per armed taxel: frames (global indices) last on, last released, last seeded.
_Marks = tuple[int, int, int]


class ChunkCleaner:
    """Clean contact images chunk by chunk, as :func:`clean_images` cleans them all at once.

    Parameters
    ----------
    shape : (rows, cols)
        Frame shape.
    config : CleaningConfig, optional

    Examples
    --------
    >>> import numpy as np
    >>> from taxelkit.smart.cleaning import clean_images
    >>> img = np.zeros((6, 8, 8), bool); img[1:, 3:5, 3:5] = True
    >>> t = np.arange(6) * 0.05
    >>> cleaner = ChunkCleaner((8, 8))
    >>> parts = [cleaner.push(img[a:a + 4], t[a:a + 4]) for a in (0, 4)]
    >>> bool(np.array_equal(np.concatenate(parts), clean_images(img, t)))
    True
    """

    def __init__(self, shape: tuple[int, int], *, config: CleaningConfig | None = None) -> None:
        rows, cols = int(shape[0]), int(shape[1])
        if rows < 1 or cols < 1:
            raise InputError(f"shape must be two positive integers, got {shape!r}")
        self.shape = (rows, cols)
        self.config = CleaningConfig() if config is None else config
        self._ops = _backend(cols)
        self.reset()

    def reset(self) -> None:
        """Forget the stream."""
        self._n_seen = 0
        self._t0: float | None = None
        self._dt: float | None = None
        self._since_start: NDArray[Any] | None = None  # running AND, None before frame 0
        self._iso_tail: NDArray[Any] | None = None  # last n_stuck - 1 isolated-and-on frames
        self._marks: dict[tuple[int, Any], _Marks] = {}  # armed (word, bit) -> marks
        self._prev: NDArray[Any] | None = None  # bridged frame before the chunk

    def push(self, images: ArrayLike, t_s: ArrayLike) -> NDArray[np.bool_]:
        """Clean the next chunk.

        Parameters
        ----------
        images : (n, rows, cols) bool
            The next ``n`` thresholded contact images (``n`` may be 0).
        t_s : (n,) float, s
            Their timestamps.

        Returns
        -------
        (n, rows, cols) bool
            The cleaned images, those :func:`clean_images` gives for these frames.
        """
        img = np.asarray(images)
        if img.ndim != 3 or img.dtype != bool or img.shape[1:] != self.shape:
            raise InputError(
                f"images must be bool with shape (n, {self.shape[0]}, {self.shape[1]}), "
                f"got {img.dtype} {img.shape}"
            )
        t = np.asarray(t_s, dtype=np.float64)
        if t.shape != (img.shape[0],):
            raise InputError(f"t_s must have shape ({img.shape[0]},), got {t.shape}")
        n = img.shape[0]
        if n == 0:
            return img.copy()
        if self._t0 is None:
            self._t0 = float(t[0])
        if self._dt is None and self._n_seen + n > 1:
            self._dt = float(t[1 - self._n_seen] - self._t0)
        ops, cfg = self._ops, self.config
        on = ops.pack(img)
        if self._prev is None:
            self._prev = np.zeros_like(on[0])
        stuck = self._stuck(on) if cfg.stuck else np.zeros_like(on)
        bridged = _bridged(ops, on, stuck, cfg)
        out = _clean(ops, bridged, self._prev, cfg)
        self._prev = bridged[-1].copy()
        self._n_seen += n
        return ops.unpack(out, self.shape[1])

    # -- rule 1 with carried state -------------------------------------------------------
    def _since_start_of(self, on: NDArray[Any]) -> NDArray[Any]:
        """Taxels on in every frame since the stream began (running AND across chunks)."""
        acc = on[0] if self._since_start is None else self._since_start
        if not np.any(acc):
            self._since_start = acc
            return np.zeros_like(on)
        out: NDArray[Any] = np.bitwise_and.accumulate(np.concatenate([acc[None], on]), axis=0)[1:]
        self._since_start = out[-1].copy()
        return out

    def _stuck(self, on: NDArray[Any]) -> NDArray[Any]:
        dt = 1.0 if self._dt is None else self._dt
        n_stuck = stuck_frames_for(dt, self.config)
        n_release = release_frames_for(dt, self.config)
        iso = on & ~_neighbours8(self._ops, on)
        tail = self._iso_tail if self._iso_tail is not None else iso[:0]
        both = np.concatenate([tail, iso])
        held = _held(both, n_stuck)[tail.shape[0] :]
        self._iso_tail = both[max(0, both.shape[0] - (n_stuck - 1)) :].copy()
        seed = self._since_start_of(on) | held
        return self._mask(on, seed, n_release)

    def _mask(self, on: NDArray[Any], seed: NDArray[Any], n_release: int) -> NDArray[Any]:
        """Bits masked in each frame: seeded and not yet off for ``n_release`` frames."""
        frames, rest = on.shape[0], on.shape[1:]
        on_f = on.reshape(frames, -1)
        seed_f = seed.reshape(frames, -1)
        out = np.zeros_like(on_f)
        g = np.arange(self._n_seen, self._n_seen + frames)
        seeded = np.bitwise_or.reduce(seed_f, axis=0)
        keys = {
            (j, bit)
            for j in np.flatnonzero(seeded).tolist()
            for bit in _bits_of(int(seeded[j]), on_f.dtype)
        }
        keys.update(self._marks)
        marks: dict[tuple[int, Any], _Marks] = {}
        for j, bit in sorted(keys, key=lambda key: (key[0], int(key[1]))):
            last_on0, last_release0, last_seed0 = self._marks.get((j, bit), (-1, -1, -1))
            o = (on_f[:, j] & bit) != 0
            s = (seed_f[:, j] & bit) != 0
            last_on = np.maximum(np.maximum.accumulate(np.where(o, g, -1)), last_on0)
            released = (g - last_on) >= n_release
            last_release = np.maximum(
                np.maximum.accumulate(np.where(released, g, -1)), last_release0
            )
            last_seed = np.maximum(np.maximum.accumulate(np.where(s, g, -1)), last_seed0)
            masked = o & (last_seed > last_release)
            out[masked, j] |= bit
            if last_seed[-1] > last_release[-1]:  # still armed: carry its marks
                marks[(j, bit)] = (int(last_on[-1]), int(last_release[-1]), int(last_seed[-1]))
        self._marks = marks
        return out.reshape((frames, *rest))
