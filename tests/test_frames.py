"""TactileFrames validates itself and keeps its data immutable."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.frames import DEFAULT_FRAME_INTERVAL_S, DEFAULT_PITCH_MM, TactileFrames


def test_defaults_and_summary() -> None:
    rec = TactileFrames(np.zeros((5, 3, 4)))
    np.testing.assert_array_equal(rec.t_s, np.arange(5) * DEFAULT_FRAME_INTERVAL_S)
    assert rec.pitch_mm == DEFAULT_PITCH_MM
    assert rec.units == "mm" and not rec.is_contact
    assert rec.rate_hz == pytest.approx(1.0 / DEFAULT_FRAME_INTERVAL_S)
    assert rec.shape == (5, 3, 4)


def test_bool_frames_are_contact_units_and_integers_become_float() -> None:
    assert TactileFrames(np.ones((1, 2, 2), bool)).units == "contact"
    assert TactileFrames(np.ones((1, 2, 2), np.int16)).frames.dtype == np.float64
    with pytest.raises(InputError, match="bool"):
        TactileFrames(np.ones((1, 2, 2)), units="contact")


def test_arrays_are_read_only_copies() -> None:
    data = np.zeros((2, 2, 2))
    rec = TactileFrames(data)
    data[0, 0, 0] = 1.0
    assert rec.frames[0, 0, 0] == 0.0
    with pytest.raises(ValueError, match="read-only"):
        rec.frames[0, 0, 0] = 2.0


def test_adopt_keeps_the_arrays_it_is_handed_and_checks_them_alike() -> None:
    frames = np.random.default_rng(0).random((3, 2, 2)) > 0.5
    t_s = np.array([0.0, 0.5, 1.5])
    rec = TactileFrames.adopt(frames, t_s, pitch_mm=2.0, sensor="x")
    assert rec.frames is frames  # no copy: made read-only in place
    assert not frames.flags.writeable
    assert rec.equals(TactileFrames(frames.copy(), t_s.copy(), pitch_mm=2.0, sensor="x"))
    ints = TactileFrames.adopt(np.ones((1, 2, 2), np.int16))  # converted: as the constructor
    assert ints.frames.dtype == np.float64 and ints.units == "mm"
    for bad, t, match in [(np.zeros((3, 4)), None, "3 dimensions"), (frames, t_s[:2], "3 entries")]:
        with pytest.raises(InputError, match=match):
            TactileFrames.adopt(bad, t)


@pytest.mark.parametrize(
    ("frames", "t_s", "match"),
    [
        (np.zeros((3, 4)), None, "3 dimensions"),
        (np.full((2, 2, 2), np.nan), None, "finite"),
        (np.zeros((3, 2, 2)), [0.0, 1.0, 1.0], "strictly increasing"),
        (np.zeros((3, 2, 2)), [0.0, 1.0], "3 entries"),
        (np.zeros((2, 2, 2)), [0.0, np.inf], "finite"),
        (np.array([[["a"]]]), None, "dtype"),
    ],
)
def test_invalid_recordings_raise(frames: object, t_s: object, match: str) -> None:
    with pytest.raises(InputError, match=match):
        TactileFrames(frames, t_s)  # type: ignore[arg-type]


def test_contact_and_equals() -> None:
    rec = TactileFrames(np.array([[[0.0, 0.2]]]), t_s=[0.5], pitch_mm=2.0, sensor="x")
    np.testing.assert_array_equal(rec.contact(0.1), [[[False, True]]])
    same = TactileFrames(np.array([[[0.0, 0.2]]]), t_s=[0.5], pitch_mm=2.0, sensor="x")
    assert rec.equals(same)
    assert not rec.equals(TactileFrames(np.array([[[0.0, 0.2]]]), t_s=[0.5]))
    with pytest.raises(InputError, match="pitch_mm"):
        TactileFrames(np.zeros((1, 1, 1)), pitch_mm=0.0)
