"""A line that reseats is not sliding (``SlipConfig.line_reseat_s``)."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.slip import SlipConfig
from taxelkit.smart.slip_return import reseat_steps
from taxelkit.smart.slip_scan import SlipScanner

from .test_slip import line_rows_between

LINE = int(ContactClass.LINE)
PITCH = 1.7625


def _ends(points: list[tuple[float, float, float, float]]) -> np.ndarray:
    """Feature rows ``(n, 15)`` holding only the two drawn ends of each frame."""
    x = np.zeros((len(points), 15))
    x[:, 7:11] = points
    return x


def test_reseat_steps_need_both_ends_along_the_line_the_same_way() -> None:
    x = _ends(
        [
            (-8.0, 0.0, 8.0, 0.0),
            (-6.2, 0.0, 9.8, 0.0),  # both ends 1.8 mm along the line: a step of both
            (-6.2, 0.0, 11.6, 0.0),  # one end only
            (-8.0, 0.0, 13.4, 0.0),  # opposite ways (the line grew at both ends)
            (-8.0, 1.8, 13.4, 1.8),  # across the line
            (-7.0, 1.8, 14.4, 1.8),  # both along, 1 mm: over a limit of 0.6 only
            (np.nan, np.nan, 15.4, 1.8),  # an end not measured
        ]
    )
    np.testing.assert_array_equal(reseat_steps(x, 0.6), [1, 0, 0, 0, 1, 0])
    np.testing.assert_array_equal(reseat_steps(x, 1.2), [1, 0, 0, 0, 0, 0])


def _reseating_line(rate_hz: float) -> np.ndarray:
    """Rows of a still line whose two drawn ends jump a pitch along it at 1 s, and stay.

    The footprint of a MuJoCo cone settling onto the next facet of its mesh.
    """
    t = np.arange(int(2.5 * rate_hz)) / rate_hz
    jump = PITCH * (t >= 1.0)
    return line_rows_between(-8.0 + jump, 8.0 + jump, t)


def _together_line(rate_hz: float, speed_mm_s: float = 4.0) -> np.ndarray:
    """Rows of a line sliding along itself from 1 s whose two ends step together, a pitch apart.

    A line whose length is a whole number of pitches along a grid axis:
    both ends cross a taxel edge in the same frame, every 0.44 s.
    """
    t = np.arange(int(3.0 * rate_hz)) / rate_hz
    slid = PITCH * np.floor(speed_mm_s * np.clip(t - 1.0, 0.0, None) / PITCH)
    return line_rows_between(-8.0 + slid, 8.0 + slid, t)


@pytest.mark.parametrize("rate_hz", [20.0, 100.0, 240.0])
@pytest.mark.parametrize("reference", [False, True])
def test_a_reseating_line_does_not_slip_and_a_sliding_one_does(
    rate_hz: float, reference: bool
) -> None:
    def slips(rows: np.ndarray, cfg: SlipConfig) -> list:
        scan = SlipScanner(LINE, cfg, k=2, reference=reference, pitch_mm=PITCH)
        return scan.extend(np.arange(rows.shape[0]), rows)

    seat, slide = _reseating_line(rate_hz), _together_line(rate_hz)
    assert slips(seat, SlipConfig()) == []
    off = SlipConfig(line_reseat_s=0.0)
    assert slips(seat, off)  # the jump reads as a slide without the test
    late, early = slips(slide, SlipConfig()), slips(slide, off)
    assert late and early and late[0].kind == "line slides along itself"
    # decided at the slide's second step (1.88 s), not its first (1.44 s)
    assert early[0].detected_frame / rate_hz < 1.8 <= late[0].detected_frame / rate_hz < 2.2


def test_the_rest_before_a_reseat_is_checked() -> None:
    with pytest.raises(InputError, match="line_reseat_s"):
        SlipConfig(line_reseat_s=-1.0)
