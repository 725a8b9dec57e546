"""Segmentation of contact images into contact regions (several objects on one array).

Paper 001's Levels 1-4 assume one object on the sensor. With several, each
frame is first split into *contact regions*, one per object as far as the
image can tell, and :mod:`taxelkit.smart.tracks` follows the regions over time.

Rules (:class:`RegionConfig` holds the numbers)
    1. **Components.** Contact taxels are grouped into 8-connected components
       within a frame (a taxel touches the eight around it; diagonal
       neighbours belong together because a thin line at 45 deg is a chain
       of diagonal taxels). Frames are never connected to each other: a
       ``(T, rows, cols)`` stack is labelled in one call with a structuring
       element that is empty along time.
    2. **Fragments merged.** A dead taxel or a thin gap splits one contact
       into fragments. Two components are one region when they come within
       ``merge_gap_pitches`` pitches of each other (default 3: up to two
       missing taxels between them; a dead taxel leaves one in a line, and a
       cone's line contact fades for up to two taxels near its light end). This
       is done by dilating every frame with a disc of radius
       ``merge_gap_pitches / 2`` pitches and labelling the dilation with
       4-connectivity; each contact taxel takes the label of the dilated
       component it lies in. The distance in mm is
       ``merge_gap_pitches * pitch_mm``: the rule scales with the array.
       Two objects whose contacts come that close are seen as one region
       (a *merge*, reported by the tracker).

The regions are labelled for the whole stack at once (no loop over frames);
their sizes and centroids come from ``np.bincount`` over the labels. When
most frames repeat the one before (at 240 frames/s a rolling contact keeps
its image for two frames in three; :data:`REPEATS_WORTH`), each distinct
image is segmented once and its regions are copied to its repeats: the same
:class:`Regions` (tested).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import ndimage

from taxelkit.errors import InputError, check_positive

__all__ = ["RegionConfig", "Regions", "disc_offsets", "segment_frames"]

#: Default merge distance, pitches: a gap of up to two taxels (a dead taxel in a
#: line, or the low-pressure end of a cone's line contact, which fades to
#: nothing for one or two taxels before its last taxel).
MERGE_GAP_PITCHES = 3.0
#: Largest share of changed frames for which a stack is segmented one distinct image at a
#: time (at 240 frames/s a rolling contact repeats its image in about two frames of three).
REPEATS_WORTH = 0.75


@dataclass(frozen=True)
class RegionConfig:
    """Numbers of the segmentation.

    Parameters
    ----------
    merge_gap_pitches : float
        Components closer than this (in pitches, centre to centre of their
        nearest taxels, approximately) are one region; 0 keeps the plain
        8-connected components.
    """

    merge_gap_pitches: float = MERGE_GAP_PITCHES

    def __post_init__(self) -> None:
        if not (math.isfinite(self.merge_gap_pitches) and self.merge_gap_pitches >= 0.0):
            raise InputError(f"merge_gap_pitches must be >= 0, got {self.merge_gap_pitches!r}")

    def merge_gap_mm(self, pitch_mm: float) -> float:
        """The merge distance in mm for an array of pitch ``pitch_mm``."""
        return float(self.merge_gap_pitches) * check_positive("pitch_mm", pitch_mm)


@dataclass(frozen=True, eq=False)
class Regions:
    """The contact regions of a stack of frames.

    Attributes
    ----------
    labels : (T, rows, cols) int32
        0 off contact, else ``1 + `` the region's index.
    frame : (n,) int
        Frame of each region, in increasing order.
    n_taxels : (n,) int
        Contact taxels of each region.
    centre_mm : (n, 2) float, mm
        Centroid ``(x, y)`` of each region's taxels, x along columns, y along
        rows, from the centre of taxel (0, 0).
    area_mm2 : (n,) float, mm^2
        ``n_taxels * pitch_mm ** 2``.
    pitch_mm : float
    taxel_rc : (K, 2) float
        (row, column) of every contact taxel, grouped by region.
    taxel_start : (n + 1,) int
        Region ``k``'s taxels are ``taxel_rc[taxel_start[k]:taxel_start[k + 1]]``.
    """

    labels: NDArray[np.int32]
    frame: NDArray[np.intp]
    n_taxels: NDArray[np.intp]
    centre_mm: NDArray[np.float64]
    area_mm2: NDArray[np.float64]
    pitch_mm: float
    taxel_rc: NDArray[np.float64]
    taxel_start: NDArray[np.intp]

    @property
    def n_regions(self) -> int:
        """Number of regions ``n``."""
        return int(self.frame.size)

    def taxels_of(self, idx: NDArray[np.intp]) -> list[NDArray[np.float64]]:
        """(row, column) of the taxels of the regions ``idx`` (views)."""
        s = self.taxel_start
        return [self.taxel_rc[s[k] : s[k + 1]] for k in idx.tolist()]

    def in_frame(self, t: int) -> NDArray[np.intp]:
        """Indices of the regions of frame ``t``."""
        lo, hi = np.searchsorted(self.frame, [t, t + 1])
        return np.arange(lo, hi)


def disc_offsets(radius: float) -> NDArray[np.bool_]:
    """A disc of grid points within ``radius`` (in pitches) of the centre, as a bool kernel.

    Parameters
    ----------
    radius : float
        Radius in pitches, >= 0.

    Returns
    -------
    (2 r + 1, 2 r + 1) bool
        With ``r = floor(radius)``.
    """
    return _disc(float(radius)).copy()


@functools.lru_cache(maxsize=8)
def _disc(radius: float) -> NDArray[np.bool_]:
    """:func:`disc_offsets`, computed once per radius (read-only: shared by the callers)."""
    r = math.floor(radius + 1e-9)
    y, x = np.mgrid[-r : r + 1, -r : r + 1]
    out: NDArray[np.bool_] = (x * x + y * y) <= radius * radius + 1e-9
    out.flags.writeable = False
    return out


def _dilated(img: NDArray[np.bool_], disc: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Every frame of ``img`` ``(T, rows, cols)`` dilated by ``disc``, frames apart.

    As :func:`scipy.ndimage.binary_dilation` with ``disc[None]``, several
    times faster on small frames: each frame is one flat row of taxels, the
    disc a stack of centred horizontal runs; a run of half-width ``w`` ORs
    the frames shifted by up to ``w`` columns (masked where a shift would
    wrap to the next row), and each row offset ORs those shifted by whole rows.
    """
    t, rows, cols = img.shape
    r = disc.shape[0] // 2
    flat = img.reshape(t, rows * cols)
    col = np.arange(rows * cols) % cols
    widths = [int(np.count_nonzero(disc[k])) // 2 for k in range(disc.shape[0])]
    runs = [flat]  # runs[w]: the frames dilated by a run of half-width w
    for w in range(1, max(widths) + 1):
        h = runs[-1].copy()
        if w < cols:
            h[:, w:] |= flat[:, :-w] & (col[w:] >= w)
            h[:, :-w] |= flat[:, w:] & (col[:-w] < cols - w)
        runs.append(h)
    out = runs[widths[r]].copy()
    for k, w in enumerate(widths):
        dy = k - r
        if dy == 0 or abs(dy) >= rows:
            continue
        shift = abs(dy) * cols
        if dy > 0:
            out[:, shift:] |= runs[w][:, :-shift]
        else:
            out[:, :-shift] |= runs[w][:, shift:]
    grown: NDArray[np.bool_] = out.reshape(img.shape)
    return grown


_EIGHT_IN_PLANE = np.zeros((3, 3, 3), bool)
_EIGHT_IN_PLANE[1] = True
_FOUR_IN_PLANE = np.zeros((3, 3, 3), bool)
_FOUR_IN_PLANE[1] = [[False, True, False], [True, True, True], [False, True, False]]


def segment_frames(
    images: ArrayLike, *, pitch_mm: float, config: RegionConfig | None = None
) -> Regions:
    """Split every frame of a stack into contact regions (rules in the module docstring).

    Parameters
    ----------
    images : (T, rows, cols) bool
        Contact images (thresholded and, usually, cleaned).
    pitch_mm : float
        Taxel pitch, mm.
    config : RegionConfig, optional

    Returns
    -------
    Regions
        Regions ordered by frame, then by the position of their first taxel
        in raster order.

    Raises
    ------
    InputError
        If ``images`` is not a bool ``(T, rows, cols)`` stack.

    Examples
    --------
    >>> img = np.zeros((1, 6, 8), bool)
    >>> img[0, 1, 1:3] = img[0, 1, 4:6] = True   # one line, a dead taxel at column 3
    >>> img[0, 4, 7] = True                        # another contact, far away
    >>> segment_frames(img, pitch_mm=1.0).n_taxels.tolist()
    [4, 1]
    """
    cfg = RegionConfig() if config is None else config
    pitch = check_positive("pitch_mm", pitch_mm)
    img = np.asarray(images)
    if img.ndim != 3 or img.dtype != bool:
        raise InputError(
            f"images must be bool with shape (T, rows, cols), got {img.dtype} {img.shape}"
        )
    new = _changed(img)
    if new is not None:  # many frames repeat the one before (a held or slow contact)
        return _repeated(_segment(img[new], pitch, cfg), new)
    return _segment(img, pitch, cfg)


def _changed(img: NDArray[np.bool_]) -> NDArray[np.bool_] | None:
    """Frames that differ from the one before ``(T,)`` (the first does), or None if most do."""
    t = img.shape[0]
    if t < 2:
        return None
    flat = img.reshape(t, -1)
    if flat.shape[1] % 8 == 0 and flat.flags.c_contiguous:
        flat = flat.view(np.uint64)  # eight taxels a word
    new = np.ones(t, bool)
    new[1:] = (flat[1:] != flat[:-1]).any(axis=1)
    return new if np.count_nonzero(new) <= REPEATS_WORTH * t else None


def _repeated(unique: Regions, new: NDArray[np.bool_]) -> Regions:
    """The regions of every frame from those of its distinct images (``new``: changed frames)."""
    frame_of = np.cumsum(new) - 1  # each frame's distinct image
    t, n_unique = new.size, int(np.count_nonzero(new))
    m_unique = np.bincount(unique.frame, minlength=n_unique)
    start_unique = np.concatenate([[0], np.cumsum(m_unique)])
    m = m_unique[frame_of]
    start = np.concatenate([[0], np.cumsum(m)])
    frame = np.repeat(np.arange(t), m)
    src = start_unique[frame_of[frame]] + (np.arange(start[-1]) - start[frame])
    offset = (start[:-1] - start_unique[frame_of]).astype(np.int32)
    labels = np.take(unique.labels, frame_of, axis=0)
    np.add(labels, offset[:, None, None], out=labels, where=labels > 0)  # no temporaries
    count = unique.n_taxels[src]
    taxel_start = np.concatenate([[0], np.cumsum(count)]).astype(np.intp)
    first = unique.taxel_start[src]
    take = np.repeat(first - taxel_start[:-1], count) + np.arange(taxel_start[-1])
    return Regions(
        labels=labels,
        frame=frame.astype(np.intp),
        n_taxels=count,
        centre_mm=unique.centre_mm[src],
        area_mm2=unique.area_mm2[src],
        pitch_mm=unique.pitch_mm,
        taxel_rc=unique.taxel_rc[take],
        taxel_start=taxel_start,
    )


def _segment(img: NDArray[np.bool_], pitch: float, cfg: RegionConfig) -> Regions:
    """:func:`segment_frames` on every frame of ``img``."""
    t, rows, cols = img.shape
    radius = 0.5 * float(cfg.merge_gap_pitches)
    if radius >= 1.0 - 1e-9:
        grown = _dilated(img, _disc(radius))
        lab, n = ndimage.label(grown, structure=_FOUR_IN_PLANE)
    else:
        lab, n = ndimage.label(img, structure=_EIGHT_IN_PLANE)
    # renumber the labels that hold contact taxels 1..n in order of first taxel (raster order)
    on = np.flatnonzero(img)  # every contact taxel lies in a labelled component
    raw = lab.reshape(-1)[on]
    used, first = np.unique(raw, return_index=True)
    order = np.argsort(first, kind="stable")  # ndimage numbers in raster order already
    remap = np.zeros(n + 1, np.int32)
    remap[used[order]] = np.arange(1, used.size + 1, dtype=np.int32)
    n_reg = int(used.size)
    ids = remap[raw] - 1
    lab = np.zeros(img.shape, np.int32)  # labels on the contact taxels only
    lab.reshape(-1)[on] = ids + 1
    tt, rr, cc = np.unravel_index(on, (t, rows, cols))
    count = np.bincount(ids, minlength=n_reg)
    sx = np.bincount(ids, weights=cc, minlength=n_reg)
    sy = np.bincount(ids, weights=rr, minlength=n_reg)
    frame = np.zeros(n_reg, np.intp)
    frame[ids] = tt  # every taxel of a region is in one frame
    with np.errstate(invalid="ignore", divide="ignore"):
        centre = np.column_stack([sx, sy]) / np.maximum(count, 1)[:, None] * pitch
    order = np.argsort(ids, kind="stable")
    taxel_rc = np.column_stack([rr[order], cc[order]]).astype(np.float64)
    taxel_start = np.concatenate([[0], np.cumsum(count)]).astype(np.intp)
    return Regions(
        labels=lab,
        frame=frame,
        n_taxels=count.astype(np.intp),
        centre_mm=centre,
        area_mm2=count.astype(np.float64) * (pitch * pitch),
        pitch_mm=pitch,
        taxel_rc=taxel_rc,
        taxel_start=taxel_start,
    )
