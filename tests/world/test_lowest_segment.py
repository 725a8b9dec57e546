"""The lowest segment of a body lying on its side: the whole generator, whatever the last digit.

A cone, truncated cone or cylinder lying on its side has its two rims'
lowest points at the same height; which one comes out lower is a rounding
error. The segment (the skin's groove for a line contact) must not depend on
it: it once collapsed to one end whenever the last rim's point came out lower.
"""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.motion.scenarios import make_scenario
from taxelkit.world.solids_polyhedra import LOWEST_TIE_MM
from taxelkit.world.solids_revolution import _lowest_rim_points_mm


# seeds whose rolls have lying poses with the last rim's point lower (the case that
# collapsed the segment); a cylinder's two rims come out exactly equal here
@pytest.mark.parametrize(("name", "seed"), [("cylinder", 0), ("cone", 1), ("truncated-cone", 2)])
def test_a_lying_body_touches_along_its_whole_generator(name: str, seed: int) -> None:
    sc = make_scenario(name, rng=seed)
    pts = _lowest_rim_points_mm(sc.solid.profile, sc.rotations)  # (P, 2, 3): one point a rim
    z = pts[..., 2]
    lying = np.abs(z[:, 0] - z[:, 1]) <= LOWEST_TIE_MM
    last_lower = lying & (z[:, 1] < z[:, 0])
    assert lying.sum() >= 10
    assert name == "cylinder" or last_lower.sum() >= 10  # the scenario exercises it
    ends = sc.solid.lowest_segment_mm(sc.rotations)
    np.testing.assert_array_equal(ends[lying], pts[lying])  # both rims, in rim order
    tilted = ~lying  # one lowest point: both ends on it
    low = np.argmin(z[tilted], axis=1)
    np.testing.assert_array_equal(ends[tilted, 0], pts[tilted][np.arange(low.size), low])
    np.testing.assert_array_equal(ends[tilted, 1], ends[tilted, 0])


def test_a_rounding_difference_does_not_move_the_ends() -> None:
    sc = make_scenario("cone", rng=1)
    ends = sc.solid.lowest_segment_mm(sc.rotations)
    nudged = sc.solid.lowest_segment_mm(sc.rotations * (1.0 + 1e-15))
    np.testing.assert_allclose(nudged, ends, rtol=0, atol=1e-12)
