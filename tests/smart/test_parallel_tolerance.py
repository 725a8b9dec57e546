"""LCMP's tolerance grows with the distance rolled (``parallel_tol_growth_deg_per_mm``)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.smart.contact_classes import ContactClass
from taxelkit.smart.segment_scan import SegmentScanner
from taxelkit.smart.tacteme_table import Tacteme
from taxelkit.smart.tactemes import PAPER_LEVEL3, SegmentTrack, TactemeConfig, segment_tactemes
from taxelkit.smart.tactemes_batch import batch_tactemes

RATE_HZ = 60.0


def rolling_line(orientation_deg: np.ndarray, speed_mm_s: float = 3.0) -> np.ndarray:
    """Rows (ROW_COLUMNS) of a line along x rolling across itself (+y) from frame 15 on.

    Its first 15 frames it forms where it lies (area 10 -> 38 mm^2), as a body
    tipped onto its side does; then it keeps its area and rolls.
    """
    n = orientation_deg.size
    j = np.arange(n)
    rows = np.zeros((n, 9))
    rows[:, 1] = np.maximum(j - 15, 0) * speed_mm_s / RATE_HZ
    rows[:, 2] = orientation_deg
    rows[:, 3] = np.minimum(10.0 + 2.0 * j, 38.0)
    rows[:, 4] = 6.0
    rows[:, 5] = 5.0
    rows[:, 6], rows[:, 7] = -5.5, 5.5
    rows[:, 8] = j / RATE_HZ
    return rows


def three_paths(rows: np.ndarray, cfg: TactemeConfig) -> list[tuple[Tacteme, int]]:
    """The line's tactemes per track, in the batch and streamed in chunks (all equal)."""
    frames = np.arange(rows.shape[0])
    track = SegmentTrack(
        frames, rows[:, 0:2], rows[:, 2], rows[:, 3], rows[:, 4], rows[:, 5], rows[:, 8],
        rows[:, 6:8],
    )  # fmt: skip
    cls = int(ContactClass.LINE)
    want = segment_tactemes(cls, track, cfg)
    assert batch_tactemes([(cls, track)], cfg) == [want]
    for step in (1, 13, rows.shape[0]):
        scan = SegmentScanner(cls, cfg)
        got = [
            x
            for a in range(0, rows.shape[0], step)
            for x in scan.extend(frames[a : a + step], rows[a : a + step])
        ]
        assert got + scan.close() == want, step
    return want


def test_a_cylinder_whose_line_formed_a_few_degrees_off_reads_parallel_once_far() -> None:
    n = 15 + int(3.5 * RATE_HZ)  # 10.5 mm rolled
    jitter = np.where((np.arange(n) // 5) % 2 == 0, 0.5, -0.5)
    orientation = np.where(np.arange(n) < 15, 4.0, 0.0) + jitter
    rows = rolling_line(orientation)
    cfg = TactemeConfig()
    found = dict(three_paths(rows, cfg))
    assert Tacteme.LCMP in found and Tacteme.LCMT not in found
    rolled_mm = rows[found[Tacteme.LCMP], 1]
    # the limit passes the ~4 deg offset (and its jitter) only beyond 3.5 mm
    assert 6.0 < rolled_mm < 9.0
    fixed = dataclasses.replace(cfg, parallel_tol_growth_deg_per_mm=0.0)
    assert Tacteme.LCMP not in dict(three_paths(rows, fixed))  # a fixed 3 deg: never


def test_a_turning_line_that_dips_under_the_tolerance_for_a_moment_is_not_parallel() -> None:
    n = 15 + int(4.0 * RATE_HZ)
    rolled = np.maximum(np.arange(n) - 15, 0) * 3.0 / RATE_HZ
    orientation = 1.5 * rolled
    dip = (rolled > 3.6) & (rolled < 4.4)  # reads back near its start for 0.27 s
    orientation[dip] = 1.0
    rows = rolling_line(orientation)
    found = dict(three_paths(rows, TactemeConfig()))
    assert Tacteme.LCMP not in found and Tacteme.LCMT in found
    short = TactemeConfig(parallel_hold_s=0.15)  # held as long as any motion: parallel
    assert Tacteme.LCMP in dict(three_paths(rows, short))


@pytest.mark.parametrize("rate_deg_per_mm", [1.5, 2.5])
def test_a_line_turning_as_a_truncated_cone_never_reads_parallel(rate_deg_per_mm: float) -> None:
    n = 15 + int(4.0 * RATE_HZ)
    rolled = np.maximum(np.arange(n) - 15, 0) * 3.0 / RATE_HZ
    rows = rolling_line(rate_deg_per_mm * rolled)
    found = dict(three_paths(rows, TactemeConfig()))
    assert Tacteme.LCMP not in found and Tacteme.LCMT in found


def test_the_limit_grows_from_the_tolerance_and_the_paper_keeps_it_fixed() -> None:
    cfg = TactemeConfig()
    rolled = np.array([3.5, 5.5, 9.5])
    np.testing.assert_allclose(cfg.parallel_limit_deg(rolled), [3.0, 4.5, 7.5])
    np.testing.assert_array_equal(PAPER_LEVEL3.parallel_limit_deg(rolled), 4.0)
    with pytest.raises(InputError, match="parallel_tol_growth_deg_per_mm"):
        TactemeConfig(parallel_tol_growth_deg_per_mm=-0.5)


def test_batch_reads_each_segments_own_parallel_hold() -> None:
    """Two rates with the same motion hold (10 frames) but parallel holds of 20 and 19."""
    cfg, cls, items = TactemeConfig(), int(ContactClass.LINE), []
    for dt in (0.0155, 0.0160):
        n = 400
        rows = rolling_line(np.where(np.arange(n) < 15, 4.0, 0.0))
        rows[:, 8] = np.arange(n) * dt
        rows[:, 1] = np.maximum(np.arange(n) - 15, 0) * 3.0 * dt
        items.append(
            (cls, SegmentTrack(np.arange(n), rows[:, 0:2], rows[:, 2], rows[:, 3], rows[:, 4],
                               rows[:, 5], rows[:, 8], rows[:, 6:8]))
        )  # fmt: skip
    alone = [segment_tactemes(c, t, cfg) for c, t in items]
    assert all(Tacteme.LCMP in dict(found) for found in alone)
    assert batch_tactemes(items, cfg) == alone
