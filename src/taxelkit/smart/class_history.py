"""Level 2 classes kept as runs, and the check of a chunk fed to a chunked recogniser.

Shared by the streaming paths (:mod:`taxelkit.smart.stream_state`, the
sensor bank, the chunked recogniser): :class:`ClassHistory` keeps every
frame's class in memory that grows with the changes of class only.
"""

from __future__ import annotations

import bisect
from collections.abc import Iterator, Sequence
from typing import Any, overload

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError

__all__ = ["ClassHistory", "check_chunk", "check_chunk_times"]


def check_chunk(
    frames: ArrayLike, t_s: ArrayLike, shape: tuple[int, int], t_last_s: float
) -> tuple[NDArray[Any], NDArray[np.float64]]:
    """A chunk of frames fed to a chunked recogniser, checked.

    Parameters
    ----------
    frames : (n, rows, cols) bool or float
    t_s : (n,) float, s
    shape : (rows, cols)
        The recogniser's frame shape.
    t_last_s : float, s
        Timestamp of the previous chunk's last frame (``-inf`` before the first).

    Returns
    -------
    frames : (n, rows, cols) ndarray
    t_s : (n,) float64, s

    Raises
    ------
    InputError
        If the shapes do not match or the timestamps do not increase across chunks.
    """
    f = np.asarray(frames)
    if f.ndim != 3 or f.shape[1:] != tuple(shape):
        raise InputError(f"frames must have shape (n, {shape[0]}, {shape[1]}), got {f.shape}")
    return f, check_chunk_times(t_s, f.shape[0], t_last_s)


def check_chunk_times(t_s: ArrayLike, n: int, t_last_s: float) -> NDArray[np.float64]:
    """The timestamps ``(n,)`` of a chunk of ``n`` frames, checked (see :func:`check_chunk`), s.

    Raises
    ------
    InputError
        If there are not ``n`` of them or they do not increase across chunks.
    """
    t = np.asarray(t_s, dtype=np.float64)
    if t.shape != (n,):
        raise InputError(f"t_s must have shape ({n},), got {t.shape}")
    if n and not t[0] > t_last_s:
        raise InputError(f"t_s must increase across chunks, got {float(t[0])!r} after {t_last_s!r}")
    return t


class ClassHistory(Sequence[int]):
    """Level 2 class of every frame so far, stored as runs (memory grows with changes only).

    A read-only sequence of ints: ``len``, indexing (``history[-1]`` is the
    latest frame's class), iteration; :meth:`to_array` materialises it.
    """

    def __init__(self) -> None:
        self._starts: list[int] = []
        self._codes: list[int] = []
        self._n = 0

    def append(self, code: int) -> None:
        """One more frame."""
        if not self._codes or self._codes[-1] != code:
            self._starts.append(self._n)
            self._codes.append(code)
        self._n += 1

    def extend_array(self, codes: NDArray[np.integer]) -> None:
        """More frames ``(m,)``, vectorised."""
        if codes.size == 0:
            return
        cut = np.flatnonzero(np.diff(codes)) + 1
        firsts = np.concatenate([[0], cut])
        values = codes[firsts].tolist()
        starts = (firsts + self._n).tolist()
        if self._codes and self._codes[-1] == values[0]:
            values, starts = values[1:], starts[1:]
        self._codes += values
        self._starts += starts
        self._n += int(codes.size)

    def extend_constant(self, code: int, m: int) -> None:
        """``m`` more frames of class ``code``."""
        if m <= 0:
            return
        if not self._codes or self._codes[-1] != code:
            self._starts.append(self._n)
            self._codes.append(code)
        self._n += m

    def __len__(self) -> int:
        return self._n

    @overload
    def __getitem__(self, i: int) -> int: ...
    @overload
    def __getitem__(self, i: slice) -> list[int]: ...
    def __getitem__(self, i: int | slice) -> int | list[int]:
        if isinstance(i, slice):
            return self.to_array()[i].tolist()  # type: ignore[no-any-return]
        j = i + self._n if i < 0 else i
        if not 0 <= j < self._n:
            raise IndexError(f"frame {i} out of range for {self._n} frames")
        return self._codes[bisect.bisect_right(self._starts, j) - 1]

    def __iter__(self) -> Iterator[int]:
        return iter(self.to_array().tolist())

    def runs(self) -> list[tuple[int, int, int]]:
        """``(class, first_frame, last_frame)`` of every run, in order."""
        ends = [*self._starts[1:], self._n]
        return [(c, s, e - 1) for c, s, e in zip(self._codes, self._starts, ends, strict=True)]

    def to_array(self) -> NDArray[np.int8]:
        """The classes ``(T,)`` int8."""
        lengths = np.diff(np.asarray([*self._starts, self._n], dtype=np.int64)).tolist()
        return np.repeat(np.asarray(self._codes, dtype=np.int8), lengths)

    def __array__(self, dtype: Any = None, copy: bool | None = None) -> NDArray[Any]:
        a = self.to_array()
        return a if dtype is None else a.astype(dtype)
