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
import itertools

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError, check_in_range
from taxelkit.smart.contact_network import (
    AREA_MAX_ELONGATION,
    AREA_MIN_AREA_MM2,
    DEFAULT_CONFIDENCE,
    HAND_SET,
    HIDDEN_SLOPE_PER_NEPER,
    LINE_MIN_AREA_MM2,
    LINE_MIN_ELONGATION,
    LINE_VOTE,
    OUTPUT_GAIN,
    POINT_MAX_AREA_MM2,
    REFERENCE_AREA_MM2,
    ContactNetwork,
    hand_set_network,
)
from taxelkit.smart.index_sums import product_rows
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
    return _inputs(f)


def _inputs(f: NDArray[np.float64]) -> NDArray[np.float64]:
    """:func:`network_inputs` of checked features (area > 0)."""
    x: NDArray[np.float64] = np.log(f / np.array([REFERENCE_AREA_MM2, 1.0]))
    return x


def _forward(
    net: ContactNetwork, x: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Hidden activations ``(N, H)`` and softmax outputs ``(N, 3)`` for inputs ``x``.

    The products run over pieces of rows small enough for one BLAS thread
    (:func:`~taxelkit.smart.index_sums.product_rows`), none of one row unless
    ``N`` is 1: NumPy multiplies a single row as a vector, with sums rounded
    otherwise, while a row's product in a matrix of rows is the same whatever
    the piece.
    """
    n, (k, hidden), out = x.shape[0], net.w_hidden.shape, net.w_output.shape[1]
    step = max(2, product_rows(max(k * hidden, hidden * out), 1, most=n))
    cuts = [*range(0, n, step), n]
    if len(cuts) > 2 and cuts[-1] - cuts[-2] == 1:
        cuts[-2] -= 1  # the last piece gets two rows
    h = np.empty((n, hidden))
    z = np.empty((n, out))
    for a, b in itertools.pairwise(cuts):
        h[a:b] = np.tanh(x[a:b] @ net.w_hidden + net.b_hidden)
        z[a:b] = h[a:b] @ net.w_output + net.b_output
    top = z[:, 0].copy()  # the largest output (exact, as z.max(axis=1), without a call per row)
    for k in range(1, z.shape[1]):
        np.maximum(top, z[:, k], out=top)
    z = z - top[:, None]
    e = np.exp(z)
    total = e[:, 0].copy()  # e.sum(axis=1): the same additions in the same order, column-wise
    for k in range(1, e.shape[1]):
        total += e[:, k]
    p: NDArray[np.float64] = e / total[:, None]
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
        p = _forward(network, _inputs(f[touched]))[1]  # checked above: no second check
        best = np.zeros(p.shape[0], np.intp)  # p.argmax(axis=1), a column at a time
        top = p[:, 0].copy()
        for k in range(1, p.shape[1]):
            more = p[:, k] > top  # the first of equal outputs wins, as argmax
            best[more] = k
            np.maximum(top, p[:, k], out=top)
        codes = np.asarray([int(c) for c in OUTPUT_CLASSES], dtype=np.int8)[best]
        sure = top > conf
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
