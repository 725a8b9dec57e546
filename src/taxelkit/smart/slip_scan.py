"""The slip detector of :mod:`taxelkit.smart.slip`, fed one contact segment a chunk at a time."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.slip import SLIP_KINDS, Slip, SlipConfig
from taxelkit.smart.slip_features import N_FEATURES, motion_mm, slip_features
from taxelkit.smart.slip_motion import window_decisions
from taxelkit.smart.slip_reference import scan_frames
from taxelkit.smart.slip_return import ReturnTest, drop_returns, first_hold_hit

__all__ = ["SlipScanner"]

_LINE = int(ContactClass.LINE)

#: Frames whose motions are computed together by the vectorised scan (the
#: window sums of a piece stay small enough for the cache).
_PIECE = 512

# Feature columns averaged over the windows (:mod:`taxelkit.smart.slip_features`).
_CX, _CY, _AREA_COL, _C2, _S2, _HALF, _ELONG = range(7)
_END1, _END2, _COV, _AREA2 = slice(7, 9), slice(9, 11), slice(11, 14), 14
_N_FEATURES = N_FEATURES


class SlipScanner:
    """Slip phases of one contact segment, fed a chunk of frames at a time.

    Parameters
    ----------
    cls : int
        The segment's :class:`~taxelkit.smart.contact_classes.ContactClass`
        (points and other classes report nothing).
    config : SlipConfig
    k : int
        Frames whose median interval fixes the frame rate (the debounce ``k``).
    reference : bool
        Decide frame by frame in Python (the rule as written, kept as the
        reference the vectorised scan is tested against). By default a
        chunk's motions are computed at once (:mod:`taxelkit.smart.slip_motion`)
        and the scan jumps from decision to decision; the slips are the same.
    pitch_mm : float
        Taxel pitch, mm (0: unknown), for
        :attr:`~taxelkit.smart.slip.SlipConfig.line_length_pitches`.

    Notes
    -----
    Keeps the features of the last ``max(current + reference + return, 2 end)``
    frames (``return``: a line's ``line_return_s``, else 0) and a few numbers.

    Examples
    --------
    >>> import numpy as np
    >>> scan = SlipScanner(int(ContactClass.AREA), SlipConfig(), k=2)
    >>> rows = np.zeros((40, 9)); rows[:, 3] = 50.0; rows[:, 4] = 1.0
    >>> rows[:, 8] = np.arange(40) / 20; rows[20:, 0] = np.arange(20) * 0.25  # 5 mm/s from 1 s
    >>> [(s.first_frame, s.detected_frame) for s in scan.extend(np.arange(40), rows)]
    [(21, 23)]
    """

    def __init__(
        self,
        cls: int,
        config: SlipConfig,
        *,
        k: int = 2,
        reference: bool = False,
        pitch_mm: float = 0.0,
    ) -> None:
        self.cls = int(cls)
        pitch = float(pitch_mm)
        #: a line's largest difference of its two ends' moves, mm (inf: no test)
        self.length_mm = config.line_length_pitches * pitch if pitch > 0.0 else math.inf
        self.reference = bool(reference)
        self.config = config
        self.k = max(2, int(k))
        self.slips: list[Slip] = []
        self._active = self.cls in SLIP_KINDS
        self._t_head: list[float] = []
        self._ready = False
        self._buf = np.zeros((0, _N_FEATURES))
        self._u_last: NDArray[np.float64] | None = None  # the last line's axis, oriented
        self._buf_frames = np.zeros(0, np.intp)
        self._n = 0  # frames seen
        self._anchor = 0  # segment index where the reference may start
        self._above: list[bool] = []  # the last ``hold`` decided frames: motion above the limit
        self._open: Slip | None = None
        self._open_i = 0  # segment index of the open slip's first frame

    @property
    def kept_features(self) -> NDArray[np.float64]:
        """The features ``(n, 15)`` of the last frames kept for the next windows."""
        return self._buf

    @property
    def last_axis(self) -> NDArray[np.float64] | None:
        """A line's last oriented axis ``(2,)`` (None before its first frame, or not a line)."""
        return self._u_last

    # -- set-up ------------------------------------------------------------------------------
    def _start(self) -> None:
        steps = sorted(b - a for a, b in zip(self._t_head, self._t_head[1:], strict=False))
        mid = len(steps) // 2
        dt = steps[mid] if len(steps) % 2 else 0.5 * (steps[mid - 1] + steps[mid])
        cfg = self.config

        def frames(seconds: float, least: int) -> int:
            return max(least, math.ceil(seconds / dt - 1e-9)) if dt > 0 else least

        self.cur = frames(cfg.current_s, 2)
        self.ref = frames(cfg.line_reference_s if self.cls == _LINE else cfg.reference_s, 2)
        self.end = frames(cfg.end_s, 2)
        self.hold = max(0, round(cfg.hold_s / dt)) + 1 if dt > 0 else 1  # frames spanning hold_s
        self.hold_needed = max(1, math.ceil(cfg.hold_fraction * self.hold - 1e-9))
        self._limit_mm = cfg.line_slip_mm if self.cls == _LINE else cfg.slip_mm
        # a line: frames before the reference it may be back at (line_return_s), and
        # whether one frame lies in every current window of the hold (line_jump_back)
        back = frames(cfg.line_return_s, 1) if self.cls == _LINE and cfg.line_return_s else 0
        jump = self.cls == _LINE and cfg.line_jump_back and self.hold <= self.cur
        rest = frames(cfg.line_reseat_s, 1) if self.cls == _LINE and cfg.line_reseat_s else 0
        reseat = cfg.line_slip_mm if rest else 0.0
        self._back: ReturnTest | None = None
        if back or jump or rest:
            self._back = ReturnTest(
                self.cur, self.ref, back, jump, cfg.line_return_mm, cfg.area_step, reseat, rest
            )
        self.keep = max(self.cur + self.ref + max(back, rest), 2 * self.end)
        self._ready = True

    def features(self, rows: NDArray[np.float64]) -> NDArray[np.float64]:
        """Per-frame features ``(m, 15)`` from rows ``(m, 9)`` (segment_scan's ``ROW_COLUMNS``).

        Centre, area, doubled-angle axis, half-length, elongation, a line's
        two ends (its drawn extent along its axis, the axis oriented like the
        previous frame's so that the ends keep their order), a face's
        second central moments and the area squared. The vectorised scan leaves the columns its
        class does not read at 0 (a face's ends, a line's moments).
        """
        out, u = self.segment_features(rows)
        if u is not None and rows.shape[0]:
            self._u_last = u[-1].copy()
        return out

    def segment_features(
        self, rows: NDArray[np.float64], starts: NDArray[np.intp] | None = None
    ) -> tuple[NDArray[np.float64], NDArray[np.float64] | None]:
        """:meth:`features` of rows ``(m, 9)``, and a line's oriented axes ``(m, 2)`` (else None).

        ``starts``: the rows hold several segments laid end to end (see
        :func:`~taxelkit.smart.slip_features.slip_features`); None: one
        segment that continues this scanner's.
        """
        return slip_features(
            rows,
            line=self.cls == _LINE,
            every=self.reference,
            u_last=self._u_last,
            starts=starts,
        )

    # -- the motion measure --------------------------------------------------------------------
    def motion_mm(self, ref: NDArray[np.float64], cur: NDArray[np.float64]) -> float:
        """How far the footprint moved from mean features ``ref`` to ``cur`` ``(15,)``, mm.

        :func:`~taxelkit.smart.slip_features.motion_mm` of this scanner's class.
        """
        line = self.cls == _LINE
        return motion_mm(ref, cur, line=line, config=self.config, length_mm=self.length_mm)

    # -- feeding ---------------------------------------------------------------------------------
    def prime(self, t_s: NDArray[np.float64]) -> bool:
        """Fix the frame rate from a new segment's first times ``t_s`` before it is extended.

        Whether the rate is fixed (the window lengths :attr:`cur`, :attr:`ref`
        known): the batch path (:mod:`taxelkit.smart.slip_batch`) groups
        segments by them. :meth:`extend` then behaves as without it.
        """
        if self._active and not self._ready and self._n == 0 and t_s.size >= self.k:
            self._t_head = t_s[: self.k].tolist()
            self._start()
        return self._ready

    def extend(
        self,
        frames: NDArray[np.intp],
        rows: NDArray[np.float64],
        *,
        features: tuple[NDArray[np.float64], NDArray[np.float64] | None] | None = None,
        decided: tuple[NDArray[np.bool_], NDArray[np.bool_]] | None = None,
    ) -> list[Slip]:
        """Add frames ``(m,)`` with their rows ``(m, 9)``; the slips opened or closed by them.

        ``features`` (:meth:`features` of the rows, and the last line axis it
        leaves) and ``decided`` (:meth:`decisions` of the first scan of a
        primed segment) may come computed, for many segments at once
        (:mod:`taxelkit.smart.slip_batch`).

        Returns
        -------
        list of Slip
            New slips (open) and slips whose end was decided here (closed), in
            order; a slip opened and closed in one chunk is returned once, closed.
        """
        m = int(frames.size)
        if m == 0 or not self._active:
            self._n += m
            return []
        if not self._ready:
            self._t_head += rows[: self.k - len(self._t_head), 8].tolist()
        if features is None:
            feats = self.features(rows)
        else:
            feats, u_last = features
            if u_last is not None:
                self._u_last = u_last
        x = np.concatenate([self._buf, feats])
        fr = np.concatenate([self._buf_frames, np.asarray(frames, np.intp)])
        n_old = self._buf.shape[0]
        base = self._n - n_old  # segment index of x[0]
        self._n += m
        if not self._ready:
            if len(self._t_head) < self.k:
                self._buf, self._buf_frames = x, fr
                return []
            self._start()
            n_old = 0  # every frame so far is new to the scan
        if self.reference:
            out = self._scan_frames(x, fr, base, n_old)
        else:
            out = self._scan_chunk(x, fr, base, n_old, decided)
        self._buf, self._buf_frames = x[-self.keep :], fr[-self.keep :]
        return out

    def _scan_frames(
        self, x: NDArray[np.float64], fr: NDArray[np.intp], base: int, first: int
    ) -> list[Slip]:
        """Decide frames ``x[first:]`` one by one: the rule as written.

        :func:`~taxelkit.smart.slip_reference.scan_frames`.
        """
        return scan_frames(self, x, fr, base, first)

    # -- the vectorised scan ------------------------------------------------------------------
    def decisions(
        self,
        x: NDArray[np.float64],
        a0: int,
        wa: int,
        b0: int,
        wb: int,
        count: int,
        limit: float,
        piece: int = _PIECE,
    ) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
        """:func:`~taxelkit.smart.slip_motion.window_decisions` for this scanner's class."""
        return window_decisions(
            x,
            a0,
            wa,
            b0,
            wb,
            count,
            limit,
            line=self.cls == _LINE,
            config=self.config,
            piece=piece,
            length_mm=self.length_mm,
        )

    def _onset(self, flags: NDArray[np.bool_]) -> int | None:
        """First of a run of decided frames ``flags`` (motion above the limit) that opens a slip.

        The run continues the hold kept in ``_above``; without an onset, the
        hold is kept for the next frames.
        """
        if not flags.any():  # no onset without a frame above the limit: the hold moves on
            tail = [*self._above, *([False] * min(flags.size, self.hold))]
            self._above = tail[len(tail) - min(self.hold, len(tail)) :]
            return None
        hit = first_hold_hit(self._above, flags, self.hold, self.hold_needed)
        if hit is not None:
            return hit
        seq = [*self._above, *flags[-self.hold :].tolist()]
        self._above = seq[len(seq) - min(self.hold, len(seq)) :]
        return None

    def _scan_chunk(
        self,
        x: NDArray[np.float64],
        fr: NDArray[np.intp],
        base: int,
        first: int,
        decided: tuple[NDArray[np.bool_], NDArray[np.bool_]] | None = None,
    ) -> list[Slip]:
        """:meth:`_scan_frames`, jumping from decision to decision over vectorised motions.

        ``decided``: the first :meth:`decisions` below, computed already.
        """
        c, r, e = self.cur, self.ref, self.end
        n = x.shape[0]
        p0 = max(first, c + r - 1)  # the first frame with a full reference in the buffer
        changed = above = np.zeros(0, bool)
        if decided is not None:
            changed, above = decided
        elif p0 < n:
            changed, above = self.decisions(
                x, p0 - c - r + 1, r, p0 - c + 1, c, n - p0, self._limit_mm
            )
        re_anchor = np.flatnonzero(changed) + p0
        out: list[Slip] = []
        p = first
        while p < n:
            if self._open is None:
                s = max(p, self._anchor + c + r - 1 - base)  # the reference after the anchor
                if s >= n:
                    break
                assert s >= p0
                k = int(np.searchsorted(re_anchor, s))
                stop = int(re_anchor[k]) if k < re_anchor.size else n
                q = self._first_onset(above[s - p0 : stop - p0], x, base, s)
                if q is not None:
                    p = s + q
                    onset = max(0, p - self.hold - c + 2)
                    self._open_i = base + onset
                    self._open = Slip(SLIP_KINDS[self.cls], int(fr[onset]), int(fr[p]))
                    self._above = []
                    out.append(self._open)
                elif stop < n:
                    self._anchor, self._above = base + stop - c + 1, []
                    p = stop
                else:
                    break
            else:
                s = max(p, 2 * e - 1, self._open_i - base + e - 1)  # the last window: all slip
                if s >= n:
                    break
                end = self._slip_end(x, s, n)
                if end is None:
                    break
                p = end
                self._end_open(out, fr, p, base + p - e + 1)
            p += 1
        return out

    def _first_onset(
        self, above: NDArray[np.bool_], x: NDArray[np.float64], base: int, s: int
    ) -> int | None:
        """:meth:`_onset` of the decided frames ``above`` (frames ``s`` on of ``x``).

        A line's frames that are back where it was are dropped first, block
        by block (blocks that grow fourfold from 256 frames, each continuing
        the hold as a new chunk would), so that the search costs what the
        frames cost however many are dropped.
        """
        if self._back is None or not above.any():
            return self._onset(above)
        lo, size = 0, 256
        while lo < above.size:
            m = min(size, above.size - lo)
            flags = above[lo : lo + m]
            if flags.any():
                flags = self._drop_returns(flags, x, base, s + lo)
            q = self._onset(flags)
            if q is not None:
                return lo + q
            lo, size = lo + m, 4 * size
        return None

    def _slip_end(self, x: NDArray[np.float64], s: int, n: int) -> int | None:
        """The first frame from ``s`` (of ``n`` in ``x``) at which the open slip ends, or None.

        The end test (the footprint still, or the contact changed) is
        computed over blocks of frames that grow fourfold from 64, so that a
        segment holding many slips costs what its frames cost, not what each
        slip's remaining frames cost (the decisions are the rule's, block
        by block).
        """
        e, lo, size = self.end, s, 64
        while lo < n:
            m = min(size, n - lo)
            changed, moving = self.decisions(
                x, lo - 2 * e + 1, e, lo - e + 1, e, m, self.config.still_mm
            )
            ended = np.flatnonzero(changed | ~moving)  # still (or the contact changed)
            if ended.size:
                return lo + int(ended[0])
            lo, size = lo + m, 4 * size
        return None

    def _drop_returns(
        self, flags: NDArray[np.bool_], x: NDArray[np.float64], base: int, s: int
    ) -> NDArray[np.bool_]:
        """``flags`` (frames ``s`` on of ``x``) less those at which a line is back."""
        test = self._back
        assert test is not None
        return drop_returns(
            flags,
            self.hold,
            lambda f: first_hold_hit(self._above, f, self.hold, self.hold_needed),
            lambda js: test.returned(x, s + js, self._anchor - base),
        )

    def _end_open(self, out: list[Slip], fr: NDArray[np.intp], p: int, anchor: int) -> None:
        """The open slip's end was decided at row ``p`` of frames ``fr``; the reference restarts.

        The end is dated ``1.5 end`` frames earlier (no earlier than its
        start); the next reference may start at segment index ``anchor``.
        """
        assert self._open is not None
        e, slip = self.end, self._open
        last = max(slip.first_frame, int(fr[p - e - e // 2]))
        self._replace(out, Slip(slip.kind, slip.first_frame, slip.detected_frame, last, int(fr[p])))
        self._open, self._anchor = None, anchor

    def _replace(self, out: list[Slip], done: Slip) -> None:
        self.slips.append(done)
        if out and out[-1].detected_frame == done.detected_frame:
            out[-1] = done
        else:
            out.append(done)

    def close(self) -> list[Slip]:
        """The segment ended: an open slip ends at its last frame (returned, closed)."""
        if self._open is None:
            return []
        last = int(self._buf_frames[-1]) if self._buf_frames.size else self._open.detected_frame
        done = Slip(self._open.kind, self._open.first_frame, self._open.detected_frame, last, last)
        self._open = None
        self.slips.append(done)
        return [done]

    def all_slips(self) -> list[Slip]:
        """Every slip so far: the ended ones, then the one going on (if any)."""
        return [*self.slips, *([] if self._open is None else [self._open])]
