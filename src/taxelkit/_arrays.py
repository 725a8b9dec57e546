"""Small array helpers shared across layers."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike, DTypeLike, NDArray

__all__ = ["readonly_copy"]


def readonly_copy(a: ArrayLike, dtype: DTypeLike | None = None) -> NDArray[Any]:
    """A read-only copy of ``a`` (optionally cast to ``dtype``).

    Frozen dataclasses hold their arrays through this, so that nothing can change
    them through a reference.
    """
    out = np.array(a, dtype=dtype, copy=True)
    out.setflags(write=False)
    return out
