"""The batch-fed streaming sensor gives the batch recogniser's events for any batching."""

from __future__ import annotations

import numpy as np
import pytest

from taxelkit.motion.engines import scenario_from_engine
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart.recogniser import recognise
from taxelkit.smart.stream_batches import BatchSmartSensor


@pytest.mark.parametrize("name", ["cube", "sphere", "cone", "tetrahedron"])
def test_batches_give_the_events_of_recognise(name: str) -> None:
    scenario = scenario_from_engine("kinematic", name, rng=4, rate_hz=20.0, lift_gap_s=0.0)
    rec = frames_from_scenario(BONNEVILLE_16X16, scenario, rng=4, add_noise=True)
    ref = recognise(rec)
    for size in (1, 3, 50, rec.n_frames):
        sensor = BatchSmartSensor(rec.shape[1:], pitch_mm=rec.pitch_mm)
        events = []
        classes = []
        for a in range(0, rec.n_frames, size):
            got, cls = sensor.push_many(rec.frames[a : a + size], rec.t_s[a : a + size])
            events.extend(got)
            classes.append(cls)
        assert tuple(events) == ref.events, size
        assert np.array_equal(np.concatenate(classes), ref.classes)
        result = sensor.result()
        assert result.identified == ref.identified and result.verdict == ref.verdict
        assert len(sensor.classes) <= size  # the per-frame list does not grow


def test_single_frames_go_through_push_many() -> None:
    sensor = BatchSmartSensor((4, 4), pitch_mm=1.0)
    with pytest.raises(ValueError, match="push_many"):
        sensor.push(np.zeros((4, 4), bool))
    assert sensor.push_many(np.zeros((0, 4, 4), bool), np.empty(0))[0] == []
