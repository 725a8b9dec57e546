"""Level 2 of the smart tactile sensor: contact classes from area and elongation.

Paper 001 (Section 3, Level 2) classifies each binary tactile image as *none*
(``m00 = 0``), *point*, *line*, *area* or *indeterminate*. A three-layer
neural network partitions the plane of (area, elongation) into point, line
and area regions separated by an indeterminate band (Figure 3 of the paper,
lost in the OCR copy and reconstructed here). The paper set the weights by
hand from measured contacts and notes that they could be learnt by
back-propagation; both are provided.

The network
-----------
``features = (area_mm2, elongation)`` (from :class:`~taxelkit.smart.moments.ImageStats`)
are first scaled to ``x = (ln(area / 1 mm^2), ln(elongation))``: logarithms
because the classes differ by *ratios* (a line is 2.5 times longer than wide,
an area several times a point's), and physical mm^2 rather than taxel counts
so that the same weights describe the same contact on any sensor whose pitch
resolves it. Then

* input layer: the 2 scaled features;
* hidden layer: ``h = tanh(x @ w_hidden + b_hidden)``, ``H`` units; each unit
  is a soft half-plane detector (+1 on one side of a line in the ``x`` plane,
  -1 on the other);
* output layer: ``p = softmax(h @ w_output + b_output)``, 3 units for point,
  line and area (in that order, :data:`OUTPUT_CLASSES`).

An image is assigned the class of the largest output when that output
exceeds ``confidence``; otherwise it is *indeterminate*. The hand-set weights
(:func:`hand_set_network`) give the winning class a logit at least ``g`` above
the others inside its region; in the band between the regions two or three
logits tie at the maximum, so no output exceeds 1/2 there and the band is
indeterminate for any ``confidence >= 0.5``.

Training by back-propagation lives in :mod:`taxelkit.smart.contact_training`.

The reconstructed partition (Figure 3)
--------------------------------------
Measured on the simulated Bonneville array (``taxelkit.motion.contact_samples``,
1.7625 mm pitch, one taxel = 3.11 mm^2): a point contact (sphere, vertex,
apex) lights 1 to 4 taxels (a 2 x 2 block when it sits on a taxel corner,
elongation at most 2 for a pair), up to 12.4 mm^2; the smallest flat faces
light 7 or more (>= 21.7 mm^2) with elongation <= 1.6; line contacts
(cylinder side, cube and tetrahedron edges) light three or more taxels with
elongation mostly above 2.5 (deep presses of thick cylinders and of edges
widen to elongation 1.8-2.5, which the band leaves indeterminate: 1-3 % of the
simulated lines). Hence, with soft boundaries:

* **point**: area < 14 mm^2, unless it is a line;
* **line**: elongation > 2.5 and area > 8 mm^2 (three taxels in a row; a
  diagonal pair, elongation sqrt(7) = 2.65 but 6.2 mm^2, stays a point);
* **area**: area > 20 mm^2 and elongation < 1.8;
* **indeterminate**: the rest - compact contacts of 14-20 mm^2, large ones of
  elongation 1.8-2.5.

The thresholds are the midpoints of soft detectors. At the default
confidence 0.7 the regions of :data:`HAND_SET` end at: point up to 14.4 mm^2;
area from 19.5 mm^2 and up to elongation 1.85; line from elongation 2.40
(2.57 just above 8 mm^2) and from 8.2 mm^2. Where the band is narrow in both
directions (near 17 mm^2 and elongation 2.1) the soft detectors let one output
reach 0.50, never more.

References
----------
Paper 001, Section 3, Level 2 and Figure 3.
"""

from __future__ import annotations

import enum
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit._arrays import readonly_copy
from taxelkit.errors import InputError, check_in_range, check_positive
from taxelkit.smart.moments import ImageStats

__all__ = [
    "AREA_MAX_ELONGATION",
    "AREA_MIN_AREA_MM2",
    "DEFAULT_CONFIDENCE",
    "HAND_SET",
    "HIDDEN_SLOPE_PER_NEPER",
    "LINE_MIN_AREA_MM2",
    "LINE_MIN_ELONGATION",
    "LINE_VOTE",
    "OUTPUT_CLASSES",
    "OUTPUT_GAIN",
    "POINT_MAX_AREA_MM2",
    "REFERENCE_AREA_MM2",
    "ContactClass",
    "ContactNetwork",
    "classify_contacts",
    "classify_features",
    "contact_features",
    "contact_probabilities",
    "hand_set_network",
    "network_inputs",
]


class ContactClass(enum.IntEnum):
    """Contact type of one tactile image (paper 001, Level 2).

    The integer codes are what the vectorised functions return (int8 arrays).
    """

    #: No taxel in contact (``m00 = 0``).
    NONE = 0
    #: In contact, but no class is confident (the band between the regions).
    INDETERMINATE = 1
    #: A vertex, apex, rim point or small sphere: small and compact.
    POINT = 2
    #: An edge or a generator of a round body: elongated.
    LINE = 3
    #: A flat face: large and compact.
    AREA = 4


#: The classes of the network's three outputs, in output order.
OUTPUT_CLASSES: tuple[ContactClass, ContactClass, ContactClass] = (
    ContactClass.POINT,
    ContactClass.LINE,
    ContactClass.AREA,
)

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


