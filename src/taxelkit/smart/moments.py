"""Level 1 of the smart tactile sensor: statistics of binary contact images.

Paper 001 (Section 3, Level 1) thresholds every tactile image at a fixed level
(``tau_ij = 1`` where taxel ``(i, j)`` touches the object) and describes the
contact by its moments of area ``m_pq``: the area ``m00``, the centre of area
``(m10 / m00, m01 / m00)``, the orientation of the axis of minimum second
moment and the elongation (aspect ratio of the contact).

Conventions
-----------
* **Coordinates** follow :mod:`taxelkit.sensors.array_geometry`: taxel
  ``(i, j)`` (row ``i``, column ``j``) is centred at ``x = (j - (cols - 1) / 2)
  * pitch``, ``y = (i - (rows - 1) / 2) * pitch`` mm, relative to the array
  centre; x runs along the columns, y along the rows.
* **Taxels are unit cells.** The contact region is the union of the
  ``pitch x pitch`` squares of the taxels in contact, and ``m_pq`` is its
  moment of area, ``m_pq = integral of x^p y^q dx dy`` over that region
  (mm^(2 + p + q)). For ``p + q <= 1`` this equals the sum over taxel centres
  times ``pitch^2``; each second moment gains the cell's own term ``pitch^2 /
  12`` per unit area (``m20`` and ``m02``, not ``m11``). The cell term is what
  keeps the elongation finite for a single taxel (elongation 1) and for a line
  one taxel wide (a ``k x 1`` line has elongation exactly ``k``; an ``a x b``
  rectangle has exactly ``a / b``).
* **Orientation** is the angle of the axis of minimum second moment (the long
  axis), counter-clockwise from +x towards +y, in degrees in ``(-90, 90]``:
  ``theta = 0.5 atan2(2 mu11, mu20 - mu02)``. A line along the columns has
  0 deg, along the rows 90 deg, along ``x = y`` 45 deg. When the second-moment
  matrix is isotropic (``mu20 == mu02`` and ``mu11 == 0``: a single taxel, a
  square, a symmetric disc; elongation exactly 1) the axis is undefined and
  ``atan2(0, 0) = 0`` gives 0 deg.
* **Elongation** is ``sqrt(lambda_max / lambda_min)`` of the central
  second-moment matrix (cell term included), the ratio of the long to the
  short side of the rectangle (or ellipse) with the same second moments.
  Dimensionless, ``>= 1``; it does not depend on the pitch.
* **Empty frames** (no taxel in contact, ``m00 = 0``): area 0 and
  ``n_taxels`` 0; centre, orientation, elongation and the second moments are
  NaN.

Every statistic is computed for all frames at once with matrix products
against coordinate vectors. The sums are taken in centred *index* units (half
integers), where binary images give sums that are exact in float64; only the
final scaling by the pitch rounds. The results therefore do not depend on how
frames are batched: :func:`frame_stats` on one frame returns bit-for-bit the
numbers :func:`image_stats` returns for that frame in a recording.

References
----------
Paper 001, Section 3, Level 1 (moments of area, Eq. 1-3; centre of area,
axis of minimum moment of inertia, elongation); B. K. P. Horn, *Robot Vision*
(MIT Press, 1986), Ch. 3 (binary images: area, position, orientation).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit._arrays import readonly_copy
from taxelkit.errors import InputError, check_finite_array, check_ndim, check_positive
from taxelkit.frames import TactileFrames
from taxelkit.smart.index_sums import index_sums

__all__ = [
    "CELL_SECOND_MOMENT",
    "FrameStats",
    "ImageStats",
    "binary_images",
    "check_images",
    "frame_stats",
    "image_stats",
]

#: Second moment of a unit cell about its own centre per unit area,
#: ``integral of x^2 over [-1/2, 1/2] = 1/12`` (in pitch^2): the term each taxel,
#: taken as a ``pitch x pitch`` square, adds to ``mu20 / m00`` and ``mu02 / m00``.
CELL_SECOND_MOMENT = 1.0 / 12.0


def binary_images(frames: ArrayLike, threshold: float | None = None) -> NDArray[np.bool_]:
    """Binary contact images ``tau = frames > threshold``; bool frames pass through.

    Parameters
    ----------
    frames : (..., rows, cols) bool or float
        Contact images (bool, returned as they are) or taxel displacements in
        any unit (mm for the simulator).
    threshold : float, optional
        Fixed contact threshold in the unit of ``frames`` (paper 001, Level 1);
        a taxel is in contact where its value is strictly greater. Required
        for numeric frames, ignored for bool frames.

    Returns
    -------
    (..., rows, cols) bool
        ``True`` where a taxel is in contact.

    Raises
    ------
    InputError
        If ``frames`` has fewer than 2 dimensions, is not bool or numeric,
        holds NaN/Inf, or is numeric with ``threshold`` missing or not finite.

    Examples
    --------
    >>> binary_images([[0.0, 0.05], [0.02, 0.1]], 0.03).astype(int).tolist()
    [[0, 1], [0, 1]]
    """
    f = np.asarray(frames)
    if f.ndim < 2:
        raise InputError(
            f"frames must have shape (..., rows, cols) (>= 2 dimensions), got shape {f.shape}"
        )
    if f.dtype == np.bool_:
        return f
    if f.dtype.kind not in "iuf":
        raise InputError(f"frames must be bool or numeric, got dtype {f.dtype}")
    if threshold is None:
        raise InputError("threshold must be a finite number for numeric frames, got None")
    try:
        thr = float(threshold)
    except (TypeError, ValueError):
        raise InputError(f"threshold must be a finite number, got {threshold!r}") from None
    if not np.isfinite(thr):
        raise InputError(f"threshold must be a finite number, got {threshold!r}")
    check_finite_array("frames", f)
    # in float64, as the chunked and per-track paths: a float32 taxel at the threshold's
    # float32 value (a flat face pressed exactly the threshold deep) is above it
    return np.asarray(np.asarray(f, dtype=np.float64) > thr)


def check_images(frames: ArrayLike, threshold: float | None) -> NDArray[np.bool_]:
    """``(T, rows, cols)`` frames as binary images (:func:`binary_images`), checked for shape."""
    f = np.asarray(frames)
    check_ndim("frames", f, 3, "(T, rows, cols)")
    return binary_images(f, threshold)


@dataclass(frozen=True)
class FrameStats:
    """Level 1 statistics of one contact image (see :class:`ImageStats`).

    Parameters
    ----------
    n_taxels : int
        Taxels in contact.
    area_mm2 : float
        Area of contact ``m00``, mm^2.
    centre_mm : tuple of float
        Centre of area ``(x, y)``, mm (NaN when empty).
    orientation_deg : float
        Axis of minimum second moment, deg in ``(-90, 90]`` (NaN when empty).
    elongation : float
        Aspect ratio ``>= 1`` (NaN when empty).
    var_x_mm2, var_y_mm2, cov_xy_mm2 : float
        Central second moments per unit area, ``mu20 / m00``, ``mu02 / m00``,
        ``mu11 / m00``, mm^2 (NaN when empty).
    """

    n_taxels: int
    area_mm2: float
    centre_mm: tuple[float, float]
    orientation_deg: float
    elongation: float
    var_x_mm2: float
    var_y_mm2: float
    cov_xy_mm2: float

    @property
    def is_empty(self) -> bool:
        """True when no taxel is in contact."""
        return self.n_taxels == 0


@dataclass(frozen=True, eq=False)
class ImageStats:
    """Level 1 statistics of a sequence of contact images, one entry per frame.

    Parameters
    ----------
    pitch_mm : float
        Taxel pitch used for the physical units, mm.
    n_taxels : (T,) int
        Taxels in contact in each frame.
    area_mm2 : (T,) float, mm^2
        Area of contact ``m00 = n_taxels * pitch^2``.
    centre_mm : (T, 2) float, mm
        Centre of area ``(m10 / m00, m01 / m00)`` as ``(x, y)`` relative to the
        array centre; NaN for empty frames.
    orientation_deg : (T,) float, deg
        Axis of minimum second moment in ``(-90, 90]``, counter-clockwise from
        +x; 0 for isotropic contacts; NaN for empty frames.
    elongation : (T,) float
        ``sqrt(lambda_max / lambda_min)`` of the second-moment matrix, ``>= 1``;
        NaN for empty frames.
    var_x_mm2, var_y_mm2, cov_xy_mm2 : (T,) float, mm^2
        ``mu20 / m00``, ``mu02 / m00``, ``mu11 / m00`` (cell term included);
        NaN for empty frames.

    Notes
    -----
    Built by :func:`image_stats`. Arrays are copied and made read-only.
    """

    pitch_mm: float
    n_taxels: NDArray[np.int64]
    area_mm2: NDArray[np.float64]
    centre_mm: NDArray[np.float64]
    orientation_deg: NDArray[np.float64]
    elongation: NDArray[np.float64]
    var_x_mm2: NDArray[np.float64]
    var_y_mm2: NDArray[np.float64]
    cov_xy_mm2: NDArray[np.float64]

    def __post_init__(self) -> None:
        check_positive("pitch_mm", self.pitch_mm)
        n = np.asarray(self.n_taxels).shape
        if len(n) != 1:
            raise InputError(f"n_taxels must have shape (T,), got {n}")
        for name in (
            "n_taxels",
            "area_mm2",
            "orientation_deg",
            "elongation",
            "var_x_mm2",
            "var_y_mm2",
            "cov_xy_mm2",
        ):
            value = np.asarray(getattr(self, name))
            if value.shape != n:
                raise InputError(f"{name} must have shape {n}, got {value.shape}")
            object.__setattr__(self, name, readonly_copy(value))
        centre = np.asarray(self.centre_mm)
        if centre.shape != (*n, 2):
            raise InputError(f"centre_mm must have shape ({n[0]}, 2), got {centre.shape}")
        object.__setattr__(self, "centre_mm", readonly_copy(centre))

    @property
    def n_frames(self) -> int:
        """Number of frames ``T``."""
        return int(self.n_taxels.shape[0])

    def __len__(self) -> int:
        return self.n_frames

    @property
    def is_empty(self) -> NDArray[np.bool_]:
        """(T,) bool: frames with no taxel in contact (``m00 = 0``)."""
        return np.asarray(self.n_taxels == 0)

    def frame(self, t: int) -> FrameStats:
        """The statistics of frame ``t`` as scalars.

        Raises
        ------
        InputError
            If ``t`` is not a valid frame index.
        """
        if not -self.n_frames <= int(t) < self.n_frames:
            raise InputError(f"t must be in [0, {self.n_frames - 1}], got {t!r}")
        k = int(t)
        return FrameStats(
            n_taxels=int(self.n_taxels[k]),
            area_mm2=float(self.area_mm2[k]),
            centre_mm=(float(self.centre_mm[k, 0]), float(self.centre_mm[k, 1])),
            orientation_deg=float(self.orientation_deg[k]),
            elongation=float(self.elongation[k]),
            var_x_mm2=float(self.var_x_mm2[k]),
            var_y_mm2=float(self.var_y_mm2[k]),
            cov_xy_mm2=float(self.cov_xy_mm2[k]),
        )


def _fresh_stats(**fields: Any) -> ImageStats:
    """An :class:`ImageStats` of arrays just computed here (valid, owned by no one else).

    They are made read-only in place rather than copied, as ``__post_init__`` does.
    """
    out: ImageStats = object.__new__(ImageStats)
    for name, value in fields.items():
        if isinstance(value, np.ndarray):
            value.setflags(write=False)
        object.__setattr__(out, name, value)
    return out


def _stats_from_sums(sums: NDArray[np.float64], pitch: float) -> ImageStats:
    """Elementwise finish: physical statistics from the exact index sums."""
    n, su, sv, suu, svv, suv = sums
    filled = n > 0
    nn = np.where(filled, n, 1.0)
    nan = np.nan
    # central second moments per unit area, pitch units; the numerators
    # n * sum u^2 - (sum u)^2 are exact (multiples of 1/16) up to ~360 x 360
    # taxels; beyond, they round, but identically in any batch
    cuu = (nn * suu - su * su) / (nn * nn) + CELL_SECOND_MOMENT
    cvv = (nn * svv - sv * sv) / (nn * nn) + CELL_SECOND_MOMENT
    cuv = (nn * suv - su * sv) / (nn * nn)
    half_diff = 0.5 * (cuu - cvv)
    radius = np.hypot(half_diff, cuv)
    lam_max = 0.5 * (cuu + cvv) + radius
    lam_min = (cuu * cvv - cuv * cuv) / lam_max  # det / lambda_max: no cancellation
    elongation = np.sqrt(np.maximum(lam_max / lam_min, 1.0))  # >= 1 despite rounding
    theta = 0.5 * np.degrees(np.arctan2(2.0 * cuv, cuu - cvv))
    theta = np.where(theta <= -90.0, theta + 180.0, theta)
    p2 = pitch * pitch
    centre = np.stack([su / nn * pitch, sv / nn * pitch], axis=-1)
    return _fresh_stats(
        pitch_mm=pitch,
        n_taxels=n.astype(np.int64),
        area_mm2=n * p2,
        centre_mm=np.where(filled[:, None], centre, nan),
        orientation_deg=np.where(filled, theta, nan),
        elongation=np.where(filled, elongation, nan),
        var_x_mm2=np.where(filled, cuu * p2, nan),
        var_y_mm2=np.where(filled, cvv * p2, nan),
        cov_xy_mm2=np.where(filled, cuv * p2, nan),
    )


def image_stats(
    frames: TactileFrames | ArrayLike,
    *,
    pitch_mm: float | None = None,
    threshold: float | None = None,
) -> ImageStats:
    """Level 1 statistics of every frame of a recording, vectorised over frames.

    Parameters
    ----------
    frames : TactileFrames or (T, rows, cols) bool or float
        Contact images, or displacements to be thresholded.
    pitch_mm : float, optional
        Taxel pitch, mm. Defaults to the recording's ``pitch_mm`` for a
        :class:`~taxelkit.frames.TactileFrames`; required for an array.
    threshold : float, optional
        Fixed contact threshold in the frames' unit (mm for the simulator, for
        example ``BONNEVILLE_16X16.contact_threshold_mm``); required for
        numeric frames, ignored for bool frames.

    Returns
    -------
    ImageStats
        Arrays of length ``T``: area (mm^2), centre (mm), orientation (deg),
        elongation, second moments (mm^2). Empty frames: area 0, the rest NaN.

    Raises
    ------
    InputError
        On a bad shape or dtype, NaN/Inf frames, a missing or non-positive
        pitch, or a missing threshold for numeric frames.

    References
    ----------
    Paper 001, Section 3, Level 1.

    Examples
    --------
    >>> img = np.zeros((2, 16, 16), bool)
    >>> img[1, 7, 4:10] = True                  # a 6 x 1 line along x
    >>> s = image_stats(img, pitch_mm=1.7625)
    >>> s.n_taxels.tolist(), float(s.orientation_deg[1]), float(s.elongation[1])
    ([0, 6], 0.0, 6.0)
    >>> bool(np.isnan(s.elongation[0]))
    True
    """
    if isinstance(frames, TactileFrames):
        pitch = check_positive("pitch_mm", frames.pitch_mm if pitch_mm is None else pitch_mm)
        images = binary_images(frames.frames, threshold)
    else:
        if pitch_mm is None:
            raise InputError("pitch_mm must be given for an array of frames, got None")
        pitch = check_positive("pitch_mm", pitch_mm)
        images = check_images(frames, threshold)
    return _stats_from_sums(index_sums(images), pitch)


def frame_stats(frame: ArrayLike, *, pitch_mm: float, threshold: float | None = None) -> FrameStats:
    """Level 1 statistics of a single frame, for streaming use.

    Parameters
    ----------
    frame : (rows, cols) bool or float
        One contact image, or one displacement frame to be thresholded.
    pitch_mm : float
        Taxel pitch, mm.
    threshold : float, optional
        Contact threshold for a numeric frame.

    Returns
    -------
    FrameStats
        Bit-for-bit the values :func:`image_stats` gives for this frame inside
        any batch (the sums are exact; see the module notes).

    Raises
    ------
    InputError
        As :func:`image_stats`, and if ``frame`` is not 2-D.
    """
    f = check_ndim("frame", frame, 2, "(rows, cols)")
    return image_stats(f[None], pitch_mm=pitch_mm, threshold=threshold).frame(0)
