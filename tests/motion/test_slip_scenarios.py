"""Rolls with a slipping phase: the slip is where the script says, and only there."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.motion.slip_scenarios import make_partial_slip_scenario
from taxelkit.world.solids import SOLID_NAMES


@pytest.mark.parametrize("name", SOLID_NAMES)
def test_the_slip_is_in_the_sliding_phase_only(name: str) -> None:
    sc = make_partial_slip_scenario(name, rng=2)
    assert sc.name == f"{name}-slip" and sc.object_name == name and not sc.slides
    speed = np.nan_to_num(sc.slip_mm() / np.diff(sc.t_s))
    # a step into or out of a "sliding" frame slides (a move's last frame has the next label)
    steps = list(itertools.pairwise(sc.phase))
    sliding = np.array(["sliding" in pair for pair in steps])
    assert speed[sliding].min() > 2.5  # 3-6 mm/s slides
    tipping = np.array(["tipping" in pair for pair in steps])
    assert speed[~sliding & ~tipping].max() < 0.05  # rolling without slip, still, placing
    assert speed[~sliding].max() < 2.5  # a tip moves a lifting face sideways a little


def test_same_seed_same_scenario_and_bad_names() -> None:
    one = make_partial_slip_scenario("cone", rng=4)
    assert one.equals(make_partial_slip_scenario("cone", rng=4))
    with pytest.raises(InputError, match="unknown solid"):
        make_partial_slip_scenario("sliding", rng=0)