def contact_features(stats: ImageStats) -> NDArray[np.float64]:
    """The Level 2 features of every frame: ``(area_mm2, elongation)``.

    Parameters
    ----------
    stats : ImageStats

    Returns
    -------
    (T, 2) float
        Area, mm^2, and elongation (NaN for empty frames).
    """
    return np.column_stack([stats.area_mm2, stats.elongation])


def _check_features(features: ArrayLike) -> NDArray[np.float64]:
    f = np.asarray(features, dtype=np.float64)
    if f.ndim != 2 or f.shape[1] != 2:
        raise InputError(f"features must have shape (N, 2) (area_mm2, elongation), got {f.shape}")
    area, elong = f[:, 0], f[:, 1]
    if np.any(~np.isfinite(area)) or np.any(area < 0):
        raise InputError("features[:, 0] (area_mm2) must be finite and >= 0")
    touched = area > 0
    bad = touched & ~(np.isfinite(elong) & (elong >= 1.0))
    if np.any(bad):
        k = int(np.argmax(bad))
        raise InputError(
            f"features[:, 1] (elongation) must be finite and >= 1 where area > 0, "
            f"got {elong[k]!r} at row {k}"
        )
    return f


def network_inputs(features: ArrayLike) -> NDArray[np.float64]:
    """The network's scaled inputs ``(ln(area / 1 mm^2), ln(elongation))``.

    Parameters
    ----------
    features : (N, 2) float
        ``(area_mm2, elongation)`` of contacts (area > 0, elongation >= 1).

    Returns
    -------
    (N, 2) float, neper

    Raises
    ------
    InputError
        On a wrong shape, an area <= 0 or an elongation < 1.
    """
    f = _check_features(features)
    if np.any(f[:, 0] <= 0):
        raise InputError("features[:, 0] (area_mm2) must be > 0 for network inputs")
    x: NDArray[np.float64] = np.log(f / np.array([REFERENCE_AREA_MM2, 1.0]))
    return x


def _forward(
    net: ContactNetwork, x: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Hidden activations ``(N, H)`` and softmax outputs ``(N, 3)`` for inputs ``x``."""
    h = np.tanh(x @ net.w_hidden + net.b_hidden)
    z = h @ net.w_output + net.b_output
    z = z - z.max(axis=1, keepdims=True)
    e = np.exp(z)
    p: NDArray[np.float64] = e / e.sum(axis=1, keepdims=True)
    return h, p


def contact_probabilities(
    features: ArrayLike, network: ContactNetwork = HAND_SET
) -> NDArray[np.float64]:
    """Softmax outputs (point, line, area) of the network for contacts.

    Parameters
    ----------
    features : (N, 2) float
        ``(area_mm2, elongation)``, area > 0.
    network : ContactNetwork

    Returns
    -------
    (N, 3) float
        Rows sum to 1; columns in :data:`OUTPUT_CLASSES` order.
    """
    return _forward(network, network_inputs(features))[1]


def classify_features(
    features: ArrayLike,
    network: ContactNetwork = HAND_SET,
    *,
    confidence: float = DEFAULT_CONFIDENCE,
) -> NDArray[np.int8]:
    """Contact class codes of ``(area_mm2, elongation)`` pairs, vectorised.

    Parameters
    ----------
    features : (N, 2) float
        Area, mm^2 (0 = no contact, elongation then ignored), and elongation.
    network : ContactNetwork
    confidence : float in [0, 1]
        The largest output must exceed it; otherwise INDETERMINATE. 0 always
        takes the largest output.

    Returns
    -------
    (N,) int8
        :class:`ContactClass` codes.

    Raises
    ------
    InputError
        On bad features or confidence.
    """
    conf = check_in_range("confidence", confidence, 0.0, 1.0)
    f = _check_features(features)
    out = np.full(f.shape[0], int(ContactClass.NONE), dtype=np.int8)
    touched = f[:, 0] > 0
    if np.any(touched):
        p = contact_probabilities(f[touched], network)
        best = p.argmax(axis=1)
        codes = np.asarray([int(c) for c in OUTPUT_CLASSES], dtype=np.int8)[best]
        sure = p[np.arange(best.size), best] > conf
        out[touched] = np.where(sure, codes, np.int8(ContactClass.INDETERMINATE))
    return out


def classify_contacts(
    stats: ImageStats,
    network: ContactNetwork = HAND_SET,
    *,
    confidence: float = DEFAULT_CONFIDENCE,
) -> NDArray[np.int8]:
    """Level 2 contact class of every frame (paper 001).

    Parameters
    ----------
    stats : ImageStats
        Level 1 statistics of ``T`` frames.
    network : ContactNetwork
        :data:`HAND_SET` by default, or a trained network.
    confidence : float in [0, 1]
        See :func:`classify_features`.

    Returns
    -------
    (T,) int8
        :class:`ContactClass` codes: NONE where ``m00 = 0``.

    References
    ----------
    Paper 001, Section 3, Level 2.

    Examples
    --------
    >>> from taxelkit.smart.moments import image_stats
    >>> img = np.zeros((3, 16, 16), bool)
    >>> img[1, 8, 8] = True
    >>> img[2, 4:9, 4:9] = True
    >>> codes = classify_contacts(image_stats(img, pitch_mm=1.7625))
    >>> [ContactClass(c).name for c in codes]
    ['NONE', 'POINT', 'AREA']
    """
    return classify_features(contact_features(stats), network, confidence=confidence)
