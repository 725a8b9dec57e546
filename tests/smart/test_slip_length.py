"""A line sliding along itself keeps its length (``SlipConfig.line_length_pitches``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.slip import SlipConfig
from taxelkit.smart.slip_features import motion_mm
from taxelkit.smart.slip_motion import motions_mm
from taxelkit.smart.slip_scan import SlipScanner

from .test_slip import _stepping_line, line_rows_between

LINE = int(ContactClass.LINE)
PITCH = 1.7625


def _features(centre_x: float, lo: float, hi: float) -> np.ndarray:
    """Mean features ``(15,)`` of a line along x from ``centre_x + lo`` to ``centre_x + hi``."""
    f = np.zeros(15)
    f[0], f[2], f[3] = centre_x, 28.0, 1.0  # centre, area, the doubled angle's cosine (axis x)
    f[5], f[6] = 0.5 * (hi - lo), 5.0  # half-length, elongation
    f[7:11] = [centre_x + lo, 0.0, centre_x + hi, 0.0]  # the two drawn ends
    f[14] = 28.0**2
    return f


@pytest.mark.parametrize(("grow", "expected"), [(0.0, 0.9), (1.5, 0.9), (2.6, 0.0)])
def test_ends_that_move_unequally_by_more_than_a_pitch_are_not_a_slide(
    grow: float, expected: float
) -> None:
    """Both ends move 0.9 mm the same way, one of them ``grow`` mm further."""
    ref = _features(0.0, -8.0, 8.0)
    cur = _features(0.0, -8.0 + 0.9, 8.0 + 0.9 + grow)
    cur[0] = 0.5 * (cur[7] + cur[9])
    length = PITCH * SlipConfig().line_length_pitches
    got = motion_mm(ref, cur, line=True, config=SlipConfig(), length_mm=length)
    assert got == pytest.approx(expected)
    # without a pitch (or with the test off) the nearer end's move counts, as before
    assert motion_mm(ref, cur, line=True, config=SlipConfig()) == pytest.approx(0.9)
    fast, unsure = motions_mm(
        ref[None], cur[None], line=True, area_step=0.5, min_elongation=1.6,
        limit_mm=0.6, bound=1e-12, line_length_mm=length,
    )  # fmt: skip
    assert fast[0] == pytest.approx(expected) and not unsure[0]


def test_a_line_at_its_length_limit_is_recomputed() -> None:
    ref = _features(0.0, -8.0, 8.0)
    cur = _features(0.0, -7.0, 8.0 + 1.0 + PITCH)
    _, unsure = motions_mm(
        ref[None], cur[None], line=True, area_step=0.5, min_elongation=1.6,
        limit_mm=0.6, bound=1e-9, line_length_mm=PITCH,
    )  # fmt: skip
    assert unsure[0]


def _growing_line(rate_hz: float) -> np.ndarray:
    """Rows of a still line that, at 1 s, grows two pitches at one end and shifts half a pitch.

    The footprint of a MuJoCo cone starting to roll after resting on its
    side: its drawn ends move the same way along it, by unequal amounts.
    """
    n = int(2.5 * rate_hz)
    t = np.arange(n) / rate_hz
    on = t >= 1.0
    lo = np.where(on, -8.0 + 0.5 * PITCH, -8.0)
    hi = np.where(on, 8.0 + 2.0 * PITCH, 8.0)
    return line_rows_between(lo, hi, t)


@pytest.mark.parametrize("rate_hz", [20.0, 100.0, 240.0])
@pytest.mark.parametrize("reference", [False, True])
def test_a_line_growing_at_one_end_does_not_slip_and_a_sliding_one_does(
    rate_hz: float, reference: bool
) -> None:
    grow = _growing_line(rate_hz)
    frames = np.arange(grow.shape[0])
    cfg = SlipConfig(line_reseat_s=0.0)  # (its ends step the same way at once: a reseat too)
    assert (
        SlipScanner(LINE, cfg, k=2, reference=reference, pitch_mm=PITCH).extend(frames, grow) == []
    )
    assert SlipScanner(LINE, SlipConfig(), k=2, reference=reference).extend(frames, grow) == []
    if rate_hz > 20.0:  # (at 20 frames/s the single step does not hold long enough anyway)
        # the test needs the pitch; without it (or switched off) the growth reads as a slide
        assert SlipScanner(LINE, cfg, k=2, reference=reference).extend(frames, grow)
        off = SlipConfig(line_length_pitches=math.inf, line_reseat_s=0.0)
        scan = SlipScanner(LINE, off, k=2, reference=reference, pitch_mm=PITCH)
        assert scan.extend(frames, grow)
    slide = _stepping_line(rate_hz)  # its ends step a pitch each, at their own phases
    slips = SlipScanner(LINE, cfg, k=2, reference=reference, pitch_mm=PITCH).extend(
        np.arange(slide.shape[0]), slide
    )
    assert slips and slips[0].kind == "line slides along itself"


def test_the_length_limit_is_checked() -> None:
    with pytest.raises(InputError, match="line_length_pitches"):
        SlipConfig(line_length_pitches=0.0)
