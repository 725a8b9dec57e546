"""The tacteme table checked by simulation, and the recogniser end to end on rolling objects."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from taxelkit.cli import run
from taxelkit.frames import TactileFrames
from taxelkit.io.recordings import write_recording
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import make_scenario
from taxelkit.sensors import BONNEVILLE_16X16
from taxelkit.smart.recogniser import SmartSensor, recognise
from taxelkit.smart.tacteme_table import OBJECTS, Tacteme, eliminated_by

TRIALS = 12


@pytest.fixture(scope="module")
def simulated() -> dict[str, list[tuple[TactileFrames, object]]]:
    out: dict[str, list[tuple[TactileFrames, object]]] = {}
    for k, name in enumerate(OBJECTS):
        out[name] = []
        for t in range(TRIALS):
            rng = np.random.default_rng([2024, k, t])
            sc = make_scenario(name, rng=rng)
            rec = frames_from_scenario(BONNEVILLE_16X16, sc, rng=rng)
            out[name].append((rec, recognise(rec)))
    return out


@pytest.mark.parametrize("name", OBJECTS)
def test_no_rolling_object_produces_a_tacteme_that_eliminates_it(
    name: str, simulated: dict[str, list[tuple[TactileFrames, object]]]
) -> None:
    bad = [
        t
        for _, r in simulated[name]
        for t, _ in r.tactemes  # type: ignore[attr-defined]
        if name in eliminated_by(Tacteme(t))
    ]
    assert bad == []


def test_rolling_objects_are_identified(
    simulated: dict[str, list[tuple[TactileFrames, object]]],
) -> None:
    outcomes = {n: [r.identified for _, r in v] for n, v in simulated.items()}  # type: ignore[attr-defined]
    correct = sum(o == n for n, v in outcomes.items() for o in v)
    wrong = sum(o not in (n, None, "unknown") for n, v in outcomes.items() for o in v)
    assert wrong == 0
    assert correct / (len(OBJECTS) * TRIALS) >= 0.95  # measured 0.99 over 600 trials


def test_sliding_is_never_identified() -> None:
    for t in range(10):
        rng = np.random.default_rng([7, t])
        rec = frames_from_scenario(BONNEVILLE_16X16, make_scenario("sliding", rng=rng), rng=rng)
        assert recognise(rec).identified in (None, "unknown")


def test_streaming_equals_batch_on_simulated_rolls(
    simulated: dict[str, list[tuple[TactileFrames, object]]],
) -> None:
    for name in OBJECTS:
        rec, batch = simulated[name][0]
        sensor = SmartSensor((16, 16), pitch_mm=rec.pitch_mm)
        for f, t in zip(rec.frames, rec.t_s, strict=True):
            sensor.push(f, t)
        assert list(sensor.result().events) == list(batch.events), name  # type: ignore[attr-defined]


def test_recognize_a_cube_recorded_by_another_program_at_another_pitch(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Binary frames of a rolling cube on a 24 x 24 array at 1.2 mm pitch, written as plain CSV."""
    from dataclasses import replace

    from taxelkit.sensors import TaxelArray

    sensor = replace(
        BONNEVILLE_16X16, array=TaxelArray(rows=24, cols=24, pitch_mm=1.2, element_size_mm=1.0)
    )
    rng = np.random.default_rng(11)
    sc = make_scenario("cube", rng=rng, sensor=sensor)
    rec = frames_from_scenario(sensor, sc, rng=rng)
    contact = sensor.contact_from_displacement(rec.frames)
    path = tmp_path / "cube.csv"
    header = "t_s," + ",".join(f"r{i}c{j}" for i in range(24) for j in range(24))
    rows = [
        f"{t:.4f}," + ",".join(str(int(v)) for v in f.ravel())
        for t, f in zip(rec.t_s, contact, strict=True)
    ]
    path.write_text("\n".join([header, *rows]) + "\n")  # no metadata: pitch from the CLI
    code = run(["recognize", str(path), "--pitch-mm", "1.2", "--json"])
    out = capsys.readouterr().out
    assert code == 0
    import json

    doc = json.loads(out)
    assert doc["identified"] == "cube"
    assert {"identified", "candidates", "tactemes", "class_segments"} <= set(doc)
    assert doc["n_frames"] == rec.n_frames
    assert doc["class_segments"][-1]["last_frame"] == rec.n_frames - 1
    code = run(["recognize", str(path), "--pitch-mm", "1.2", "--json", "--per-frame"])
    assert len(json.loads(capsys.readouterr().out)["classes"]) == rec.n_frames


def test_recognize_cli_on_a_simulated_roll(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "roll.npz"
    assert run(["simulate", "roll", "--object", "cylinder", "--seed", "4", "--out", str(out)]) == 0
    capsys.readouterr()
    assert run(["recognize", str(out)]) == 0
    text = capsys.readouterr().out
    assert "identified: cylinder" in text
    write_recording(TactileFrames(np.zeros((3, 4, 4), bool)), tmp_path / "blank.h5")
    assert run(["recognize", str(tmp_path / "blank.h5"), "--json"]) == 0
    assert '"identified": null' in capsys.readouterr().out
