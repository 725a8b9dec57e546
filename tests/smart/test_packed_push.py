"""Packed contact rows pushed to the chunked recogniser: the recognition of the frames unpacked."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from taxelkit.errors import InputError
from taxelkit.motion.engines import scenario_from_engine
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.sensors.faults import fault_model
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart.levels12 import DEFAULT_THRESHOLD_MM
from taxelkit.smart.recognise_chunks import ChunkRecogniser


def _contact(name: str, seed: int, faults: bool) -> tuple[np.ndarray, np.ndarray, float]:
    scenario = scenario_from_engine("kinematic", name, rng=seed, rate_hz=20.0, lift_gap_s=0.0)
    rec = frames_from_scenario(BONNEVILLE_16X16, scenario, rng=seed, add_noise=True)
    if faults:
        threshold = BONNEVILLE_16X16.contact_threshold_mm
        rec = fault_model("all").apply(rec, threshold=threshold, rng=seed)
    return rec.frames > DEFAULT_THRESHOLD_MM, rec.t_s, rec.pitch_mm


def _recognised(
    frames: np.ndarray, t_s: np.ndarray, pitch: float, size: int, packed: bool, junk: bool = False
) -> object:
    recogniser = ChunkRecogniser(frames.shape[1:], pitch_mm=pitch, per_frame=True)
    rows = np.packbits(frames, axis=2, bitorder="little")
    if junk and frames.shape[2] % 8:  # the bits past the row are not taxels
        rows[:, :, -1] |= np.uint8(0xFF << (frames.shape[2] % 8) & 0xFF)
    for a in range(0, frames.shape[0], size):
        if packed:
            recogniser.push_packed(rows[a : a + size], t_s[a : a + size])
        else:
            recogniser.push(frames[a : a + size], t_s[a : a + size])
    return recogniser.result()


def _same(a: object, b: object) -> None:
    assert a.events == b.events  # type: ignore[attr-defined]
    assert a.verdict == b.verdict and a.slips == b.slips  # type: ignore[attr-defined]
    assert np.array_equal(a.classes, b.classes)  # type: ignore[attr-defined]


@pytest.mark.parametrize("name", ["cube", "cone", "sliding"])
@pytest.mark.parametrize("faults", [False, True])
@pytest.mark.parametrize("cols", [16, 8, 12, 32])
def test_packed_rows_are_recognised_as_the_frames(name: str, faults: bool, cols: int) -> None:
    frames, t_s, pitch = _contact(name, 2, faults)
    frames = np.pad(frames[:, :, :cols], ((0, 0), (0, 0), (0, max(0, cols - 16))))
    for size in (1, 7, frames.shape[0]):
        ref = _recognised(frames, t_s, pitch, size, packed=False)
        _same(_recognised(frames, t_s, pitch, size, packed=True, junk=True), ref)


@settings(max_examples=25, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    density=st.floats(0.02, 0.5),
    size=st.integers(1, 90),
    cols=st.sampled_from([8, 13, 16]),
)
def test_random_packed_rows_are_recognised_as_the_frames(
    seed: int, density: float, size: int, cols: int
) -> None:
    rng = np.random.default_rng(seed)
    frames = rng.random((180, 9, cols)) < density
    frames[rng.random(180) < 0.3] = False  # lifts
    frames[60:120, 2:5, 3:7] = True  # a held contact
    t_s = np.arange(180) / 20.0
    ref = _recognised(frames, t_s, 1.5, size, packed=False)
    _same(_recognised(frames, t_s, 1.5, size, packed=True), ref)


def test_packed_rows_are_checked() -> None:
    recogniser = ChunkRecogniser((4, 16), pitch_mm=1.0)
    with pytest.raises(InputError, match="uint8"):
        recogniser.push_packed(np.zeros((3, 4, 2), np.int16), np.arange(3.0))
    with pytest.raises(InputError, match="uint8"):
        recogniser.push_packed(np.zeros((3, 4, 3), np.uint8), np.arange(3.0))
    assert recogniser.push_packed(np.zeros((0, 4, 2), np.uint8), np.zeros(0)) == []
    recogniser.push_packed(np.zeros((3, 4, 2), np.uint8), np.arange(3.0))
    with pytest.raises(InputError, match="increase"):
        recogniser.push_packed(np.zeros((1, 4, 2), np.uint8), [1.0])
