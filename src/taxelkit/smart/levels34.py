"""Levels 3-4 over accepted runs, shared by the batch recogniser, the streaming sensor and the bank.

A contact segment is seen through a small interface (:class:`Segment`): its
size, first frames, mean axis and motion tactemes. The batch path wraps a
whole :class:`~taxelkit.smart.tactemes.SegmentTrack` (:class:`TrackSegment`);
the streaming paths feed a :class:`~taxelkit.smart.segment_scan.SegmentScanner`
a chunk at a time. The state machine below does not know which.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.elimination import Eliminator, Event, Verdict, explain
from taxelkit.smart.object_table import ObjectTable
from taxelkit.smart.slip import SLIP_KINDS, Slip, slip_to_json
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.tactemes import TactemeConfig
from taxelkit.smart.track_segment import TrackSegment, track_segments
from taxelkit.smart.transitions import transition_tactemes

__all__ = ["Levels34", "Recognition", "Segment", "TrackSegment", "finish", "track_segments"]

#: Tactemes only slip produces (they eliminate every object): with slip
#: detection on they are evidence of slip, not of shape, and never eliminate.
SLIDING_TACTEMES = frozenset(
    {Tacteme.AC_MOVES, Tacteme.AC_ROTATES, Tacteme.LC_SLIDES, Tacteme.LC_SPINS}
)

#: What a slip going on can fake besides the sliding tactemes (held back from
#: elimination from the slip's decision to its end). A line sliding along itself
#: moves its middle, by which the pivot of its turn is judged: a truncated cone
#: rolled about its virtual apex and then slid along its line towards that apex
#: reads "about one end" (its pivot ratio fell from 1.5 to 1.0 half-lengths over the
#: slide: ``slip-heldout``, seed 11, kinematic partial-slip truncated cone 24 at 20
#: frames/s, named cone), so a line's two pivot tactemes are held back while it
#: slips. Tried when the line-slip detector still fired on MuJoCo cones' jittering
#: lines (before ``SlipConfig.line_across_mm`` and ``line_return_s``), holding them
#: back left 27 and 13 more of 160 MuJoCo cone trials undecided at 5 and 20
#: frames/s; now ``robustness`` (seed 0) and ``robustness-heldout`` give the same
#: outcomes with and without it. A slide the detector misses still moves the pivot
#: (``make_partial_slip_scenario("truncated-cone", rng=60)`` at 20 frames/s is named
#: cone). A face sliding fakes only the sliding tactemes.
FAKED_BY_SLIP: dict[str, frozenset[Tacteme]] = {
    SLIP_KINDS[int(ContactClass.LINE)]: frozenset({Tacteme.LCMT_ABOUT_END, Tacteme.LCMT_ARC}),
    SLIP_KINDS[int(ContactClass.AREA)]: frozenset(),
}

_BASIC = {
    int(ContactClass.POINT): Tacteme.PC,
    int(ContactClass.LINE): Tacteme.LC,
    int(ContactClass.AREA): Tacteme.AC,
}


class Segment(Protocol):
    """What Levels 3-4 read of a contact segment (frames seen so far)."""

    size: int
    first_frame: int
    last_frame: int

    @property
    def pitch_mm(self) -> float: ...

    def frames_for(self, seconds: float, k: int, *, minimum: int | None = None) -> int: ...
    def frame_interval_s(self, k: int) -> float: ...
    def jump_frame(self) -> int | None: ...
    def frame_at(self, i: int) -> int: ...
    def mean_axis_deg(self, stop: int | None = None) -> float: ...
    def mean_centre_mm(self, stop: int) -> tuple[float, float]: ...
    def grid_wobble_deg(self, stop: int) -> float: ...
    def tactemes(self) -> list[tuple[Tacteme, int]]: ...
    def slips(self) -> list[Slip]: ...
    def close_slips(self) -> list[Slip]: ...


@dataclass(frozen=True, eq=False)
class Recognition:
    """What the smart sensor concluded from a recording.

    Attributes
    ----------
    classes : (T,) int8
        Level 2 class of every frame.
    tactemes : tuple of (str, int)
        Level 3 tactemes with the frame at which each was seen.
    events : tuple of Event
        Everything in order.
    identified : str or None
        The object of the last contact, ``"unknown"``, or None if undecided;
        a last contact too brief to rule out anything is passed over
        (:attr:`~taxelkit.smart.tactemes.TactemeConfig.blip_s`,
        :attr:`Verdict.passed_over <taxelkit.smart.elimination.Verdict.passed_over>`).
    candidates : tuple of str
        Objects not yet eliminated for that contact.
    verdict : Verdict
        Why: what ruled out each object of the last contact and, when
        undecided, which tactemes (motions) would decide; whether it slid.
    slips : tuple of Slip
        Slip phases of every contact, in order (:mod:`taxelkit.smart.slip`).
    """

    classes: NDArray[np.int8]
    tactemes: tuple[tuple[str, int], ...]
    events: tuple[Event, ...]
    identified: str | None
    candidates: tuple[str, ...]
    verdict: Verdict
    slips: tuple[Slip, ...] = ()

    def class_names(self) -> list[str]:
        """Per-frame class names (``"none"``, ``"indeterminate"``, ``"point"``, ...)."""
        return [ContactClass(int(c)).name.lower() for c in self.classes]

    def to_json(self) -> dict[str, Any]:
        """``identified``, ``candidates``, ``tactemes`` and ``classes`` as JSON types."""
        return {
            "identified": self.identified,
            "candidates": list(self.candidates),
            "why": self.verdict.to_json(),
            "tactemes": [{"name": n, "frame": f} for n, f in self.tactemes],
            "slips": [slip_to_json(s) for s in self.slips],
            "classes": self.class_names(),
        }


class Levels34:
    """Levels 3-4 state over accepted runs.

    Parameters
    ----------
    config : TactemeConfig
    """

    def __init__(self, config: TactemeConfig, frame_interval_s: float | None = None) -> None:
        self.config = config
        # the recording's frame interval (its first), s: None until known
        self.frame_interval_s = frame_interval_s
        self.k = int(config.debounce_frames)
        self.elim = Eliminator.for_table(config.objects)
        self.history: list[tuple[int, float]] = []
        self.centres: list[tuple[float, float]] = []  # of the history's segments
        self.wobbles: list[float] = []  # the grid's share of each segment's axis, deg
        self.in_contact = False
        self.events: list[Event] = []
        self._open: tuple[int, set[Tacteme]] | None = None  # class, motion tactemes emitted
        self._last_frame = -1  # last frame of the previous contact segment
        self._gap = 0  # frames between the previous contact segment and the open one
        self._len = 0  # frames of the open (then previous) segment
        self._prev_len = 0
        self._held = 0
        self._prev_held = 0
        self._transitions_done = True
        self._seg: Segment | None = None
        self._slips_seen: dict[int, Slip] = {}  # the open segment's, by detection frame
        self.slips: dict[int, Slip] = {}  # every slip by detection frame (latest state)
        # the frame interval of the current (or last) contact's segments whose motion was
        # not read (TactemeConfig.max_motion_gap_s), s; None: every segment's was
        self.unread_gap_s: float | None = None

    def open_run(self, cls: int, accept: int, seg: Segment | None) -> None:
        """A new class was accepted at frame ``accept``; ``seg`` holds its frames so far."""
        self.close_run(accept)
        if cls == ContactClass.NONE:
            if self.in_contact:
                self.events.append(Event("lifted", accept, self.elim.candidates))
                self.elim.reset()
                self.history = []
                self.centres = []
                self.wobbles = []
                self.in_contact = False
            return
        assert seg is not None  # a contact class always has frames
        if not self.in_contact:
            self.unread_gap_s = None
        self.in_contact = True
        self.events.append(Event("contact", accept, ContactClass(cls).name.lower()))
        self.history.append((cls, seg.mean_axis_deg(self.k)))
        self.centres.append(seg.mean_centre_mm(self.k))
        self.wobbles.append(seg.grid_wobble_deg(self.k))
        self._gap = seg.first_frame - self._last_frame - 1
        self._prev_len = self._len
        self._prev_held = self._held
        self.events.extend(self.elim.apply(_BASIC[cls], accept))
        self._open = (cls, set())
        self._seg = seg
        self._slips_seen = {}
        self._transitions_done = False
        self.update(seg)

    def update(self, seg: Segment) -> None:
        """The open segment grew: emit its new motion tactemes (detection is causal)."""
        if self._open is None:
            return
        cls, done = self._open
        # sparse frames (max_motion_gap_s): the first frame the contact jumped to
        dt, gap = self.frame_interval_s, self.config.max_motion_gap_s
        jump = seg.jump_frame() if gap > 0 and dt is not None and dt > gap else None
        # Transitions need a held edge (2 k frames of line): a round face tipping
        # onto its rim shrinks through a lens that reads as a line for a moment.
        held = seg.frames_for(self.config.edge_hold_s, self.k)
        line_before = self.history[-2][0] == ContactClass.LINE if len(self.history) > 1 else False
        ready = (
            seg.size >= held
            if cls == ContactClass.LINE
            else (not line_before or self._prev_len >= self._prev_held)
        )
        if not self._transitions_done and ready:
            self._transitions_done = True
            if cls == ContactClass.LINE:  # the new edge's direction over its held frames
                self.history[-1] = (cls, seg.mean_axis_deg(held))
                self.centres[-1] = seg.mean_centre_mm(held)
                self.wobbles[-1] = seg.grid_wobble_deg(held)
                if jump is not None and jump <= seg.frame_at(min(seg.size, held) - 1):
                    self.wobbles[-1] = math.inf  # two edges, not one: no angle read
            at = (
                seg.frame_at(min(seg.size, held) - 1)
                if cls == ContactClass.LINE
                else (seg.frame_at(self.k - 1) if seg.size >= self.k else seg.last_frame)
            )
            max_gap = max(2 * self.k, seg.frames_for(self.config.transition_gap_s, self.k))
            found = transition_tactemes(
                self.history,
                self.config,
                gap_frames=self._gap,
                max_gap_frames=max_gap,
                centres=self.centres,
                wobbles_deg=self.wobbles,
                pitch_mm=seg.pitch_mm,
            )
            for tac in found:
                self.events.extend(self.elim.apply(tac, at))
        motions = [(frame, 1, tac) for tac, frame in seg.tactemes() if tac not in done]
        if jump is not None and motions:  # sparse frames, the contact jumped: not followed
            kept = [m for m in motions if m[0] < jump]
            if len(kept) < len(motions):
                self.unread_gap_s = seg.frame_interval_s(self.k)
            motions = kept
        done.update(tac for _, _, tac in motions)
        self._apply_in_order(motions, self._new_slips(seg.slips()))
        self._len = seg.size
        self._held = held
        # a line's direction over all its frames (held still, an edge dominates its tips)
        self.history[-1] = (cls, seg.mean_axis_deg())
        if jump is not None and cls == ContactClass.LINE:
            self.wobbles[-1] = math.inf  # it jumped: no angle read from it as the edge before
        self._last_frame = seg.last_frame

    def _new_slips(self, slips: list[Slip]) -> list[tuple[int, int, Event]]:
        """Slip onsets and ends not yet reported, as ``(decision frame, 0, event)``."""
        out: list[tuple[int, int, Event]] = []
        for sl in slips:
            before = self._slips_seen.get(sl.detected_frame)
            if before is None:
                out.append((sl.detected_frame, 0, Event("slip", sl.first_frame, sl.kind)))
            ended = sl.last_frame is not None and sl.end_frame is not None
            if ended and (before is None or before.end_frame is None):
                assert sl.last_frame is not None and sl.end_frame is not None
                out.append((sl.end_frame, 0, Event("slip-end", sl.last_frame, sl.kind)))
            self._slips_seen[sl.detected_frame] = sl
            self.slips[sl.detected_frame] = sl
        return out

    def _withheld(self, tac: Tacteme, frame: int) -> bool:
        """Whether a tacteme found at ``frame`` is slip's evidence rather than shape's."""
        if self.config.slip is None:
            return False
        if tac in SLIDING_TACTEMES:
            return True
        return any(
            tac in FAKED_BY_SLIP.get(sl.kind, frozenset())
            and sl.detected_frame <= frame
            and (sl.end_frame is None or frame <= sl.end_frame)
            for sl in self._slips_seen.values()
        )

    def _apply_in_order(
        self, found: list[tuple[int, int, Tacteme]], slips: list[tuple[int, int, Event]]
    ) -> None:
        """Slip events and tactemes by the frame they were decided at (slips first)."""
        items: list[tuple[int, int, Tacteme | Event]] = [*slips, *found]
        items.sort(key=lambda item: (item[0], item[1]))
        for _, _, what in items:
            if isinstance(what, Event):
                self.events.append(what)
            elif self._withheld(what, _frame_of(what, found)):
                self.events.append(Event("withheld", _frame_of(what, found), what.value))
            else:
                self.events.extend(self.elim.apply(what, _frame_of(what, found)))

    def close_run(self, frame: int | None = None) -> None:
        """The open segment ended (a new class accepted at ``frame``)."""
        seg, self._seg = self._seg, None
        if seg is not None and self._open is not None:
            self._apply_in_order([], self._new_slips(seg.close_slips() + seg.slips()))
        self._open = None


@dataclass
class _Contact:
    """One contact as the events tell it: its frames, candidates, tactemes, slip."""

    first: int
    last: int | None  # the frame it was lifted at (None: still on)
    candidates: tuple[str, ...]
    seen: list[tuple[str, int]]
    slid: bool = False


def _contacts(events: list[Event], objects: tuple[str, ...]) -> list[_Contact]:
    """The contacts of ``events``, in order."""
    out: list[_Contact] = []
    current: _Contact | None = None
    for e in events:
        if e.kind == "contact" and current is None:
            current = _Contact(e.frame, None, objects, [])
            out.append(current)
        target = current if current is not None else (out[-1] if out else None)
        if target is None:
            continue
        if e.kind in ("slip", "withheld"):
            target.slid = True
        elif e.kind == "candidates":
            target.candidates = tuple(e.value)
        elif e.kind == "lifted":
            target.candidates = tuple(e.value)
            if current is not None:
                current.last, current = e.frame, None
        elif e.kind == "tacteme":
            target.seen.append((str(e.value), e.frame))
    return out


def _blip(
    c: _Contact, objects: tuple[str, ...], blip_s: float, dt: float | None, end: int | None
) -> bool:
    """A contact lifted within ``blip_s`` that ruled out nothing and did not slip.

    A contact still on counts up to ``end``, the recording's last frame (None: never a blip).
    """
    last = c.last if c.last is not None else end
    if last is None or dt is None or not blip_s > 0:
        return False
    return (last - c.first) * dt < blip_s and set(c.candidates) == set(objects) and not c.slid


def _frame_of(tac: Tacteme, found: list[tuple[int, int, Tacteme]]) -> int:
    return next(f for f, _, t in found if t == tac)


def finish(
    classes: NDArray[np.int8],
    events: list[Event],
    slips: list[Slip] | None = None,
    *,
    objects: ObjectTable | None = None,
    unread_gap_s: float | None = None,
    blip_s: float = 0.0,
    frame_interval_s: float | None = None,
    last_frame: int | None = None,
) -> Recognition:
    """Summarise: the outcome is that of the current contact, or of the last one lifted.

    ``slips``: the slip phases found; ``objects``: the object table the events
    were found with (None: the six); ``unread_gap_s``: that contact's frames
    were too sparse for its motion to be read (:attr:`Levels34.unread_gap_s`).
    ``blip_s``, ``frame_interval_s``: a contact lifted within ``blip_s`` that
    ruled out no object is passed over, and the summary is that of the
    contact before it (:attr:`~taxelkit.smart.tactemes.TactemeConfig.blip_s`).
    ``last_frame``: the recording's last frame; a contact still on then that
    began less than ``blip_s`` before it and ruled out no object is passed over
    too (it is cut off, too brief to tell; None: never).
    """
    tactemes = tuple((str(e.value), e.frame) for e in events if e.kind == "tacteme")
    state = Eliminator.for_table(objects)
    contacts = _contacts(events, state.objects)
    covered, passed = len(contacts) - 1, []
    while covered > 0 and _blip(
        contacts[covered], state.objects, blip_s, frame_interval_s, last_frame
    ):
        blip = contacts[covered]
        end = last_frame if blip.last is None else blip.last
        assert end is not None  # a contact still on is a blip only up to last_frame
        passed.append((blip.first, end))
        covered -= 1
    still_on = bool(passed) and contacts[-1].last is None
    last = contacts[covered] if contacts else None
    final = None if last is None else last.candidates
    state.candidates = state.objects if final is None else final
    verdict = explain(
        [] if last is None else last.seen,
        objects=state.objects,
        slid=last is not None and last.slid,
        table=objects,
        unread_gap_s=unread_gap_s if not passed else None,
        passed_over=tuple(reversed(passed)),
        still_on=still_on,
    )
    assert verdict.candidates == state.candidates  # the same elimination, told twice
    return Recognition(
        classes,
        tactemes,
        tuple(events),
        verdict.outcome,  # state.outcome, unless a rare reading withheld the name
        state.candidates,
        verdict,
        tuple(slips or ()),
    )
