"""The slip detector of :mod:`taxelkit.smart.slip`, fed one contact segment a chunk at a time."""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.slip import SLIP_KINDS, Slip, SlipConfig
from taxelkit.smart.slip_motion import AREA as _AREA_COL
from taxelkit.smart.slip_motion import C2 as _C2
from taxelkit.smart.slip_motion import COV as _COV
from taxelkit.smart.slip_motion import CX as _CX
from taxelkit.smart.slip_motion import CY as _CY
from taxelkit.smart.slip_motion import ELONG as _ELONG
from taxelkit.smart.slip_motion import END1 as _END1
from taxelkit.smart.slip_motion import END2 as _END2
from taxelkit.smart.slip_motion import (
    GUARD_MM,
    Windows,
    motions_area,
    motions_line,
    window_means,
)
from taxelkit.smart.slip_motion import HALF as _HALF
from taxelkit.smart.slip_motion import N_FEATURES as _N_FEATURES
from taxelkit.smart.slip_motion import S2 as _S2

__all__ = ["SlipScanner"]

_LINE = int(ContactClass.LINE)


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

    Notes
    -----
    Keeps the last ``reference + current + end`` frames' features and a few
    numbers. The rule is a scalar step per frame (:meth:`motion_mm` and the
    onset and end counts); a chunk's motions are computed at once and the
    steps jump from one decision to the next.

    Examples
    --------
    >>> import numpy as np
    >>> scan = SlipScanner(int(ContactClass.AREA), SlipConfig(), k=2)
    >>> rows = np.zeros((40, 9)); rows[:, 3] = 50.0; rows[:, 4] = 1.0
    >>> rows[:, 8] = np.arange(40) / 20; rows[20:, 0] = np.arange(20) * 0.25  # 5 mm/s from 0.95 s
    >>> [(s.first_frame, s.detected_frame) for s in scan.extend(np.arange(40), rows)]
    [(20, 21)]
    """

    def __init__(self, cls: int, config: SlipConfig, *, k: int = 2) -> None:
        self.cls = int(cls)
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
        self._count = 0  # frames in a row above slip_mm
        self._open: Slip | None = None
        self._open_i = 0  # segment index of the open slip's first frame

    # -- set-up ------------------------------------------------------------------------------
    def _start(self) -> None:
        steps = sorted(b - a for a, b in zip(self._t_head, self._t_head[1:], strict=False))
        mid = len(steps) // 2
        dt = steps[mid] if len(steps) % 2 else 0.5 * (steps[mid - 1] + steps[mid])
        cfg = self.config

        def frames(seconds: float, least: int) -> int:
            return max(least, math.ceil(seconds / dt - 1e-9)) if dt > 0 else least

        self.cur = frames(cfg.current_s, 2)
        self.ref = frames(cfg.reference_s, 2)
        self.end = frames(cfg.end_s, 2)
        self.hold = frames(cfg.hold_s, 1)
        self._limit_mm = cfg.line_slip_mm if self.cls == _LINE else cfg.slip_mm
        self.keep = max(self.cur + self.ref, 2 * self.end)
        self._ready = True

    def features(self, rows: NDArray[np.float64]) -> NDArray[np.float64]:
        """Per-frame features ``(m, 14)`` from rows ``(m, 9)`` (segment_scan's ``ROW_COLUMNS``).

        Centre, area, doubled-angle axis, half-length, elongation, and a
        line's two ends: its drawn extent along its axis, the axis oriented
        like the previous frame's so that the ends keep their order; for a
        face, its second central moments instead of the ends (the columns a
        class's motion does not read are zero).
        """
        m = rows.shape[0]
        theta = np.deg2rad(rows[:, 2])
        t2 = 2.0 * theta
        c, s_ = np.cos(theta), np.sin(theta)
        out = np.zeros((m, _N_FEATURES))
        out[:, _CX], out[:, _CY], out[:, _AREA_COL] = rows[:, 0], rows[:, 1], rows[:, 3]
        out[:, _C2], out[:, _S2], out[:, _HALF], out[:, _ELONG] = (
            np.cos(t2),
            np.sin(t2),
            rows[:, 5],
            rows[:, 4],
        )
        if self.cls == _LINE:  # the two ends (a face's motion does not read them)
            u = np.stack([c, s_], axis=-1)
            prev = np.concatenate([u[:1] if self._u_last is None else self._u_last[None], u[:-1]])
            flip = np.cumprod(np.where(np.einsum("ij,ij->i", u, prev) < 0.0, -1.0, 1.0))
            u = u * flip[:, None]
            if m:
                self._u_last = u[-1].copy()
            lo = np.where(flip > 0, rows[:, 6], -rows[:, 7])
            hi = np.where(flip > 0, rows[:, 7], -rows[:, 6])
            centre = rows[:, :2]
            out[:, _END1] = centre + lo[:, None] * u
            out[:, _END2] = centre + hi[:, None] * u
        else:  # the second moments (a line's motion does not read them)
            lam_max = rows[:, 5] ** 2 / 3.0  # half = sqrt(3 lambda_max)
            lam_min = lam_max / np.maximum(rows[:, 4], 1.0) ** 2  # elongation = sqrt(max / min)
            out[:, _COV.start] = lam_max * c * c + lam_min * s_ * s_
            out[:, _COV.start + 1] = lam_max * s_ * s_ + lam_min * c * c
            out[:, _COV.start + 2] = (lam_max - lam_min) * c * s_
        return out

    # -- the motion measure --------------------------------------------------------------------
    def motion_mm(self, ref: NDArray[np.float64], cur: NDArray[np.float64]) -> float:
        """How far the footprint moved from mean features ``ref`` to ``cur`` ``(7,)``, mm.

        NaN when the area changed by more than ``area_step`` (no decision).
        """
        cfg = self.config
        a_ref, a_cur = float(ref[_AREA_COL]), float(cur[_AREA_COL])
        if not a_ref > 0 or abs(a_cur / a_ref - 1.0) > cfg.area_step:
            return math.nan
        dx, dy = float(cur[_CX] - ref[_CX]), float(cur[_CY] - ref[_CY])
        if self.cls == _LINE:  # along the bisector of the two axes: a turn about a pivot cancels
            c2, s2 = float(ref[_C2] + cur[_C2]), float(ref[_S2] + cur[_S2])
            th = 0.5 * math.atan2(s2, c2)
            ax, ay = math.cos(th), math.sin(th)
            e1, e2 = cur[_END1] - ref[_END1], cur[_END2] - ref[_END2]
            d1, d2 = float(e1[0] * ax + e1[1] * ay), float(e2[0] * ax + e2[1] * ay)
            if math.isnan(d1 + d2):  # ends not measured: the centre less the change of length
                return abs(dx * ax + dy * ay) - abs(float(cur[_HALF] - ref[_HALF]))
            return min(abs(d1), abs(d2)) if d1 * d2 > 0.0 else 0.0  # both ends, the same way
        # both sides of the footprint must move: one that grows or shrinks on one side
        # moves its centre by half the change of its length along the motion
        moved = math.hypot(dx, dy)
        if moved > 0.0:
            nx, ny = dx / moved, dy / moved
            size = [
                math.sqrt(
                    12.0 * max(0.0, float(v[0] * nx * nx + v[1] * ny * ny + 2 * v[2] * nx * ny))
                )
                for v in (ref[_COV], cur[_COV])
            ]
            moved -= 0.5 * abs(size[1] - size[0])
        th_ref = 0.5 * math.atan2(float(ref[_S2]), float(ref[_C2]))
        if min(float(ref[_ELONG]), float(cur[_ELONG])) >= cfg.min_elongation:
            th_cur = 0.5 * math.atan2(float(cur[_S2]), float(cur[_C2]))
            turn = abs((th_cur - th_ref + 0.5 * math.pi) % math.pi - 0.5 * math.pi)
            moved = max(moved, turn * float(ref[_HALF]))
        return moved

    def _motions(
        self, ref: NDArray[np.float64], cur: NDArray[np.float64], limit_mm: float
    ) -> NDArray[np.float64]:
        """:meth:`motion_mm` of rows ``ref``, ``cur`` ``(K, F)``, to be compared with ``limit_mm``.

        Vectorised with the scalar's operations in its order
        (:mod:`~taxelkit.smart.slip_motion`); the few values within
        :data:`~taxelkit.smart.slip_motion.GUARD_MM` of ``limit_mm`` (where a
        last-bit difference of a library's ``atan2`` or ``hypot`` could flip the
        comparison) are recomputed by :meth:`motion_mm`, so every decision is
        the scalar's.
        """
        out = (
            motions_line(ref, cur)
            if self.cls == _LINE
            else motions_area(ref, cur, self.config.min_elongation)
        )
        ratio = cur[:, _AREA_COL] / ref[:, _AREA_COL] - 1.0
        out[~(ref[:, _AREA_COL] > 0) | (np.abs(ratio) > self.config.area_step)] = np.nan
        for i in np.flatnonzero(np.abs(out - limit_mm) <= GUARD_MM).tolist():
            out[i] = self.motion_mm(ref[i], cur[i])
        return out

    # -- feeding ---------------------------------------------------------------------------------
    def extend(self, frames: NDArray[np.intp], rows: NDArray[np.float64]) -> list[Slip]:
        """Add frames ``(m,)`` with their rows ``(m, 9)``; the slips opened or closed by them.

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
        feats = self.features(rows)
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
        out = self._scan(x, fr, base, n_old)
        self._buf, self._buf_frames = x[-self.keep :], fr[-self.keep :]
        return out

    def _scan(
        self, x: NDArray[np.float64], fr: NDArray[np.intp], base: int, first: int
    ) -> list[Slip]:
        """Decide frames ``x[first:]``; ``x[0]`` is segment frame ``base``.

        The rule is a scalar step per frame (:meth:`_scan_frames`); here the
        motions are computed for all frames at once and the steps jump from
        one decision (re-anchor, onset, end) to the next.
        """
        c, r, e, n = self.cur, self.ref, self.end, x.shape[0]
        out: list[Slip] = []
        p = first
        lo_x = max(0, first - c - r + 1)  # earliest row a window read here starts at
        search = end = None
        while p < n:
            if self._open is None:
                if search is None:
                    search = self._search_motions(x[lo_x:], first - lo_x)
                p = self._search(search, p - first, first, base, fr, out)
            else:
                if end is None:
                    end = Windows(x, e, max(0, p - 2 * e + 1))
                p = self._watch_end(end, p, base, fr, out)
        return out

    def _search_motions(self, x: NDArray[np.float64], first: int) -> NDArray[np.float64]:
        """Motion of frames ``x[first:]`` against their reference (NaN where none), mm."""
        c, r = self.cur, self.ref
        n = x.shape[0]
        out = np.full(n - first, np.nan)
        q0 = max(first, c + r - 1)  # the first frame with a full reference in x
        if q0 < n:
            cur_m = window_means(x[q0 - c + 1 :], c)
            ref_m = window_means(x[q0 - c - r + 1 : n - c], r)
            out[q0 - first :] = self._motions(ref_m, cur_m, self._limit_mm)
        return out

    def _search(
        self,
        motion: NDArray[np.float64],
        k: int,
        first: int,
        base: int,
        fr: NDArray[np.intp],
        out: list[Slip],
    ) -> int:
        """No slip open: step frames ``first + k ...`` to the next decision; the next frame."""
        c, r, hold = self.cur, self.ref, self.hold
        m = motion.size
        while k < m:
            k = max(k, self._anchor + c + r - 1 - base - first)  # a full reference after the anchor
            if k >= m:
                break
            seg = motion[k:]
            nan = np.flatnonzero(np.isnan(seg))
            stop = seg.size if nan.size == 0 else int(nan[0])
            above = seg[:stop] > self._limit_mm
            # frames in a row above the limit at each frame, the count carried in
            below = np.flatnonzero(~above)
            run = np.arange(1, stop + 1) + self._count
            if below.size:
                last_below = np.maximum.accumulate(np.where(~above, np.arange(stop), -1))
                run = np.where(last_below >= 0, np.arange(stop) - last_below, run)
            onset = np.flatnonzero(run >= hold)
            if onset.size:
                q = k + int(onset[0])
                p = first + q
                q0 = max(0, p - hold - c + 2)
                self._open_i = base + q0
                self._open = Slip(SLIP_KINDS[self.cls], int(fr[q0]), int(fr[p]))
                self._count = 0
                out.append(self._open)
                return p + 1
            if nan.size == 0:
                self._count = int(run[-1]) if stop else self._count
                return first + m
            self._anchor, self._count = base + first + k + stop - c + 1, 0
            k += stop + 1
        return first + m

    def _watch_end(
        self, end: Windows, p: int, base: int, fr: NDArray[np.intp], out: list[Slip]
    ) -> int:
        """A slip open: step frames ``p ...`` to its end; the next frame to decide."""
        assert self._open is not None
        e, n = self.end, fr.size
        p = max(p, 2 * e - 1, self._open_i - base + e - 1)  # the last window: all slip
        if p >= n:
            return n
        step = self._motions(
            end.rows(p - 2 * e + 1, n - 2 * e + 1),
            end.rows(p - e + 1, n - e + 1),
            self.config.still_mm,
        )
        still = np.flatnonzero(~(step > self.config.still_mm))
        if still.size == 0:
            return n
        p += int(still[0])
        done = Slip(
            self._open.kind,
            self._open.first_frame,
            self._open.detected_frame,
            max(self._open.first_frame, int(fr[p - e - e // 2])),
            int(fr[p]),
        )
        self._replace(out, done)
        self._open, self._anchor = None, base + p - e + 1
        return p + 1

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
