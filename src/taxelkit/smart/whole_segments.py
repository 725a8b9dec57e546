"""Foresee the segments a chunk will close, to compute their tactemes elsewhere first.

:class:`~taxelkit.smart.stream_state.ArrayStream` debounces a chunk's Level 2
classes and computes the motion tactemes of every segment accepted and ended
within the chunk together (:func:`~taxelkit.smart.tactemes_batch.batch_tactemes`).
Those depend only on the segment's class, frames and rows, so another process
that has the classes and rows can compute them first:
:class:`WholeSegments` follows the same debounce over the chunks (the runs of
equal classes, the frames each class must hold, a segment's candidate frames
carried over a chunk's edge) and :meth:`WholeSegments.tactemes` returns each
such segment's tactemes keyed by its class and frames, the keys of
:attr:`ArrayStream.precomputed <taxelkit.smart.stream_state.ArrayStream.precomputed>`.

Nothing here decides anything: a segment foreseen wrongly is a key the stream
never asks for, and a segment not foreseen is computed by the stream itself,
so the result is the stream's either way; only the share of the work done
beforehand changes.
"""

from __future__ import annotations

import itertools

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.segment_head import track_from_rows
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.tactemes import TactemeConfig, debounce_counts
from taxelkit.smart.tactemes_batch import batch_tactemes

__all__ = ["WholeSegments"]

_NONE = int(ContactClass.NONE)
_INDET = int(ContactClass.INDETERMINATE)
_LINE = int(ContactClass.LINE)

Piece = tuple[NDArray[np.intp], NDArray[np.float64]]


class WholeSegments:
    """The contact segments each chunk accepts and ends, followed across chunks.

    Parameters
    ----------
    config : TactemeConfig
    pitch_mm : float
        Taxel pitch, mm (as the stream's tracks).
    line_share : float
        The share of the lines whose tactemes :meth:`tactemes` computes
        (every point and face is computed): a line costs several times a
        point or a face, and the other process has its own work, so a
        pipeline balances its two stages with it.
    """

    def __init__(self, config: TactemeConfig, pitch_mm: float, line_share: float = 1.0) -> None:
        self.config = config
        self.pitch_mm = float(pitch_mm)
        self.line_share = float(line_share)
        self._lines = 0.0  # the shares of lines counted so far
        self._j0 = 0  # the next chunk's first frame
        self._t_first: float | None = None
        self._dt: float | None = None
        self._accepted = _NONE
        self._open: list[Piece] | None = None  # the segment accepted in this chunk, if any
        self._cand: int | None = None
        self._cand_pieces: list[Piece] = []
        self._cand_n = 0

    def segments(
        self, classes: NDArray[np.int8], rows: NDArray[np.float64], t_s: NDArray[np.float64]
    ) -> list[tuple[int, NDArray[np.intp], NDArray[np.float64]]]:
        """The next chunk's segments accepted and ended within it: ``(class, frames, rows)``.

        Parameters
        ----------
        classes : (m,) int8
        rows : (m, 9) float
        t_s : (m,) float, s
        """
        m = int(classes.size)
        j0, self._j0 = self._j0, self._j0 + m
        if m == 0:
            return []
        if self._t_first is None:  # the stream's first interval, as ArrayStream._timing
            self._t_first = float(t_s[0])
            if m > 1:
                self._dt = float(t_s[1] - t_s[0])
        elif self._dt is None:
            self._dt = float(t_s[0]) - self._t_first
        k_contact, k_none = debounce_counts(self.config, self._dt)
        idx = np.flatnonzero(classes != _INDET)
        c = classes[idx]
        cut = np.flatnonzero(np.diff(c)) + 1
        bounds = np.concatenate([[0], cut, [c.size]]).tolist()
        out: list[tuple[int, NDArray[np.intp], NDArray[np.float64]]] = []
        for s, e in itertools.pairwise(bounds):
            cls = int(c[s])
            sel = idx[s:e]
            if cls == self._accepted:
                self._drop()
                if self._open is not None:
                    self._open.append((j0 + sel, rows[sel]))
                continue
            if cls != self._cand:
                self._drop()
                self._cand = cls
            need = (k_none if cls == _NONE else k_contact) - self._cand_n
            take = sel if sel.size > need and cls != _NONE else sel[:need]
            self._cand_pieces.append((j0 + take, rows[take]))
            self._cand_n += int(take.size)
            if take.size < need:
                continue
            if self._open is not None:  # the segment before ends here
                frames = np.concatenate([p[0] for p in self._open])
                out.append((self._accepted, frames, np.concatenate([p[1] for p in self._open])))
            self._accepted = cls
            self._open = None if cls == _NONE else self._cand_pieces
            self._cand_pieces = []
            self._drop()
        self._open = None  # open at the chunk's end: the stream scans it as it grows
        return out

    def _drop(self) -> None:
        self._cand, self._cand_pieces, self._cand_n = None, [], 0

    def tactemes(
        self, classes: NDArray[np.int8], rows: NDArray[np.float64], t_s: NDArray[np.float64]
    ) -> dict[tuple[int, bytes], list[tuple[Tacteme, int]]]:
        """The motion tactemes of :meth:`segments`, by ``(class, frames.tobytes())``."""
        found = []
        for item in self.segments(classes, rows, t_s):
            if item[0] == _LINE:  # every line whose share crosses a whole number
                before, self._lines = self._lines, self._lines + self.line_share
                if int(self._lines) == int(before):
                    continue
            found.append(item)
        if not found:
            return {}
        tracks = [(cls, track_from_rows(f, r, self.pitch_mm)) for cls, f, r in found]
        done = batch_tactemes(tracks, self.config)
        return {(cls, f.tobytes()): d for (cls, f, _), d in zip(found, done, strict=True)}
