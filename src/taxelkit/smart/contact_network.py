"""The Level 2 network of the smart sensor: :class:`ContactNetwork` and its hand-set weights.

A 2 -> H -> 3 network over ``(ln area, ln elongation)``; :func:`hand_set_network`
builds paper 001's decision regions from named area and elongation limits
(the constants below). :mod:`taxelkit.smart.contact_classes` applies it to
contact images; :mod:`taxelkit.smart.contact_training` trains one on frames.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from taxelkit._arrays import readonly_copy
from taxelkit.errors import InputError, check_positive

__all__ = [
    "AREA_MAX_ELONGATION",
    "AREA_MIN_AREA_MM2",
    "DEFAULT_CONFIDENCE",
    "HAND_SET",
    "HIDDEN_SLOPE_PER_NEPER",
    "LINE_MIN_AREA_MM2",
    "LINE_MIN_ELONGATION",
    "LINE_VOTE",
    "OUTPUT_GAIN",
    "POINT_MAX_AREA_MM2",
    "REFERENCE_AREA_MM2",
    "ContactNetwork",
    "hand_set_network",
]

#: Unit of the area feature, mm^2: the network sees ``ln(area / 1 mm^2)``.
REFERENCE_AREA_MM2 = 1.0

#: Largest area of a point contact, mm^2: simulated vertices, apexes and small
#: spheres on the Bonneville array light at most a 2 x 2 block (12.4 mm^2);
#: 14 mm^2 sits between 4 and 5 taxels (12.4 and 15.5 mm^2).
POINT_MAX_AREA_MM2 = 14.0
#: Smallest area of a line contact, mm^2: between 2 and 3 taxels (6.2 and
#: 9.3 mm^2), so a line needs three taxels and a diagonal pair is not a line.
LINE_MIN_AREA_MM2 = 8.0
#: Smallest area of an area contact, mm^2: between 6 and 7 taxels (18.6 and
#: 21.7 mm^2); the smallest simulated faces (6 mm cube, 3 mm radius cylinder
#: end) light 7 or more.
AREA_MIN_AREA_MM2 = 20.0
#: Smallest elongation of a line contact (dimensionless): between a 1 x 2 pair
#: (2) and a 1 x 3 line (3); simulated cylinder sides and edges mostly exceed it.
LINE_MIN_ELONGATION = 2.5
#: Largest elongation of an area contact (dimensionless): simulated faces stay
#: below 1.6 (a disc or square on the grid); 1.8 leaves room for noise.
AREA_MAX_ELONGATION = 1.8
#: Steepness of the hidden half-plane detectors, per neper of area or
#: elongation: ``tanh(20 ln(A / A0))`` is +-0.76 at 5 % from the threshold and
#: +-0.96 at 10 %, while one taxel more or less changes the area by 20-25 %
#: near the thresholds and the elongation of common shapes moves in similar
#: steps; the regions then end within 4 % of the named thresholds.
HIDDEN_SLOPE_PER_NEPER = 20.0
#: Output gain ``g``: a class logit is ``g`` inside its region and ``<= -g``
#: elsewhere, so a clear case has probability ``>= 1 / (1 + 2 e^(-2 g))``,
#: 0.995 for ``g = 3``.
OUTPUT_GAIN = 3.0
#: Weight of each of the line's two detectors, in units of ``g``: the line
#: logit is ``g (1.5 h2 + 1.5 h4 - 1)``, ``2 g`` for an elongated contact of
#: three taxels or more, which outvotes the point logit (``g`` while the
#: contact is below ``POINT_MAX_AREA_MM2``) by ``g``: a 1 x 3 line is a line
#: with probability ``1 / (1 + e^(-g)) = 0.95``. With only one detector on,
#: the logit is ``-g``, the same as the other losing classes.
LINE_VOTE = 1.5
#: Default confidence: the largest output must exceed it for a class; below,
#: the image is indeterminate. Between the two-way tie of the band (0.5) and
#: the 0.995 of a clear case.
DEFAULT_CONFIDENCE = 0.7

_N_OUT = 3


@dataclass(frozen=True, eq=False)
class ContactNetwork:
    """A 2 -> H -> 3 network over scaled (area, elongation).

    Parameters
    ----------
    w_hidden : (2, H) float
        Input-to-hidden weights, per neper of area (row 0) and of elongation
        (row 1).
    b_hidden : (H,) float
        Hidden biases.
    w_output : (H, 3) float
        Hidden-to-output weights; columns in :data:`OUTPUT_CLASSES` order.
    b_output : (3,) float
        Output biases.
    name : str
        Where the weights came from (``"hand-set"``, ``"trained"``, ...).

    Raises
    ------
    InputError
        On inconsistent shapes or non-finite weights.
    """

    w_hidden: NDArray[np.float64]
    b_hidden: NDArray[np.float64]
    w_output: NDArray[np.float64]
    b_output: NDArray[np.float64]
    name: str = ""

    def __post_init__(self) -> None:
        w1 = np.asarray(self.w_hidden, dtype=np.float64)
        if w1.ndim != 2 or w1.shape[0] != 2 or w1.shape[1] < 1:
            raise InputError(f"w_hidden must have shape (2, H) with H >= 1, got {w1.shape}")
        h = w1.shape[1]
        expected = {"b_hidden": (h,), "w_output": (h, _N_OUT), "b_output": (_N_OUT,)}
        for name, shape in expected.items():
            got = np.shape(getattr(self, name))
            if got != shape:
                raise InputError(f"{name} must have shape {shape}, got {got}")
        for name in ("w_hidden", "b_hidden", "w_output", "b_output"):
            value = readonly_copy(getattr(self, name), np.float64)
            if not np.all(np.isfinite(value)):
                raise InputError(f"{name} must be finite, got NaN/Inf")
            object.__setattr__(self, name, value)

    @property
    def hidden_units(self) -> int:
        """Number of hidden units ``H``."""
        return int(self.w_hidden.shape[1])


def hand_set_network(
    *,
    point_max_area_mm2: float = POINT_MAX_AREA_MM2,
    line_min_area_mm2: float = LINE_MIN_AREA_MM2,
    area_min_area_mm2: float = AREA_MIN_AREA_MM2,
    line_min_elongation: float = LINE_MIN_ELONGATION,
    area_max_elongation: float = AREA_MAX_ELONGATION,
    slope_per_neper: float = HIDDEN_SLOPE_PER_NEPER,
    output_gain: float = OUTPUT_GAIN,
) -> ContactNetwork:
    """The network with weights set by hand from the class boundaries.

    Five hidden units, each a half-plane detector ``tanh(s ln(q / q0))`` on one
    feature ``q`` (area or elongation) with threshold ``q0``:

    ======  ===========================  =====================
    unit    +1 when                      threshold
    ======  ===========================  =====================
    h0      area > point_max_area        14 mm^2
    h1      area > area_min_area         20 mm^2
    h2      elongation > line_min        2.5
    h3      elongation > area_max        1.8
    h4      area > line_min_area         8 mm^2
    ======  ===========================  =====================

    and three output logits (``g`` = ``output_gain``, ``v`` = :data:`LINE_VOTE`):

    * ``point = -g h0``: ``+g`` while the contact is small;
    * ``line = g (v h2 + v h4 - 1)``: ``2 g`` when elongated *and* of three
      taxels or more, ``<= -g`` otherwise; it outvotes the point logit for a
      short line (a 1 x 3 line is a line, a diagonal pair a point);
    * ``area = g (h1 - h3 - 1)``: ``+g`` when large *and* compact, ``<= -g``
      otherwise.

    With the orderings below, every combination of saturated detectors has a
    single winner by ``>= g`` (point, line or area region), or a tie of two or
    three logits at ``-g`` (the indeterminate band, where no output exceeds
    1/2). Near a threshold the detectors are soft and the winner's margin
    shrinks; ``confidence`` then widens the band.

    Parameters
    ----------
    point_max_area_mm2 : float, mm^2
        Point contacts are smaller.
    line_min_area_mm2 : float, mm^2
        Line contacts are larger; ``< point_max_area_mm2``.
    area_min_area_mm2 : float, mm^2
        Area contacts are larger; ``> point_max_area_mm2``.
    line_min_elongation : float
        Line contacts are more elongated.
    area_max_elongation : float
        Area (and point) contacts' compactness limit; ``1 <= ... <
        line_min_elongation``.
    slope_per_neper : float
        Hidden-unit steepness ``s``, 1/neper.
    output_gain : float
        Output gain ``g``.

    Returns
    -------
    ContactNetwork
        ``H = 5``.

    Raises
    ------
    InputError
        If a value is not positive or the orderings are violated.

    References
    ----------
    Paper 001, Section 3, Level 2 ("the weights ... were calculated by hand").
    """
    areas = _check_area_order(point_max_area_mm2, line_min_area_mm2, area_min_area_mm2)
    elongations = _check_elongation_order(line_min_elongation, area_max_elongation)
    s = check_positive("slope_per_neper", slope_per_neper)
    g = check_positive("output_gain", output_gain)
    w_hidden, b_hidden = _hand_set_hidden(areas, elongations, s)
    return ContactNetwork(w_hidden, b_hidden, *_hand_set_output(g), name="hand-set")


def _check_area_order(
    point_max_area_mm2: float, line_min_area_mm2: float, area_min_area_mm2: float
) -> tuple[float, float, float]:
    """``(point_max, line_min, area_min)`` areas, positive and in the order the network needs."""
    a_pt = check_positive("point_max_area_mm2", point_max_area_mm2)
    a_ln = check_positive("line_min_area_mm2", line_min_area_mm2)
    a_ar = check_positive("area_min_area_mm2", area_min_area_mm2)
    if not a_ln < a_pt < a_ar:
        raise InputError(
            "areas must satisfy line_min_area_mm2 < point_max_area_mm2 < area_min_area_mm2, "
            f"got {a_ln!r}, {a_pt!r}, {a_ar!r}"
        )
    return a_pt, a_ln, a_ar


def _check_elongation_order(
    line_min_elongation: float, area_max_elongation: float
) -> tuple[float, float]:
    """``(line_min, area_max)`` elongations, positive and in the order the network needs."""
    e_ln = check_positive("line_min_elongation", line_min_elongation)
    e_ar = check_positive("area_max_elongation", area_max_elongation)
    if not 1.0 <= e_ar < e_ln:
        raise InputError(
            "elongations must satisfy 1 <= area_max_elongation < line_min_elongation, "
            f"got {e_ar!r}, {e_ln!r}"
        )
    return e_ln, e_ar


def _hand_set_hidden(
    areas: tuple[float, float, float], elongations: tuple[float, float], s: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Hidden weights ``(2, 5)`` and biases ``(5,)`` of the detectors h0..h4 (see above)."""
    a_pt, a_ln, a_ar = areas
    e_ln, e_ar = elongations
    ref = math.log(REFERENCE_AREA_MM2)
    # columns: h0 area>pt, h1 area>ar, h2 elong>ln, h3 elong>ar, h4 area>ln
    w_hidden = s * np.array([[1.0, 1.0, 0.0, 0.0, 1.0], [0.0, 0.0, 1.0, 1.0, 0.0]])
    b_hidden = -s * np.array(
        [
            math.log(a_pt) - ref,
            math.log(a_ar) - ref,
            math.log(e_ln),
            math.log(e_ar),
            math.log(a_ln) - ref,
        ]
    )
    return w_hidden, b_hidden


def _hand_set_output(g: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Output weights ``(5, 3)`` and biases ``(3,)``: the point, line and area logits."""
    # rows: hidden units; columns: point, line, area
    v = LINE_VOTE
    w_output = g * np.array(
        [
            [-1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, v, 0.0],
            [0.0, 0.0, -1.0],
            [0.0, v, 0.0],
        ]
    )
    b_output = g * np.array([0.0, -1.0, -1.0])
    return w_output, b_output


#: The hand-set network with the default thresholds (Bonneville 16 x 16 scale).
HAND_SET = hand_set_network()
