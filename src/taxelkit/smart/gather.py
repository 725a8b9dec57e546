"""Rows of an array gathered by index, fast: the same values as ``x[idx]``.

NumPy's fancy indexing of a 2-D array along its first axis copies each row's
elements one at a time (about ten times the cost of gathering a 1-D array
of the same number of rows); :func:`take_rows` views each row of a
contiguous array as one opaque item and takes those.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["take_rows"]


def take_rows(
    x: NDArray[Any], idx: NDArray[np.intp], out: NDArray[Any] | None = None
) -> NDArray[Any]:
    """``x[idx]``: the rows ``idx`` ``(k,)`` (integers) of ``x`` ``(n, ...)``, ``(k, ...)``.

    ``out``: a C-contiguous array of that shape and dtype to write them to (returned).

    Examples
    --------
    >>> x = np.arange(12.0).reshape(4, 3)
    >>> take_rows(x, np.array([3, 0, 3])).tolist()
    [[9.0, 10.0, 11.0], [0.0, 1.0, 2.0], [9.0, 10.0, 11.0]]
    """
    if x.ndim == 1:
        got: NDArray[Any] = x.take(idx, out=out)
        return got
    if not x.flags.c_contiguous or x.size == 0 or (out is not None and not out.flags.c_contiguous):
        got = x.take(idx, axis=0, out=out)
        return got
    rows = x.shape[0]
    item = np.dtype((np.void, x.itemsize * (x.size // rows)))
    into = None if out is None else out.reshape(np.size(idx), -1).view(item).reshape(-1)
    picked = x.reshape(rows, -1).view(item).reshape(rows).take(idx, out=into)
    got = picked.view(x.dtype).reshape(np.shape(idx) + x.shape[1:]) if out is None else out
    return got
