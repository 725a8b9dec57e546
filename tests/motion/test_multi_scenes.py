"""Scenes with several objects: tiles, delays, composition, determinism, ground truth."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.errors import InputError
from taxelkit.motion.engines import scenario_from_engine
from taxelkit.motion.multi_scenes import frames_from_multi_scene, multi_scene, tiled_sensor
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16


def test_same_seed_same_scene_and_frames() -> None:
    a = frames_from_multi_scene(multi_scene(["cube", "sphere", "cone"], rng=2), rng=2)
    b = frames_from_multi_scene(multi_scene(["cube", "sphere", "cone"], rng=2), rng=2)
    np.testing.assert_array_equal(a.recording.frames, b.recording.frames)
    np.testing.assert_array_equal(a.owner, b.owner)
    assert a.recording.frames.shape[1:] == (16, 48)
    c = frames_from_multi_scene(multi_scene(["cube", "sphere", "cone"], rng=3), rng=3)
    assert not np.array_equal(a.recording.frames[: c.owner.shape[0]], c.recording.frames[:1000])


def test_each_object_presses_only_its_own_tile() -> None:
    scene = multi_scene(["cylinder", "tetrahedron"], rng=5)
    truth = frames_from_multi_scene(scene, rng=5, add_noise=False)
    on = truth.recording.frames > BONNEVILLE_16X16.contact_threshold_mm
    cols = np.nonzero(on)[2]
    owners = truth.owner[on]
    assert set(owners.tolist()) == {0, 1}
    assert np.all(cols[owners == 0] < 16) and np.all(cols[owners == 1] >= 16)
    assert scene.names == ("cylinder", "tetrahedron")


def test_one_object_alone_is_the_single_object_frames_delayed() -> None:
    scene = multi_scene(["sphere"], rng=7, max_delay_s=0.0)
    alone = frames_from_multi_scene(scene, add_noise=False).recording.frames
    seed = int(np.random.default_rng(7).integers(2**63 - 1))
    sc = scenario_from_engine("kinematic", "sphere", rng=seed)
    ref = frames_from_scenario(BONNEVILLE_16X16, sc, add_noise=False).frames
    np.testing.assert_allclose(alone, np.maximum(ref, 0.0), atol=1e-6)


def test_tiles_and_bad_input() -> None:
    wide = tiled_sensor(BONNEVILLE_16X16, 3)
    assert (wide.array.rows, wide.array.cols) == (16, 48)
    assert wide.array.pitch_mm == BONNEVILLE_16X16.array.pitch_mm
    with pytest.raises(InputError, match="n_tiles"):
        tiled_sensor(BONNEVILLE_16X16, 0)
    with pytest.raises(InputError, match="names"):
        multi_scene([])
