"""The image cleaning of :func:`~taxelkit.smart.cleaning.clean_images`, chunk by chunk, many arrays.

:func:`~taxelkit.smart.cleaning.clean_images` cleans a whole recording;
:class:`~taxelkit.smart.cleaning_stream.ImageCleaner` one frame. Between the
two, :class:`ChunkCleaner` takes ``T`` frames of ``N`` arrays at once, with
every rule's state carried from chunk to chunk, so the streaming sensor and
the sensor bank run the batch's vectorised rule functions and give the same
images as :func:`~taxelkit.smart.cleaning.clean_images` on each array's whole
stream (tested). The state per array:

* the taxels on since the stream began (rule 1: a running AND);
* the last ``n_stuck - 1`` frames of isolated taxels (rule 1: a taxel is
  stuck once isolated ``n_stuck`` frames in a row), packed, so the count
  over a chunk's edge is the batch's own shifted AND;
* the masked (stuck) taxels and how long each has read off (rule 1's
  release), for the few taxels concerned;
* the last bridged frame and its one-frame test (rule 3, persistence).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.smart.cleaning import (
    CleaningConfig,
    _backend,
    _bridged,
    _clean,
    _neighbours8,
    release_frames_for,
    stuck_frames_for,
)
from taxelkit.smart.cleaning_runs import RUNS_WORTH, clean_runs, run_starts
from taxelkit.smart.gather import take_rows
from taxelkit.smart.packed_rows import PackedRows

__all__ = ["GROUP_FRAMES", "ChunkCleaner"]

#: Frames (arrays x frames of a chunk) cleaned per pass: about 4 MB of bool
#: 16 x 16 frames, so that the rules' temporaries stay in the cache.
GROUP_FRAMES = 16_384


def _held_along_time(a: NDArray[Any], n: int) -> NDArray[Any]:
    """Taxels on in each of the frames ``t - n + 1 .. t`` of ``a`` ``(N, T, ...)`` (axis 1).

    The doubling stops once no taxel is left on (the further ANDs keep it clear); it is
    skipped when no taxel is on at both ends and midway of any window (none is held).
    """
    frames = a.shape[1]
    if 1 < n <= frames:
        mid = (n - 1) // 2
        ends = a[:, n - 1 :] & a[:, : frames - n + 1]
        ends &= a[:, mid : mid + ends.shape[1]]
        if not np.any(ends):
            return np.zeros_like(a)
    out = a.copy()
    span = 1
    while span < n and np.any(out):
        step = min(span, n - span)
        if step < out.shape[1]:  # each frame AND the one step before (NumPy buffers the overlap)
            out[:, step:] &= out[:, :-step]
        out[:, :step] = 0
        span += step
    return out


class ChunkCleaner:
    """Clean chunks of frames of ``n_arrays`` arrays of one shape (streaming, vectorised).

    Parameters
    ----------
    n_arrays : int
    shape : (rows, cols)
    config : CleaningConfig, optional

    Examples
    --------
    >>> import numpy as np
    >>> cleaner = ChunkCleaner(2, (8, 8))
    >>> img = np.zeros((2, 3, 8, 8), bool); img[:, 1:, 3:5, 3:5] = True
    >>> t = np.arange(3) * 0.05
    >>> cleaner.push(img, np.broadcast_to(t, (2, 3))).sum(axis=(2, 3)).tolist()
    [[0, 4, 4], [0, 4, 4]]
    """

    def __init__(
        self, n_arrays: int, shape: tuple[int, int], *, config: CleaningConfig | None = None
    ) -> None:
        self.n = int(n_arrays)
        self.shape = (int(shape[0]), int(shape[1]))
        self.config = CleaningConfig() if config is None else config
        self._ops = _backend(self.shape[1])
        self._taxels = self.shape[0] * self.shape[1]
        self.reset()

    def reset(self) -> None:
        """Forget every stream."""
        n = self.n
        blank = self._ops.pack(np.zeros((n, *self.shape), bool))  # (N, *word shape)
        self._seen = np.zeros(n, dtype=np.int64)
        self._t0 = np.zeros(n)
        self._dt = np.full(n, np.nan)
        self._n_stuck = np.full(n, 3, dtype=np.int64)  # until the frame interval is known
        self._n_release = np.full(n, release_frames_for(None, self.config), dtype=np.int64)
        self._since = ~blank  # all on: the AND of no frames
        self._iso_hist = np.zeros((n, 0, *blank.shape[1:]), blank.dtype)
        # armed (stuck) taxels: array, word, bit, frames read off since last on
        self._armed: tuple[NDArray[np.int64], ...] = tuple(
            np.zeros(0, dtype=np.int64) for _ in range(4)
        )
        self._prev = blank
        self._prev_passed = blank.copy()
        self._busy = np.ones(n, bool)  # some state that a clear chunk would change

    def push(self, images: NDArray[np.bool_], t_s: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Clean frames ``(N, T, rows, cols)`` bool taken at ``t_s`` ``(N, T)``, s: same shape.

        Arrays whose frames are all clear and whose state is at rest are
        skipped (their output is clear): a quiet array costs a test.
        """
        img = np.asarray(images)
        if img.ndim != 4 or img.shape[0] != self.n or img.shape[2:] != self.shape:
            raise InputError(
                f"images must have shape ({self.n}, T, {self.shape[0]}, {self.shape[1]}), "
                f"got {img.shape}"
            )
        n, t = img.shape[:2]
        out = np.zeros_like(img)
        if t == 0:
            return out
        touched: NDArray[np.bool_] = np.any(img.reshape(n, t * self._taxels), axis=1)
        sel, longest = self.select(t_s, touched)
        group = max(1, GROUP_FRAMES // t)  # arrays per pass: the temporaries stay in cache
        for a in range(0, sel.size, group):
            g = sel[a : a + group]
            out[g] = self.clean(img if g.size == n else img[g], g, longest)
        return out

    def select(
        self, t_s: NDArray[np.float64], touched: NDArray[np.bool_]
    ) -> tuple[NDArray[np.intp], int]:
        """Start a chunk taken at ``t_s`` ``(N, T)``: the arrays to :meth:`clean`, and a length.

        ``touched`` ``(N,)``: arrays with a taxel on in the chunk. Returns the
        arrays touched or :attr:`busy` (every other array's output is clear,
        and it needs nothing more), increasing, and the ``longest`` argument of
        :meth:`clean`. Every array returned must then be cleaned, once.
        """
        t = np.asarray(t_s, dtype=np.float64).reshape(self.n, -1)
        self._timing(t)
        self._seen += t.shape[1]
        longest = int(self._n_stuck.max())
        self._settle(np.flatnonzero(self._busy & ~touched))
        sel = np.flatnonzero(self._busy | touched)
        self._resize_hist(longest)
        return sel, longest

    def _settle(self, idle: NDArray[np.intp]) -> None:
        """Arrays ``idle`` get a clear chunk: those busy only with rule 1's running AND settle.

        With no last frame, no isolated taxel in the window and no masked
        taxel, a clear chunk only clears the taxels on since the stream began
        (a fresh array's state): that is done here, without cleaning it.
        """
        if idle.size == 0:
            return
        m = idle.size
        rest = ~(
            np.any(self._prev[idle].reshape(m, -1), axis=1)
            | np.any(self._prev_passed[idle].reshape(m, -1), axis=1)
            | np.any(self._iso_hist[idle].reshape(m, -1), axis=1)
            | np.isin(idle, self._armed[0])
        )
        done = idle[rest]
        self._since[done] = 0
        self._busy[done] = False

    def clean(self, img: NDArray[np.bool_], sel: NDArray[np.intp], longest: int) -> NDArray[Any]:
        """Cleaned frames ``(m, T, rows, cols)`` of arrays ``sel`` (from :meth:`select`)."""
        cleaned: NDArray[np.bool_] = self._ops.unpack(self._clean(img, sel, longest), self.shape[1])
        return cleaned.reshape(img.shape)

    def clean_packed(
        self, img: NDArray[Any], sel: NDArray[np.intp], longest: int, *, packed: bool = False
    ) -> NDArray[Any]:
        """As :meth:`clean`, the frames packed ``(m * T, rows, ...)`` (:attr:`ops`' words).

        ``packed``: ``img`` comes packed already, ``(m, T, rows, ...)``.
        """
        return self._clean(img, sel, longest, packed)

    @property
    def ops(self) -> PackedRows:
        """The packed rows the cleaning works on.

        :func:`~taxelkit.smart.packed_rows.backend_for` the array's width.
        """
        return self._ops

    @property
    def busy(self) -> NDArray[np.bool_]:
        """``(N,)``: arrays whose state a clear chunk would change (they must be cleaned)."""
        return self._busy.copy()

    def _resize_hist(self, longest: int) -> None:
        keep = max(0, longest - 1)
        h = self._iso_hist
        if h.shape[1] != keep:
            full = np.zeros((h.shape[0], keep, *h.shape[2:]), h.dtype)
            m = min(keep, h.shape[1])
            if m:
                full[:, keep - m :] = h[:, h.shape[1] - m :]
            self._iso_hist = full

    def _clean(
        self, img: NDArray[Any], sel: NDArray[np.intp], longest: int, packed: bool = False
    ) -> NDArray[Any]:
        """The cleaned frames of arrays ``sel`` (bool, or ``packed``), packed ``(m * T, ...)``."""
        ops, cfg = self._ops, self.config
        n, t = img.shape[:2]
        if packed:
            on = np.ascontiguousarray(img).reshape(n * t, *img.shape[2:])
        else:
            on = ops.pack(img.reshape(n * t, *self.shape))
        word = on.shape[1:]
        on3 = on.reshape(n, t, *word)
        # runs of equal raw frames: a frame's isolated taxels and bridging depend on it alone
        new = run_starts(on, t) if cfg.persistence else None
        first = run = per_run = None
        if new is not None and np.count_nonzero(new) <= RUNS_WORTH * new.size:
            first, run = np.flatnonzero(new), np.cumsum(new) - 1
            per_run = take_rows(on, first)
        stuck = self._stuck(on3, on, sel, longest, per_run, run) if cfg.stuck else None
        prev, prev_passed = self._prev[sel], self._prev_passed[sel]
        if per_run is not None and (stuck is None or not np.any(stuck)):
            assert first is not None and run is not None
            frames = _bridged(ops, per_run, np.zeros((), per_run.dtype), cfg)
            out, last_passed = clean_runs(ops, frames, first, run, t, prev, prev_passed, cfg)
            last = take_rows(frames, run[t - 1 :: t])
        else:
            a = _bridged(ops, on, np.zeros_like(on) if stuck is None else stuck, cfg)
            last = a.reshape(n, t, *word)[:, -1]
            new = None if per_run is None else run_starts(a, t)  # masking splits runs
            if new is not None and np.count_nonzero(new) <= RUNS_WORTH * new.size:
                first, run = np.flatnonzero(new), np.cumsum(new) - 1
                out, last_passed = clean_runs(
                    ops, take_rows(a, first), first, run, t, prev, prev_passed, cfg
                )
            else:

                def after(start: NDArray[Any], frames: NDArray[Any]) -> NDArray[Any]:
                    f3 = frames.reshape(n, t, *word)
                    joined = np.concatenate([start[:, None], f3[:, :-1]], axis=1)
                    return joined.reshape(frames.shape)

                out, passed = _clean(ops, a, prev, prev_passed, cfg, after)
                last_passed = passed.reshape(n, t, *word)[:, -1]
        self._prev[sel] = last
        self._prev_passed[sel] = last_passed
        armed = np.zeros(self.n, bool)  # after _stuck: this chunk's armed taxels
        armed[self._armed[0]] = True
        flat = self._iso_hist[sel].reshape(n, -1)
        self._busy[sel] = (
            np.any(last.reshape(n, -1), axis=1)
            | np.any(self._since[sel].reshape(n, -1), axis=1)
            | np.any(flat, axis=1)
            | armed[sel]
        )
        return out

    def _timing(self, t: NDArray[np.float64]) -> None:
        new = self._seen == 0
        self._t0[new] = t[new, 0]
        later = np.isnan(self._dt) & ((self._seen > 0) | (t.shape[1] > 1))
        first_next = np.where(self._seen > 0, t[:, 0], t[:, min(1, t.shape[1] - 1)])
        self._dt[later] = first_next[later] - self._t0[later]
        for i in np.flatnonzero(later).tolist():  # once per array
            dt = float(self._dt[i])
            self._n_stuck[i] = stuck_frames_for(dt, self.config)
            self._n_release[i] = release_frames_for(dt, self.config)

    def _stuck(
        self,
        on3: NDArray[Any],
        on: NDArray[Any],
        sel: NDArray[np.intp],
        longest: int,
        per_run: NDArray[Any] | None = None,
        run: NDArray[np.intp] | None = None,
    ) -> NDArray[Any]:
        """Rule 1's masked bits of frames ``on`` ``(m * T, ...)`` (``on3``: ``(m, T, ...)``).

        ``per_run``, ``run``: the frame of each run of equal frames and each
        frame's run, if at hand (a frame's isolated taxels are then found once a run).
        """
        ops = self._ops
        n, t = on3.shape[:2]
        prior = self._since[sel]
        if np.any(prior):
            since = np.bitwise_and.accumulate(
                np.concatenate([prior[:, None], on3], axis=1), axis=1
            )[:, 1:]
            self._since[sel] = since[:, -1]
        else:
            since = np.zeros_like(on3)
        if per_run is None or run is None:
            iso = (on & ~_neighbours8(ops, on)).reshape(on3.shape)
        else:
            iso = take_rows(per_run & ~_neighbours8(ops, per_run), run).reshape(on3.shape)
        n_stuck = self._n_stuck[sel]
        self._resize_hist(longest)
        hist = np.concatenate([self._iso_hist[sel], iso], axis=1)
        held = np.zeros_like(iso)
        if np.any(hist):  # no isolated taxel in the window: nothing held
            one = n_stuck.size and n_stuck.min() == n_stuck.max()
            for k in [int(n_stuck[0])] if one else np.unique(n_stuck).tolist():
                rows = np.flatnonzero(n_stuck == k)
                part = hist[rows] if rows.size < n else hist
                if part.shape[1] > t + k - 1:
                    part = part[:, -(t + k - 1) :]
                held[rows] = _held_along_time(part, k)[:, -t:]
        keep = self._iso_hist.shape[1]
        if keep:
            self._iso_hist[sel] = hist[:, hist.shape[1] - keep :]
        seed = since | held
        return self._release(on3, seed, sel).reshape(on.shape)

    def _release(
        self, on3: NDArray[Any], seed: NDArray[Any], sel: NDArray[np.intp]
    ) -> NDArray[Any]:
        """Masked bits: seeded, until read off ``n_release`` frames (per taxel, all at once)."""
        n, t = on3.shape[:2]
        on_f = on3.reshape(n, t, -1)
        seed_f = seed.reshape(n, t, -1)
        out = np.zeros_like(on_f)
        n_words, n_bits = on_f.shape[2], 8 * on_f.dtype.itemsize
        # the taxels armed before this chunk, numbered within sel
        local = np.full(self.n, -1, dtype=np.int64)
        local[sel] = np.arange(sel.size)
        li = local[self._armed[0]]
        inside = li >= 0  # all of them: an armed array is busy, hence in sel
        outside = tuple(a[~inside] for a in self._armed)
        arm_i, arm_j, arm_b, arm_off = li[inside], *(a[inside] for a in self._armed[1:])
        if arm_i.size == 0 and not np.any(seed_f):  # nothing armed, nothing seeded
            self._armed = outside
            return out.reshape(on3.shape)
        # the taxels seeded in this chunk, one (array, word, bit) each
        any_seed = np.bitwise_or.reduce(seed_f, axis=1)  # (n, words)
        si, sj = np.nonzero(any_seed)
        shifts = np.arange(n_bits, dtype=np.uint64)
        q, sb = np.nonzero((any_seed[si, sj].astype(np.uint64)[:, None] >> shifts) & np.uint64(1))
        si, sj = si[q], sj[q]
        fresh = ~np.isin(
            (si * n_words + sj) * n_bits + sb, (arm_i * n_words + arm_j) * n_bits + arm_b
        )
        ii = np.concatenate([arm_i, si[fresh]])
        if ii.size == 0:
            self._armed = outside
            return out.reshape(on3.shape)
        jj = np.concatenate([arm_j, sj[fresh]])
        bit_no = np.concatenate([arm_b, sb[fresh]])
        was = np.arange(ii.size) < arm_i.size
        off = np.concatenate([arm_off, np.full(int(fresh.sum()), 10**9, dtype=np.int64)])
        bits = np.left_shift(np.ones(ii.size, on_f.dtype), bit_no.astype(on_f.dtype))
        n_release = self._n_release[sel][ii][:, None]
        idx = np.arange(t)[None, :]
        # all the taxels at once, (K, T): the batch's per-taxel rule, carried over
        o = (on_f[ii, :, jj] & bits[:, None]) != 0
        s = (seed_f[ii, :, jj] & bits[:, None]) != 0
        last_on = np.maximum.accumulate(np.where(o, idx, (-1 - off)[:, None]), axis=1)
        released = (idx - last_on) >= n_release
        last_release = np.maximum.accumulate(
            np.where(released, idx, np.where(was, -2, -1)[:, None]), axis=1
        )
        last_seed = np.maximum.accumulate(np.where(s, idx, np.where(was, -1, -2)[:, None]), axis=1)
        masked = o & (last_seed > last_release)
        # the masked bits of each word: the taxels sorted by word, OR-ed per word
        word = ii * n_words + jj
        order = np.argsort(word, kind="stable")
        w_sorted = word[order]
        starts = np.flatnonzero(np.diff(w_sorted, prepend=-1))
        bitmap = np.where(masked[order], bits[order, None], on_f.dtype.type(0))
        words = np.bitwise_or.reduceat(bitmap, starts, axis=0)  # (words, T)
        wi = w_sorted[starts]
        out[wi // n_words, :, wi % n_words] = words
        still = last_seed[:, -1] > last_release[:, -1]
        frames_off = (t - 1 - last_on[:, -1]).astype(np.int64)
        kept = (sel[ii[still]].astype(np.int64), jj[still], bit_no[still], frames_off[still])
        self._armed = tuple(np.concatenate([a, b]) for a, b in zip(outside, kept, strict=True))
        return out.reshape(on3.shape)
