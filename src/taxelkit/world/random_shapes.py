"""Many distinct relief shapes: random star-shaped polygons and smooth closed curves.

The generator behind the ``capacity`` experiment (paper 000 beyond five
shapes). Every shape is *star-shaped about its generation centre*: its
outline is ``r(theta)`` in polar coordinates about that centre, so it is a
simple polygon that the tracer can follow all the way round.

Kinds (alternating: even indices polygons, odd ones curves)
-----------------------------------------------------------
``polygon``
    ``n`` vertices, ``n`` uniform in :data:`POLYGON_VERTICES`; the angles are
    ``n`` sorted uniform draws, re-drawn until no two are closer than
    :data:`MIN_VERTEX_GAP_DEG`; the radii are uniform in
    ``[MIN_RADIUS_RATIO, 1]`` of the circumscribed radius. Convex and
    re-entrant corners both occur.
``curve``
    ``r(theta) = 1 + sum_h a_h cos(h theta + phi_h)`` for harmonics ``h`` in
    :data:`CURVE_HARMONICS`, amplitudes uniform in ``[0, CURVE_AMPLITUDE / h]``
    and random phases, rescaled so that ``min r >= MIN_RADIUS_RATIO max r``;
    sampled at :data:`CURVE_VERTICES` points (a fine polygon, like the curved
    outlines of :mod:`taxelkit.world.open_set_shapes`).

Every shape is scaled so that its farthest outline point lies on the circle
of the requested diameter about the generation centre (90 mm by default, the
paper's specimen size), so the shapes are told apart by their form, not by
their size.

Minimum pairwise difference
---------------------------
Two shapes differ by ``d = min over rotations of RMS(r_a - r_b) / R``: the
root-mean-square difference of their radial functions about the generation
centre, sampled at :data:`DIFFERENCE_SAMPLES` angles, minimised over all
rotations (one circular cross-correlation by FFT), relative to the
circumscribed radius ``R``. A candidate is accepted only if it differs from
every shape accepted before by at least ``min_difference``
(:data:`MIN_SHAPE_DIFFERENCE` = 0.08, i.e. 3.6 mm RMS at 90 mm diameter, about
18 times the tracer's RMS error on the paper's specimens), so no two
generated shapes are the same shape rotated. Mirror images count as different
(a tracer that keeps the raised side on its left sees a mirrored contour
turning the other way).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from taxelkit.errors import InputError
from taxelkit.world._planar import check_transform, transform_points
from taxelkit.world.contour_relief import DEFAULT_STEP_HEIGHT_UM, PolygonRelief

__all__ = [
    "CURVE_VERTICES",
    "MIN_SHAPE_DIFFERENCE",
    "GeneratedShape",
    "generate_shapes",
    "radial_difference",
]

#: Vertex counts of the random polygons (inclusive range).
POLYGON_VERTICES = (4, 11)
#: Smallest angle between two polygon vertices about the centre, deg.
MIN_VERTEX_GAP_DEG = 18.0
#: Smallest radius as a fraction of the circumscribed radius (keeps every
#: notch wider than the tracer's 18 mm array footprint at 90 mm diameter).
MIN_RADIUS_RATIO = 0.5
#: Harmonics of the smooth curves.
CURVE_HARMONICS = (2, 3, 4, 5, 6, 7)
#: Amplitude scale of the curves' harmonics (harmonic ``h`` draws up to this / h).
CURVE_AMPLITUDE = 1.2
#: Vertices of the polygons standing in for smooth curves.
CURVE_VERTICES = 180
#: Angles at which radial functions are compared.
DIFFERENCE_SAMPLES = 360
#: Default minimum pairwise difference (RMS radial difference / circumscribed radius).
MIN_SHAPE_DIFFERENCE = 0.08
#: Candidates drawn per accepted shape before giving up.
MAX_DRAWS_PER_SHAPE = 200


@dataclass(frozen=True, eq=False)
class GeneratedShape:
    """One generated outline.

    Attributes
    ----------
    name : str
        ``"gen-KIND-INDEX"`` (index in generation order, 3 digits).
    kind : str
        ``"polygon"`` or ``"curve"``.
    unit_vertices : (V, 2) float64
        Outline about the generation centre, counter-clockwise, farthest
        point at radius 1 (dimensionless).
    radial : (DIFFERENCE_SAMPLES,) float64
        Radial function ``r(theta)`` at equally spaced angles from 0 (radius 1
        = circumscribed).
    """

    name: str
    kind: str
    unit_vertices: NDArray[np.float64]
    radial: NDArray[np.float64]

    def outline_mm(
        self,
        *,
        diameter_mm: float = 90.0,
        rotation_deg: float = 0.0,
        offset_mm: ArrayLike = (0.0, 0.0),
    ) -> NDArray[np.float64]:
        """Vertices ``(V, 2)`` in mm: scaled to ``diameter_mm``, rotated, moved.

        Raises
        ------
        ValueError
            For a non-positive diameter or a non-finite pose (an InputError).
        """
        rot, off, radius = check_transform(rotation_deg, offset_mm, diameter_mm / 2)
        return transform_points(self.unit_vertices, rotation_deg=rot, offset_mm=off, scale=radius)

    def relief(
        self,
        *,
        diameter_mm: float = 90.0,
        rotation_deg: float = 0.0,
        offset_mm: ArrayLike = (0.0, 0.0),
        step_height_um: float = DEFAULT_STEP_HEIGHT_UM,
    ) -> PolygonRelief:
        """The raised specimen (see :meth:`outline_mm`), step ``step_height_um`` um high."""
        return PolygonRelief(
            self.outline_mm(
                diameter_mm=diameter_mm, rotation_deg=rotation_deg, offset_mm=offset_mm
            ),
            step_height_um=step_height_um,
        )


def _radial_of_polygon(
    angles: NDArray[np.float64], radii: NDArray[np.float64]
) -> NDArray[np.float64]:
    """``r(theta)`` of a star-shaped polygon at :data:`DIFFERENCE_SAMPLES` angles."""
    theta = 2 * np.pi * np.arange(DIFFERENCE_SAMPLES) / DIFFERENCE_SAMPLES
    p = np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])
    q = np.roll(p, -1, axis=0)
    edge = np.searchsorted(angles, theta, side="right") - 1  # -1: the edge last -> first
    # Intersection of the ray at theta with the edge p -> q, as a fraction along the edge.
    d = np.column_stack([np.cos(theta), np.sin(theta)])
    pe, qe = p[edge], q[edge]
    e = qe - pe
    denom = d[:, 0] * e[:, 1] - d[:, 1] * e[:, 0]
    t = (pe[:, 0] * d[:, 1] - pe[:, 1] * d[:, 0]) / denom
    r: NDArray[np.float64] = np.hypot(*(pe + t[:, None] * e).T)
    return r


def _draw_polygon(rng: np.random.Generator) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    n = int(rng.integers(POLYGON_VERTICES[0], POLYGON_VERTICES[1] + 1))
    gap = math.radians(MIN_VERTEX_GAP_DEG)
    while True:
        angles = np.sort(rng.uniform(0.0, 2 * np.pi, n))
        gaps = np.diff(np.append(angles, angles[0] + 2 * np.pi))
        if gaps.min() >= gap and gaps.max() < np.pi:  # the centre stays inside
            break
    radii = rng.uniform(MIN_RADIUS_RATIO, 1.0, n)
    radii /= radii.max()
    verts = np.column_stack([radii * np.cos(angles), radii * np.sin(angles)])
    return verts, _radial_of_polygon(angles, radii)


def _draw_curve(rng: np.random.Generator) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    def radial(theta: NDArray[np.float64]) -> NDArray[np.float64]:
        r = np.ones_like(theta)
        for h, a, ph in zip(CURVE_HARMONICS, amps, phases, strict=True):
            r += a * np.cos(h * theta + ph)
        return r

    amps = rng.uniform(0.0, 1.0, len(CURVE_HARMONICS)) * CURVE_AMPLITUDE / np.array(CURVE_HARMONICS)
    phases = rng.uniform(0.0, 2 * np.pi, len(CURVE_HARMONICS))
    theta_v = 2 * np.pi * np.arange(CURVE_VERTICES) / CURVE_VERTICES
    theta_d = 2 * np.pi * np.arange(DIFFERENCE_SAMPLES) / DIFFERENCE_SAMPLES
    rv, rd = radial(theta_v), radial(theta_d)
    lo, hi = min(rv.min(), rd.min()), max(rv.max(), rd.max())
    # Shrink the oscillation about the mean until min r >= MIN_RADIUS_RATIO max r.
    mean = 1.0
    if lo < MIN_RADIUS_RATIO * hi:
        k = (1 - MIN_RADIUS_RATIO) * mean / ((hi - mean) * MIN_RADIUS_RATIO + (mean - lo))
        rv, rd = mean + k * (rv - mean), mean + k * (rd - mean)
    scale = max(rv.max(), rd.max())
    rv, rd = rv / scale, rd / scale
    verts = np.column_stack([rv * np.cos(theta_v), rv * np.sin(theta_v)])
    return verts, rd


def radial_difference(radial_a: ArrayLike, radial_b: ArrayLike) -> NDArray[np.float64]:
    """Rotation-minimised RMS difference of radial functions (the generator's distance).

    Parameters
    ----------
    radial_a : (..., S) float
        Radial functions at ``S`` equally spaced angles (circumscribed radius 1).
    radial_b : (S,) float
        One radial function.

    Returns
    -------
    (...) float64
        ``min over cyclic shifts j of sqrt(mean((a - roll(b, j))^2))``.

    Examples
    --------
    >>> r = np.ones(360); r[:90] = 0.5
    >>> float(radial_difference(r, np.roll(r, 37)))
    0.0
    """
    a = np.asarray(radial_a, dtype=np.float64)
    b = np.asarray(radial_b, dtype=np.float64)
    s = b.shape[-1]
    # sum (a - roll(b, j))^2 = |a|^2 + |b|^2 - 2 corr[j], all j by one FFT.
    corr = np.fft.irfft(np.fft.rfft(a, axis=-1) * np.conj(np.fft.rfft(b)), n=s, axis=-1)
    sq = (a**2).sum(axis=-1) + (b**2).sum() - 2 * corr.max(axis=-1)
    out: NDArray[np.float64] = np.sqrt(np.maximum(sq, 0.0) / s)
    return out


def generate_shapes(
    n_shapes: int,
    *,
    rng: int | np.random.Generator | None = None,
    min_difference: float = MIN_SHAPE_DIFFERENCE,
) -> tuple[GeneratedShape, ...]:
    """Draw ``n_shapes`` pairwise distinct star-shaped outlines.

    Parameters
    ----------
    n_shapes : int
        Number of shapes (>= 1).
    rng : int, Generator or None
        Seed: the same seed gives the same shapes.
    min_difference : float
        Smallest accepted :func:`radial_difference` between any two shapes
        (>= 0, relative to the circumscribed radius).

    Returns
    -------
    tuple of GeneratedShape
        In generation order; names ``gen-polygon-000``, ``gen-curve-001``, ...

    Raises
    ------
    InputError
        If an argument is out of range, or no candidate far enough from the
        shapes so far is found in :data:`MAX_DRAWS_PER_SHAPE` draws.

    Examples
    --------
    >>> shapes = generate_shapes(3, rng=0)
    >>> [s.kind for s in shapes] == [s.kind for s in generate_shapes(3, rng=0)]
    True
    """
    if int(n_shapes) != n_shapes or n_shapes < 1:
        raise InputError(f"n_shapes must be an integer >= 1, got {n_shapes!r}")
    if not (math.isfinite(min_difference) and min_difference >= 0):
        raise InputError(f"min_difference must be a finite number >= 0, got {min_difference!r}")
    gen = np.random.default_rng(rng)
    shapes: list[GeneratedShape] = []
    radials = np.empty((0, DIFFERENCE_SAMPLES))
    for index in range(int(n_shapes)):
        for _ in range(MAX_DRAWS_PER_SHAPE):
            kind = "polygon" if index % 2 == 0 else "curve"
            verts, radial = _draw_polygon(gen) if kind == "polygon" else _draw_curve(gen)
            if radials.shape[0] == 0 or radial_difference(radials, radial).min() >= min_difference:
                break
        else:
            raise InputError(
                f"no shape at least {min_difference} from the {len(shapes)} drawn so far "
                f"in {MAX_DRAWS_PER_SHAPE} draws; lower min_difference or n_shapes"
            )
        name = f"gen-{kind}-{index:03d}"
        shapes.append(GeneratedShape(name, kind, verts, radial))
        radials = np.vstack([radials, radial])
    return tuple(shapes)
