"""Rotation of chain codes: cyclic shifts inside each level block (paper 000, Section V.2).

A contour rotated counter-clockwise by ``s * 360 / m`` deg moves every move
direction ``s`` sectors up, so its chain code is the original with the ``m``
elements of each of the ``l`` blocks shifted cyclically by ``+s``.
"""

from __future__ import annotations

from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError
from taxelkit.memory.chain_code import DEFAULT_CHAIN_CODE, ChainCodeConfig

__all__ = ["all_cyclic_shifts", "cyclic_shift_index"]


@lru_cache(maxsize=32)
def _shift_index(m: int, l: int) -> NDArray[np.intp]:  # noqa: E741 (paper symbol)
    shift = np.arange(m)[:, np.newaxis]  # (m, 1)
    sector = np.tile(np.arange(m), l)[np.newaxis, :]  # (1, N)
    block = np.repeat(np.arange(l) * m, m)[np.newaxis, :]  # (1, N)
    index: NDArray[np.intp] = ((sector - shift) % m + block).astype(np.intp)
    index.setflags(write=False)
    return index


def cyclic_shift_index(config: ChainCodeConfig = DEFAULT_CHAIN_CODE) -> NDArray[np.intp]:
    """Index table of all cyclic shifts: ``code[..., table]`` is ``(..., m, N)``.

    ``table[s, i + m j] = (i - s) mod m + m j``: row ``s`` is the code of the
    contour rotated counter-clockwise by ``s * 360 / m`` deg.

    Parameters
    ----------
    config : ChainCodeConfig

    Returns
    -------
    (m, N) intp
        Read-only, cached per ``(m, l)``.

    References
    ----------
    Paper 000, Section V.2 (cyclic replacement inside each block).
    """
    return _shift_index(config.m, config.l)


def all_cyclic_shifts(
    codes: ArrayLike, *, config: ChainCodeConfig = DEFAULT_CHAIN_CODE
) -> NDArray[Any]:
    """All ``m`` rotations of one or many chain codes, in one indexing operation.

    Parameters
    ----------
    codes : (..., N) int
        Chain codes (values in {-1, 0, +1}, not checked here).
    config : ChainCodeConfig

    Returns
    -------
    (..., m, N), same dtype as ``codes``
        ``out[..., s, :]`` is the code of the contour rotated counter-clockwise
        by ``s * 360 / m`` deg: ``out[..., s, i + m j] = codes[..., (i - s) mod
        m + m j]``; shift 0 is the input.

    Raises
    ------
    InputError
        If the last axis is not ``N = m * l`` long.

    References
    ----------
    Paper 000, Section V.2: element ``i + m (j - 1)`` goes to ``i + 1 + m (j -
    1)`` and ``m j`` to ``1 + m (j - 1)`` for one shift.

    Examples
    --------
    >>> cfg = ChainCodeConfig(m=3, l=2, thresholds=(0.2, 0.5))
    >>> all_cyclic_shifts(np.array([1, 2, 3, 4, 5, 6]), config=cfg).tolist()
    [[1, 2, 3, 4, 5, 6], [3, 1, 2, 6, 4, 5], [2, 3, 1, 5, 6, 4]]
    """
    x = np.asarray(codes)
    if x.ndim < 1 or x.shape[-1] != config.n_elements:
        raise InputError(
            f"codes must have shape (..., {config.n_elements}) for m={config.m}, "
            f"l={config.l}, got shape {x.shape}"
        )
    # One gather with the index table (np.take keeps the result C-contiguous).
    shifted: NDArray[Any] = np.take(x, cyclic_shift_index(config), axis=-1)
    return shifted
