"""The shape class of a held face (beyond paper 001): compact, elongated, triangular.

Paper 001's tactemes tell a face (AC) from an edge (LC) but never look at the
face's shape, so a triangular prism tipping over the edges of its rectangular
faces passes for a cube. Two numbers of Level 1, both invariant to the
face's position and yaw, give the shape class of an area contact:

* the elongation ``e = sqrt(lambda_max / lambda_min)``
  (:mod:`taxelkit.smart.moments`);
* the *triangularity* ``tau = 4 h^2 / (e A)``, with ``h = sqrt(3 lambda_max)``
  the half-length and ``A`` the area: the polar second moment of the contact,
  ``(lambda_max + lambda_min) / A``, over that of a rectangle with the same
  elongation, ``(1 + e^2) / (12 e)``. A rectangle (a square) gives exactly 1,
  a disc 0.955, a regular hexagon 0.962, an equilateral triangle 1.155, an
  isosceles triangle of height 1.4 x its base 1.15: a triangle puts more of
  its area far from its centre than the rectangle of its proportions.

Rules (thresholds in :class:`~taxelkit.smart.tactemes.TactemeConfig`, all on
values smoothed as the other Level 3 rules; only on an area segment, only
while the area stays within ``area_tolerance`` of its reference, as for "AC
moves", and only for faces of at least ``face_min_area_mm2`` (60 mm^2: smaller
discs of the jittered cylinders and cones read triangular now and then); held for
``face_hold_s``, 0.5 s):

=========================  ====================================================
AC compact                 ``e <= face_compact_max`` and ``tau <= face_symmetric_max``
AC elongated               ``e >= face_elongated_min`` and ``tau <= face_symmetric_max``
AC triangular              ``e <= face_compact_max`` and ``tau >= face_triangular_min``
AC elongated triangular    ``e >= face_elongated_min`` and ``tau >= face_triangular_min``
=========================  ====================================================

Between the limits lies a band of doubt that gives no tacteme. Measured on
the kinematic scenes of the six solids (Bonneville 16 x 16, noise on, faces
of 60 mm^2 or more): single frames, cube tau 0.97-1.03, discs of the round
bodies 0.96-1.05, tetrahedron 1.00-1.16 (median 1.08), elongation of all
these faces at most 1.47; the largest 3-frame mean over each held face, in
60 scenes each, cube 0.97-1.04 (210 faces), tetrahedron 1.02-1.16 (median
1.09). The taxel grid pulls a triangle's tau towards 1: a tetrahedron's face
of 25-45 taxels, at some positions and yaws, reads 1.00-1.02 for frames on
end and is called compact (3 of 40 scenes). A triangular face can therefore
produce the symmetric class of its elongation too. In 100 cube rolls with a
limit of 1.055 and no face hold, two faces read triangular (one lifting off,
one held at 1.05-1.09): hence 1.06 and the hold.

The elongated limit, 1.5, lies just above those faces' largest single-frame
elongation (1.47). The skin rounds a rectangle's corners: the hexagonal
prism's 6 x 11 mm sides (1.83 drawn) read 1.37-2.3, median 1.55, pressed at
48 placements, so with a limit of 1.6 a held side mostly read neither compact
nor elongated and its rolls stayed "cube, hexagonal prism or square pyramid".
Set on ``new-objects`` seed 3: hexagonal prisms identified 25 -> 62 of 100
(1.45: 81, too close to 1.47), wrong identities 0 -> 0; then measured on seed
0: 14 -> 61 and seed 11: 17 -> 66, wrong 0 -> 0, every other object
unchanged.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.tacteme_table import Tacteme

if TYPE_CHECKING:
    from taxelkit.smart.tacteme_config import TactemeConfig

__all__ = ["face_limits", "face_masks", "triangularity"]


def triangularity(
    area_mm2: NDArray[np.float64], elongation: NDArray[np.float64], half_mm: NDArray[np.float64]
) -> NDArray[np.float64]:
    """``tau = 4 h^2 / (e A)`` per frame (1 for a rectangle, 1.155 for an equilateral triangle).

    Parameters
    ----------
    area_mm2, elongation, half_mm : (n,) float
        Level 1 area (mm^2), elongation and half-length ``sqrt(3 lambda_max)`` (mm).

    Returns
    -------
    (n,) float
        NaN where the area is zero or not finite.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        tau = 4.0 * half_mm**2 / (elongation * area_mm2)
    out: NDArray[np.float64] = np.where(np.isfinite(tau), tau, np.nan)
    return out


def face_masks(
    area_mm2: NDArray[np.float64],
    elongation: NDArray[np.float64],
    tau: NDArray[np.float64],
    steady: NDArray[np.bool_],
    *,
    min_area_mm2: float,
    compact_max: float,
    elongated_min: float,
    symmetric_max: float,
    triangular_min: float,
) -> list[tuple[Tacteme, NDArray[np.bool_]]]:
    """Frames on which each face-shape class holds (before the hold is required).

    Parameters
    ----------
    area_mm2, elongation, tau : (n,) float
        Smoothed area, elongation and triangularity.
    steady : (n,) bool
        The area is near its reference (the face is held, not tipping).
    min_area_mm2, compact_max, elongated_min, symmetric_max, triangular_min : float
        The limits (see the module docstring).

    Returns
    -------
    list of (Tacteme, (n,) bool)
        In :data:`~taxelkit.smart.tacteme_table.FACE_TACTEMES` order.
    """
    ok = steady & (area_mm2 >= min_area_mm2)
    with np.errstate(invalid="ignore"):
        compact, long_ = elongation <= compact_max, elongation >= elongated_min
        sym, tri = tau <= symmetric_max, tau >= triangular_min
    return [
        (Tacteme.AC_COMPACT, ok & compact & sym),
        (Tacteme.AC_ELONGATED, ok & long_ & sym),
        (Tacteme.AC_TRIANGULAR, ok & compact & tri),
        (Tacteme.AC_ELONGATED_TRIANGULAR, ok & long_ & tri),
    ]


def face_limits(config: TactemeConfig) -> dict[str, float]:
    """The keyword limits of :func:`~taxelkit.smart.face_shapes.face_masks` from ``config``."""
    return {
        "min_area_mm2": config.face_min_area_mm2,
        "compact_max": config.face_compact_max,
        "elongated_min": config.face_elongated_min,
        "symmetric_max": config.face_symmetric_max,
        "triangular_min": config.face_triangular_min,
    }
