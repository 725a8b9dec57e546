"""Where a finished motion script touches the plate, and how it is fitted on the array.

Shared by the kinematic scripts (:mod:`taxelkit.motion.scenarios`,
:mod:`taxelkit.motion.mesh_scenarios`) and the physics-engine scenes: the
contact points of every frame in contact, the room each needs (a face ends at
its outline; a round body's point or line spreads by its patch half-width),
and the first yaw and shift that keep them all on the array.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from taxelkit import _fixed_order as fo
from taxelkit.motion.contact_truth import contact_state
from taxelkit.motion.rolling import E_Z
from taxelkit.world.pose import matrix_from_axis_angle
from taxelkit.world.solids import AnalyticSolid
from taxelkit.world.solids_round import Cone, Cylinder, Sphere, TruncatedCone

__all__ = [
    "EDGE_MARGIN_MM",
    "contact_bounds",
    "contact_xy",
    "fit_on_array",
    "patch_halfwidth_mm",
    "yawed",
]

#: Contact points stay this far inside the array edge, mm (about the skin's
#: 0.8 mm sag, assumed); points and lines of round bodies also their patch
#: half-width ``sqrt(2 rho d)``.
EDGE_MARGIN_MM = 1.0


def patch_halfwidth_mm(solid: AnalyticSolid, depth_mm: float) -> float:
    """Half-width ``sqrt(2 rho d)`` of a curved contact pressed ``d`` deep, ``rho`` its radius."""
    if isinstance(solid, Sphere | Cylinder):
        rho = float(solid.radius_mm)
    elif isinstance(solid, Cone):
        rho = math.hypot(solid.radius_mm, solid.height_mm) * solid.radius_mm / solid.height_mm
    elif isinstance(solid, TruncatedCone):
        big = max(solid.bottom_radius_mm, solid.top_radius_mm)
        slope = abs(solid.bottom_radius_mm - solid.top_radius_mm) / solid.height_mm
        rho = big * math.hypot(1.0, slope)
    else:
        return 0.0
    return math.sqrt(2.0 * rho * depth_mm)


def contact_xy(
    solid: AnalyticSolid,
    rots: NDArray[np.float64],
    cents: NDArray[np.float64],
    indent: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """xy of every contact point of the frames in contact, and the margin each needs, mm.

    A face's contact ends at its outline; a point or a line of a round body
    spreads by the patch half-width around it.
    """
    touch = indent > 0.0
    key = np.column_stack([rots.reshape(-1, 9), cents])[touch]
    _, first = np.unique(key, axis=0, return_index=True)  # held poses repeat
    rots_u, cents_u = rots[touch][first], cents[touch][first]
    state = contact_state(solid, rots_u)
    area = np.array([k == "area" for k in state.kinds])
    pts = state.relative_mm[..., :2] + cents_u[:, None, :2]
    depth = float(indent.max())
    margin = EDGE_MARGIN_MM + np.where(area, 0.0, patch_halfwidth_mm(solid, depth))
    sel = state.touching
    return pts[sel], np.broadcast_to(margin[:, None], sel.shape)[sel]


def contact_bounds(
    xy: NDArray[np.float64], margin: NDArray[np.float64], yaw: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Lower and upper xy corner of the contact points turned by ``yaw``, margins included."""
    c, s = math.cos(yaw), math.sin(yaw)
    turned = fo.matmul(xy, np.array([[c, s], [-s, c]]))
    low: NDArray[np.float64] = (turned - margin[:, None]).min(axis=0)
    high: NDArray[np.float64] = (turned + margin[:, None]).max(axis=0)
    return low, high


def fit_on_array(
    xy: NDArray[np.float64],
    margin: NDArray[np.float64],
    half_mm: NDArray[np.float64],
    shift_fraction: NDArray[np.float64],
    *,
    yaw: float = 0.0,
    tries: int = 8,
) -> tuple[float, NDArray[np.float64]] | None:
    """The first yaw (``yaw + k pi / tries``) that fits the contact on the array, and the shift.

    Parameters
    ----------
    xy : (N, 2) float, mm
        Contact points (:func:`contact_xy`).
    margin : (N,) float, mm
        The room each point needs around it.
    half_mm : (2,) float, mm
        Half the array's width and height.
    shift_fraction : (2,) float
        Where in the slack the contact goes, 0 (low edge) to 1 (high edge).
    yaw, tries
        The first yaw tried, rad, and how many are tried.

    Returns
    -------
    (turn, shift) or None
        The yaw, rad, and the xy shift, mm, to add after turning; None if no
        yaw tried fits.
    """
    for k in range(tries):
        turn = yaw + k * math.pi / tries
        low, high = contact_bounds(xy, margin, turn)
        slack = 2.0 * half_mm - (high - low)
        if np.all(slack >= 0.0):
            shift: NDArray[np.float64] = -half_mm - low + shift_fraction * slack
            return turn, shift
    return None


def yawed(
    rots: NDArray[np.float64], cents: NDArray[np.float64], yaw: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """A whole track turned about the vertical through the origin (physics is unchanged)."""
    z = matrix_from_axis_angle(E_Z, yaw)
    return fo.matmul(z, rots), fo.rotate_points(cents, z)
