"""The result of edge tracing: a :class:`Trace`, and the log that builds it section by section.

Everything here is what the tracer measured or commanded; nothing comes from
the specimen. Quantities used *while* tracing (an online recogniser, a
partial recall) must be those of the sections done so far:
:attr:`Trace.arc_length_mm` is the cumulative path length at every point and
:meth:`Trace.head` the trace as it stood after its first sections. The
contour's total length is known only once the loop has closed.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.tracing.edge_estimate import EdgeEstimate

__all__ = ["STOP_REASONS", "Trace", "TraceLog"]

#: Why a trace stops: back at its start around a plausible contour; back at
#: its start around a loop too small or too winding to be a contour
#: (:mod:`taxelkit.tracing.loop_closure`); the section budget spent; the
#: edge lost for more than ``max_misses`` points; or a prefix cut by
#: :meth:`Trace.head`.
STOP_REASONS = ("closed", "implausible_loop", "max_sections", "lost", "partial")


@dataclass(frozen=True, eq=False)
class Trace:
    """A traced contour with per-section diagnostics.

    Attributes
    ----------
    points_mm : (K + 1, 2) float, mm
        Commanded array centres, from the start to the last point.
    moves_mm : (K, 2) float, mm
        ``dr`` of every section (Eq. 7); the input of chain-symbolizing.
    dv_mm, de_mm : (K, 2) float, mm
        The two terms of Eq. 7 for every section (``dv`` is zero at a miss).
    normals : (K, 2) float
        Edge normal seen at each point (NaN at a miss).
    n_crossings : (K,) int
        Crossing points found at each point.
    closed : bool
        True when the loop closed.
    stop_reason : str
        One of :data:`STOP_REASONS`.
    """

    points_mm: NDArray[np.float64]
    moves_mm: NDArray[np.float64]
    dv_mm: NDArray[np.float64]
    de_mm: NDArray[np.float64]
    normals: NDArray[np.float64]
    n_crossings: NDArray[np.int64]
    closed: bool
    stop_reason: str

    @property
    def n_sections(self) -> int:
        """Number of sections ``K``."""
        return int(self.moves_mm.shape[0])

    @property
    def arc_length_mm(self) -> NDArray[np.float64]:
        """Path length travelled up to every point, ``(K + 1,)`` mm.

        ``arc_length_mm[k]`` is what the tracer knows after ``k`` sections;
        only the last entry, once the loop has closed, is the contour's length.
        """
        steps = np.hypot(self.moves_mm[:, 0], self.moves_mm[:, 1])
        return np.concatenate([[0.0], np.cumsum(steps)])

    @property
    def travelled_mm(self) -> float:
        """Path length travelled by the end of the trace, mm."""
        return float(self.arc_length_mm[-1])

    def head(self, n_sections: int) -> Trace:
        """The trace as it stood after its first ``n_sections`` sections.

        Parameters
        ----------
        n_sections : int
            ``0 <= n_sections <= K``.

        Returns
        -------
        Trace
            The first ``n_sections`` moves and ``n_sections + 1`` points;
            ``closed`` is False and ``stop_reason`` ``"partial"`` unless it is
            the whole trace.

        Raises
        ------
        InputError
            If ``n_sections`` is outside ``[0, K]``.
        """
        k = int(n_sections)
        if not 0 <= k <= self.n_sections:
            raise InputError(f"n_sections must be in [0, {self.n_sections}], got {n_sections!r}")
        if k == self.n_sections:
            return self
        return Trace(
            points_mm=self.points_mm[: k + 1],
            moves_mm=self.moves_mm[:k],
            dv_mm=self.dv_mm[:k],
            de_mm=self.de_mm[:k],
            normals=self.normals[:k],
            n_crossings=self.n_crossings[:k],
            closed=False,
            stop_reason="partial",
        )

    def straightness(self, *, axis_tolerance_deg: float = 3.0) -> float | None:
        """``|r|``, Pearson correlation of the points' x and y (paper 000, Fig. 7).

        Parameters
        ----------
        axis_tolerance_deg : float
            ``r`` measures straightness only for oblique lines: it tends to 0 as
            a perfectly straight line turns parallel to an axis. Within this
            angle of the x or y axis (principal direction of the points) the
            result is ``None``, as the paper leaves 0 and 90 deg unquoted.

        Returns
        -------
        float or None
        """
        p = self.points_mm - self.points_mm.mean(axis=0)
        if p.shape[0] < 3:
            return None
        _, vecs = np.linalg.eigh(p.T @ p)
        angle = float(np.rad2deg(np.arctan2(vecs[1, 1], vecs[0, 1]))) % 90.0
        if min(angle, 90.0 - angle) < axis_tolerance_deg:
            return None
        return float(abs(np.corrcoef(p[:, 0], p[:, 1])[0, 1]))


@dataclass
class TraceLog:
    """What :func:`~taxelkit.tracing.tracer.trace_edge` records, section by section."""

    points: list[NDArray[np.float64]]
    moves: list[NDArray[np.float64]] = field(default_factory=list)
    dvs: list[NDArray[np.float64]] = field(default_factory=list)
    des: list[NDArray[np.float64]] = field(default_factory=list)
    normals: list[Any] = field(default_factory=list)
    crossings: list[int] = field(default_factory=list)

    def record(
        self,
        p: NDArray[np.float64],
        dv: NDArray[np.float64],
        de: NDArray[np.float64],
        est: EdgeEstimate,
    ) -> None:
        """Append one section: the new position, its two move parts and the estimate."""
        self.points.append(p.copy())
        self.moves.append(dv + de)
        self.dvs.append(dv)
        self.des.append(de)
        self.normals.append(est.normal)
        self.crossings.append(int(est.crossings_mm.shape[0]))

    def to_trace(self, stop: str) -> Trace:
        """The recorded sections as a :class:`Trace` that stopped for ``stop``."""

        def stack(v: list[Any]) -> NDArray[np.float64]:
            return np.asarray(v, dtype=np.float64).reshape(-1, 2)

        return Trace(
            points_mm=stack(self.points),
            moves_mm=stack(self.moves),
            dv_mm=stack(self.dvs),
            de_mm=stack(self.des),
            normals=stack(self.normals),
            n_crossings=np.asarray(self.crossings, dtype=np.int64),
            closed=stop == "closed",
            stop_reason=stop,
        )
