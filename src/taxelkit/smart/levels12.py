"""Levels 1-2 of the smart sensor over chunks of frames of many arrays, state carried.

:func:`~taxelkit.smart.recogniser.recognise` runs Levels 1-2 vectorised over
a whole recording. :class:`ChunkLevels12` runs the same functions over ``T``
frames of ``N`` arrays at a time (the streaming sensor's mini-batches, the
sensor bank's pushes), carrying what crosses a chunk's edge: the image
cleaning's state (:class:`~taxelkit.smart.cleaning_chunks.ChunkCleaner`) and
the limits' hysteresis (:class:`~taxelkit.smart.contact_limits.LimitState`,
one per array). Level 1's sums are exact, so a frame's statistics do not
depend on the chunk it came in.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.cleaning import CleaningConfig
from taxelkit.smart.cleaning_chunks import GROUP_FRAMES, ChunkCleaner
from taxelkit.smart.contact_classes import ContactClass, ContactNetwork, classify_contacts
from taxelkit.smart.contact_limits import ContactLimits
from taxelkit.smart.gather import take_rows
from taxelkit.smart.limits_rows import limits_rows
from taxelkit.smart.line_extents import line_extents
from taxelkit.smart.moments import ImageStats, image_stats
from taxelkit.smart.packed_rows import PACK_MAX_COLS, backend_for, repeats

__all__ = [
    "DEFAULT_CLEANING",
    "DEFAULT_LIMITS",
    "DEFAULT_THRESHOLD_MM",
    "ChunkLevels12",
    "half_length",
]


#: Default contact threshold, mm: the Bonneville preset's fixed threshold.
DEFAULT_THRESHOLD_MM = 0.03
#: Image cleaning used unless switched off (``cleaning=None``: paper 001's pipeline).
DEFAULT_CLEANING = CleaningConfig()
#: Level 2 limits in mm and taxels used unless switched off (``limits=None``).
DEFAULT_LIMITS = ContactLimits()
#: Shortest slice along time of a long chunk (a slice costs a few NumPy calls per group).
_MIN_SLICE_FRAMES = 4096
#: Levels 1-2 are computed once per run of equal frames when at most this share is new
#: (gathering them costs about a quarter of computing them).
_REPEATS_WORTH = 0.75


def _touched(images: NDArray[np.bool_], time_major: bool) -> NDArray[np.bool_]:
    """``(N,)``: arrays with a taxel on in any frame of images ``(N, T, ...)`` or ``(T, N, ...)``.

    Time first, the frames are OR-ed 8 taxels to a word before the test.
    """
    a, b = images.shape[:2]
    taxels = int(np.prod(images.shape[2:], dtype=np.int64))
    if not time_major:
        out: NDArray[np.bool_] = np.any(images.reshape(a, b * taxels), axis=1)
        return out
    if taxels % 8 == 0 and images.flags.c_contiguous and a:
        words = images.reshape(a, b * taxels).view(np.uint64).reshape(a, b, taxels // 8)
        out = np.any(np.bitwise_or.reduce(words, axis=0), axis=1)
        return out
    out = np.any(np.any(images.reshape(a, b, taxels), axis=2), axis=0)
    return out


def half_length(stats: ImageStats) -> NDArray[np.float64]:
    """``sqrt(3 lambda_max)`` of every frame, mm: half the length of a line with its moments."""
    vx, vy, cxy = stats.var_x_mm2, stats.var_y_mm2, stats.cov_xy_mm2
    lam = 0.5 * (vx + vy) + np.hypot(0.5 * (vx - vy), cxy)
    out: NDArray[np.float64] = np.sqrt(3.0 * lam)
    return out


class ChunkLevels12:
    """Levels 1-2 of ``n_arrays`` arrays of one shape, a chunk of frames at a time.

    Parameters
    ----------
    n_arrays : int
    shape : (rows, cols)
    pitch_mm : float
    threshold : float
        Contact threshold for float frames.
    network : ContactNetwork
    confidence : float
    cleaning : CleaningConfig or None
    limits : ContactLimits or None
    """

    def __init__(
        self,
        n_arrays: int,
        shape: tuple[int, int],
        *,
        pitch_mm: float,
        threshold: float,
        network: ContactNetwork,
        confidence: float,
        cleaning: CleaningConfig | None,
        limits: ContactLimits | None,
    ) -> None:
        self.n = int(n_arrays)
        self.shape = (int(shape[0]), int(shape[1]))
        self.pitch_mm = float(pitch_mm)
        self.threshold = float(threshold)
        self.network = network
        self.confidence = float(confidence)
        self.cleaning = cleaning
        self.limits = limits
        self.ops = backend_for(self.shape[1])
        #: Whether bool frames may be given packed (:meth:`process_packed_time_major`).
        self.packs = self.shape[1] % 8 == 0 and self.shape[1] <= PACK_MAX_COLS
        self.reset()

    def reset(self) -> None:
        """Forget every stream."""
        self._cleaner = (
            None
            if self.cleaning is None
            else ChunkCleaner(self.n, self.shape, config=self.cleaning)
        )
        self._long = np.zeros(self.n, bool)  # the limits' hysteresis (LimitState), per array
        self._big = np.zeros(self.n, bool)
        self._run = np.zeros(self.n, np.int64)  # frames in a row over the area's higher mark
        self._t_prev = np.full(self.n, np.nan)  # each array's last frame time, s
        self._line_run = np.zeros(self.n, np.int64)  # frames in a row over the line's length
        self._length = np.zeros(self.n)  # each array's last frame's length, mm (0: no contact)

    def _levels(
        self,
        images: NDArray[np.bool_] | None,
        t_s: NDArray[np.float64],
        sel: NDArray[np.intp],
        words: NDArray[Any] | None = None,
        dest: NDArray[np.float64] | None = None,
    ) -> tuple[NDArray[np.int8], NDArray[np.float64]]:
        """Classes ``(m, T)`` and rows ``(m, T, 9)`` of the cleaned frames of arrays ``sel``.

        ``dest``: the ``(m, T, 9)`` array the rows are written to (returned), if given.

        ``words``: the same frames packed one word per row ``(m, T, rows)``, if at hand
        (``images`` may then be None: the frames computed are unpacked from them).
        A frame's statistics, class before the limits and line extent depend on
        its image alone: a frame equal to the one before it (a contact held
        still) takes that frame's, computed once.
        """
        given = images if images is not None else words
        assert given is not None
        m, t = given.shape[:2]
        n = m * t
        flat = None if images is None else images.reshape(n, *self.shape)
        packed = None if words is None else words.reshape(n, -1)
        new = repeats(given.reshape(n, -1), packed, _REPEATS_WORTH)
        idx = inv = None
        if new is not None:
            idx = np.flatnonzero(new)
            inv = np.cumsum(new) - 1  # each frame's computed frame
        u_packed = None if packed is None or idx is None else take_rows(packed, idx)
        if flat is None:  # unpacked for the frames computed only
            assert packed is not None
            rows_of = packed if u_packed is None else u_packed
            u_flat = self.ops.unpack(rows_of, self.shape[1]).reshape(-1, *self.shape)
            u_packed = rows_of
        else:
            u_flat = flat if idx is None else take_rows(flat, idx)

        def full(x: NDArray[Any]) -> NDArray[Any]:
            return x if inv is None else take_rows(x, inv)

        stats = image_stats(u_flat, pitch_mm=self.pitch_mm)
        u_cls = classify_contacts(stats, self.network, confidence=self.confidence)
        u_half = half_length(stats)
        cls = full(u_cls)
        if self.limits is not None:
            cls = self._limited(
                cls.reshape(m, t),
                full(stats.n_taxels).reshape(m, t),
                full(stats.area_mm2).reshape(m, t),
                full(stats.elongation).reshape(m, t),
                full(u_half).reshape(m, t),
                sel,
                np.asarray(t_s, dtype=np.float64)[sel],
            ).reshape(-1)
        # the computed frames' rows, then laid out frame by frame in one gather
        table = np.empty((u_flat.shape[0], 9))
        table[:, 0:2] = stats.centre_mm
        table[:, 2] = stats.orientation_deg
        table[:, 3] = stats.area_mm2
        table[:, 4] = stats.elongation
        table[:, 5] = u_half
        table[:, 6:8] = np.nan
        lines = np.flatnonzero(cls == ContactClass.LINE)
        at = lines  # the computed frames whose extents are read
        if lines.size:
            if inv is not None:
                need = np.zeros(u_flat.shape[0], bool)
                need[inv.take(lines)] = True
                at = np.flatnonzero(need)
            table[at, 6:8] = line_extents(
                take_rows(u_flat, at),
                take_rows(stats.centre_mm, at),
                stats.orientation_deg.take(at),
                self.pitch_mm,
                row_words=None if u_packed is None else take_rows(u_packed, at),
            )
        if dest is None:
            out = full(table)
        else:
            out = dest.reshape(n, 9)  # the caller's rows (a view: contiguous frames)
            if inv is None:
                out[...] = table
            else:
                take_rows(table, inv, out=out)
        out[:, 8] = np.asarray(t_s, dtype=np.float64)[sel].reshape(-1)
        if lines.size and inv is not None and lines.size < n:
            # a computed frame that is a line here and not there (the limits' hysteresis)
            other = np.flatnonzero(need.take(inv) & (cls != ContactClass.LINE))
            out[other, 6:8] = np.nan
        return cls.reshape(m, t), out.reshape(m, t, 9)

    def _limited(
        self,
        classes: NDArray[np.int8],
        taxels: NDArray[np.int64],
        area: NDArray[np.float64],
        elong: NDArray[np.float64],
        half: NDArray[np.float64],
        sel: NDArray[np.intp],
        t_s: NDArray[np.float64],
    ) -> NDArray[np.int8]:
        """:func:`~taxelkit.smart.contact_limits.apply_limits` on the arrays ``sel``, ``(m, T)``:
        their classes, taxels, areas, elongations and half-lengths, taken at ``t_s``."""
        assert self.limits is not None
        state = (
            self._long[sel],
            self._big[sel],
            self._run[sel],
            self._t_prev[sel],
            self._line_run[sel],
            self._length[sel],
        )
        out, after = limits_rows(classes, taxels, area, elong, half, t_s, self.limits, state)
        self._long[sel], self._big[sel], self._run[sel], self._t_prev[sel] = after[:4]
        self._line_run[sel], self._length[sel] = after[4], after[5]
        return out

    def process(
        self, frames: NDArray[np.generic], t_s: NDArray[np.float64]
    ) -> tuple[NDArray[np.int8], NDArray[np.float64]]:
        """Classes and Level 1 rows of frames ``(N, T, rows, cols)`` taken at ``t_s`` ``(N, T)``.

        Returns
        -------
        classes : (N, T) int8
            :class:`~taxelkit.smart.contact_classes.ContactClass` codes.
        rows : (N, T, 9) float
            Per frame: centre x, y (mm), orientation (deg), area (mm^2),
            elongation, half-length (mm), line extent low, high (mm; NaN
            unless a line), time (s) (:data:`~taxelkit.smart.segment_scan.ROW_COLUMNS`).
        """
        images: NDArray[np.bool_] = (
            np.asarray(frames, dtype=bool)
            if frames.dtype == bool
            else np.asarray(frames, dtype=np.float64) > self.threshold
        )
        return self._process(images, t_s, time_major=False)

    def process_time_major(
        self, frames: NDArray[np.generic], t_s: NDArray[np.float64]
    ) -> tuple[NDArray[np.int8], NDArray[np.float64]]:
        """As :meth:`process`, frames given time first, ``(T, N, rows, cols)``.

        Only the arrays touched in the chunk (or whose cleaning state is not
        at rest) are gathered, a group at a time; the others cost a test.
        """
        images: NDArray[np.bool_] = (
            np.asarray(frames, dtype=bool)
            if frames.dtype == bool
            else np.asarray(frames, dtype=np.float64) > self.threshold
        )
        return self._process(images, t_s, time_major=True)

    def process_packed_time_major(
        self, words: NDArray[Any], t_s: NDArray[np.float64]
    ) -> tuple[NDArray[np.int8], NDArray[np.float64]]:
        """As :meth:`process_time_major`, bool frames packed ``(T, N, rows)`` by :attr:`ops`.

        Only when :attr:`packs` (a row of whole bytes in one word): a bank
        buffers an eighth of the bytes, and the cleaning starts from them.
        """
        return self._process(words, t_s, time_major=True, packed=True)

    def _process(
        self,
        images: NDArray[Any],
        t_s: NDArray[np.float64],
        *,
        time_major: bool,
        packed: bool = False,
    ) -> tuple[NDArray[np.int8], NDArray[np.float64]]:
        """Levels 1-2 of images ``(N, T, rows, cols)`` (or ``(T, N, ...)``), a slice at a time.

        A long chunk is cut along time into slices of about :data:`GROUP_FRAMES`
        frames of all arrays together (the state carried across them as
        across chunks: the same result), so that the temporaries stay in the cache.
        """
        t = images.shape[0] if time_major else images.shape[1]
        step = max(_MIN_SLICE_FRAMES, GROUP_FRAMES // max(self.n, 1))
        if t <= 2 * step:
            return self._process_slice(images, t_s, time_major=time_major, packed=packed)
        classes = np.empty((self.n, t), dtype=np.int8)
        rows = np.empty((self.n, t, 9))
        for a in range(0, t, step):
            b = min(t, a + step)
            part = images[a:b] if time_major else images[:, a:b]
            self._process_slice(
                part,
                t_s[:, a:b],
                time_major=time_major,
                packed=packed,
                out=(classes[:, a:b], rows[:, a:b]),
            )
        return classes, rows

    def _process_slice(
        self,
        images: NDArray[Any],
        t_s: NDArray[np.float64],
        *,
        time_major: bool,
        packed: bool = False,
        out: tuple[NDArray[np.int8], NDArray[np.float64]] | None = None,
    ) -> tuple[NDArray[np.int8], NDArray[np.float64]]:
        """Levels 1-2 of one slice of frames (or packed rows), a group of arrays at a time.

        ``out``: the classes ``(N, T)`` and rows ``(N, T, 9)`` to write to (returned).
        """
        n = self.n
        t = images.shape[0] if time_major else images.shape[1]
        if out is None:
            classes = np.zeros((n, t), dtype=np.int8)  # NONE
            rows = np.empty((n, t, 9))  # read only where there is contact
        else:
            classes, rows = out
            classes[...] = 0
        taxels = self.shape[0] * self.shape[1]
        if packed and n == 1:
            hit = np.array([np.any(images)])
        elif packed:  # (T, N, rows) words: any word on, over time, then over rows
            hit = np.any(np.bitwise_or.reduce(images, axis=0), axis=1)
        else:
            hit = _touched(images, time_major)
        longest = 0
        if self._cleaner is not None and t:  # the arrays that may have contact
            sel, longest = self._cleaner.select(t_s, hit)
        else:
            sel = np.flatnonzero(hit)
        group = max(1, GROUP_FRAMES // max(t, 1))  # arrays per pass: the data stay in cache
        touched = []
        img: NDArray[Any] | None
        for a in range(0, sel.size, group):
            g = sel[a : a + group]
            span = slice(int(g[0]), int(g[-1]) + 1) if g[-1] - g[0] == g.size - 1 else g
            if time_major:
                order = (1, 0, 2) if packed else (1, 0, 2, 3)
                img = np.ascontiguousarray(images[:, span].transpose(*order))
            else:
                img = images if g.size == n else images[span]
            words = None
            if self._cleaner is not None:
                cleaned = self._cleaner.clean_packed(img, g, longest, packed=packed)
                if cleaned.ndim == 2:  # one word a row: unpacked by _levels, as needed
                    words, img = cleaned.reshape(g.size, t, -1), None
                else:
                    img = self.ops.unpack(cleaned, self.shape[1]).reshape(g.size, t, *self.shape)
            elif packed:
                words, img = img, None  # unpacked by _levels, as needed
            if img is None:
                assert words is not None
                on = np.any(words.reshape(g.size, -1), axis=1)
            else:
                on = img.reshape(g.size, t * taxels).any(axis=1)
            gt = g[on]
            if gt.size:
                every = gt.size == g.size
                dest: NDArray[np.float64] | None = rows[int(gt[0]) : int(gt[-1]) + 1]
                if dest is not None and (dest.shape[0] != gt.size or not dest.flags.c_contiguous):
                    dest = None  # written through a view of the rows only
                classes[gt], found = self._levels(
                    img if every or img is None else img[on],
                    t_s,
                    gt,
                    words if every or words is None else words[on],
                    dest=dest,
                )
                if dest is None:
                    rows[gt] = found
                touched.append(gt)
        quiet = np.ones(n, bool)
        for gt in touched:
            quiet[gt] = False
        self._long[quiet] = False  # no contact: no length, no area
        self._big[quiet] = False
        self._run[quiet] = 0
        self._line_run[quiet] = 0
        self._length[quiet] = 0.0
        if t:
            self._t_prev[quiet] = np.asarray(t_s, dtype=np.float64)[quiet, -1]
        return classes, rows
