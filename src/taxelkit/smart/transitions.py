"""Level 3 of the smart sensor: the tactemes of a change of contact class.

LC -> AC, AC -> LC, LC -> AC -> LC with the two lines parallel or at 90 deg
(a square face) or at 60/120 deg (a triangular face), and (with face
shapes) AC -> LC -> AC onto another face; the rules are described in
:mod:`taxelkit.smart.tactemes`, the thresholds in
:class:`~taxelkit.smart.tacteme_config.TactemeConfig`.
"""

from __future__ import annotations

import math

import numpy as np

from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.tacteme_config import TactemeConfig
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.track_geometry import axis_difference_deg

__all__ = ["transition_tactemes"]


def transition_tactemes(
    history: list[tuple[int, float]],
    config: TactemeConfig,
    *,
    gap_frames: int = 0,
    max_gap_frames: int | None = None,
    centres: list[tuple[float, float]] | None = None,
    wobbles_deg: list[float] | None = None,
    pitch_mm: float = 0.0,
) -> list[Tacteme]:
    """Tactemes of the latest change of accepted class.

    Parameters
    ----------
    history : list of (class, orientation_deg)
        Accepted non-empty segments of the current contact, oldest first; the
        orientation is the line's (mean of its frames next to the change).
    config : TactemeConfig
    gap_frames : int
        Frames between the last frame of the previous segment and the first of
        the new one. LC -> AC and AC -> LC mean a direct change: a polyhedron's
        edge lands on a face at once, while a round body between its side and
        a flat face passes through a rim-point phase, even when that phase
        reads as indeterminate. Gaps above ``max_gap_frames`` (default
        ``2 k``; the recogniser passes ``max(2 k frames, transition_gap_s)``)
        give no transition.
    max_gap_frames : int, optional
    centres : list of (x, y) mm, optional
        Centre of each segment of ``history`` (an area's first frames, a
        line's held frames). With ``config.face_shapes``: AC -> LC -> AC
        with the two areas on opposite sides of the line, each at least
        ``over_min_mm`` from it, is "AC -> LC -> AC onto another face" (a
        polyhedron tipped over an edge rather than back onto its face).
    wobbles_deg : list of float, optional
        For each segment of ``history``, how far the grid alone can tilt its
        line (:func:`~taxelkit.smart.track_geometry.grid_wobble_deg`). The
        angle between two edges is read (square or triangular face) only
        when both wobbles are within ``edge_angle_tol_deg``: an edge three
        taxels long on a coarse array reads 60 deg from a square's 90. An
        angle within ``edge_angle_doubt_deg`` of 75 deg reads as neither.
        With ``config.edge_angle_grid_sum`` an angle reads as a triangle's
        only below ``90 - (w1 + w2)`` and as a square's only above
        ``60 + (w1 + w2)``, the wobbles of the two edges: the grid can tilt
        both edges at once.
    pitch_mm : float
        Taxel pitch, mm (0: unknown). With ``config.edge_apart_pitches``, two
        parallel edges (with ``centres``) read as a square's only when they
        lie that many pitches apart across their direction: a polyhedron
        rocked back over the edge it tipped onto shows the same edge again.

    Returns
    -------
    list of Tacteme
    """
    limit = 2 * int(config.debounce_frames) if max_gap_frames is None else max_gap_frames
    if len(history) < 2 or gap_frames > limit:
        return []
    (c1, _), (c2, o2) = history[-2], history[-1]
    out: list[Tacteme] = []
    if c1 == ContactClass.LINE and c2 == ContactClass.AREA:
        out.append(Tacteme.LC_TO_AC)
        if (
            config.face_shapes
            and centres is not None
            and len(history) >= 3
            and history[-3][0] == ContactClass.AREA
        ):
            t = math.radians(history[-2][1])
            normal = np.array([-math.sin(t), math.cos(t)])
            line = np.asarray(centres[-2])
            s1 = float(normal @ (np.asarray(centres[-3]) - line))
            s2 = float(normal @ (np.asarray(centres[-1]) - line))
            if s1 * s2 < 0 and min(abs(s1), abs(s2)) >= config.over_min_mm:
                out.append(Tacteme.AC_OVER)
    if c1 == ContactClass.AREA and c2 == ContactClass.LINE:
        out.append(Tacteme.AC_TO_LC)
        tol = config.edge_angle_tol_deg
        edges = len(history) >= 3 and history[-3][0] == ContactClass.LINE
        if edges and (wobbles_deg is None or max(wobbles_deg[-3], wobbles_deg[-1]) <= tol):
            d = float(axis_difference_deg(np.array([o2]), history[-3][1])[0])
            doubt = config.edge_angle_doubt_deg  # about 75 deg, between 60 and 90
            both = 0.0  # how far the grid can move the angle between the two edges
            if config.edge_angle_grid_sum and wobbles_deg is not None:
                both = wobbles_deg[-3] + wobbles_deg[-1]
            if d <= tol:
                if not _same_edge(history, centres, config.edge_apart_pitches * pitch_mm):
                    out.append(Tacteme.LC_AC_LC_SQUARE)
            elif d >= max(90.0 - tol, 75.0 + doubt, 60.0 + both):
                out.append(Tacteme.LC_AC_LC_SQUARE)
            elif abs(d - 60.0) <= tol and d <= min(75.0 - doubt, 90.0 - both):
                out.append(Tacteme.LC_AC_LC_TRIANGLE)
    return out


def _same_edge(
    history: list[tuple[int, float]],
    centres: list[tuple[float, float]] | None,
    apart_mm: float,
) -> bool:
    """Whether the last two edges of ``history`` (parallel) are less than ``apart_mm`` apart.

    The distance is across the first edge's axis, between the two lines'
    centres. False where it cannot be measured (no centres, ``apart_mm`` 0).
    """
    if centres is None or apart_mm <= 0.0 or len(centres) < 3:
        return False
    t = math.radians(history[-3][1])
    normal = np.array([-math.sin(t), math.cos(t)])
    across = float(normal @ (np.asarray(centres[-1]) - np.asarray(centres[-3])))
    return abs(across) < apart_mm
