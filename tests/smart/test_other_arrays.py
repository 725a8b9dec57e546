"""Other arrays' recordings, written by another program, recognised with --pitch-mm/--threshold."""

from __future__ import annotations

import json
from pathlib import Path

import h5py
import numpy as np
import pytest

from taxelkit.cli import run
from taxelkit.experiments.robustness import array_sensor
from taxelkit.motion.engines import scenario_from_engine
from taxelkit.motion.rolling import frames_from_scenario

#: (object, rows, pitch mm, scale to the file's unit, unit, dtype); threshold: 0.03 mm x scale.
CASES = [
    ("cylinder", 20, 1.5, 1000.0, "kPa", "float32"),  # a pressure array, 1 kPa per um (assumed)
    ("cube", 20, 1.5, 4000.0, "counts", "int16"),  # an ADC, 4 counts per um
    ("cone", 12, 2.5, 1000.0, "kPa", "float64"),
]


def write_foreign_h5(path: Path, frames: np.ndarray, t_s: np.ndarray, unit: str) -> None:
    """An HDF5 file as another program writes the documented layout: no pitch, its own unit."""
    with h5py.File(path, "w") as f:
        f.create_dataset("frames", data=frames)
        f.create_dataset("t_s", data=t_s)
        f.attrs["units"] = unit


@pytest.mark.parametrize(("name", "rows", "pitch", "scale", "unit", "dtype"), CASES)
def test_a_foreign_analog_recording_is_recognised(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    name: str,
    rows: int,
    pitch: float,
    scale: float,
    unit: str,
    dtype: str,
) -> None:
    sensor = array_sensor(rows, pitch)
    sc = scenario_from_engine("kinematic", name, rng=21, rate_hz=50.0, sensor=sensor)
    mm = frames_from_scenario(sensor, sc, rng=21).frames
    frames = np.round(mm * scale).astype(dtype) if dtype.startswith("int") else (mm * scale)
    path = tmp_path / f"{name}.h5"
    write_foreign_h5(path, frames.astype(dtype), sc.t_s, unit)
    threshold = 0.03 * scale
    code = run(
        ["recognize", str(path), "--pitch-mm", str(pitch), "--threshold", str(threshold), "--json"]
    )
    doc = json.loads(capsys.readouterr().out)
    assert code == 0
    assert doc["identified"] == name, doc["why"]["sentence"]
