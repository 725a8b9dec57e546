"""The rerun view: ``recognize --save-view`` writes an .rrd holding every verdict."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from taxelkit.cli import run
from taxelkit.frames import TactileFrames
from taxelkit.io.recordings import read_recording, write_recording
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import make_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart.recogniser import recognise


def _roll(tmp_path: Path, name: str = "cube", seed: int = 0) -> Path:
    rec = frames_from_scenario(BONNEVILLE_16X16, make_scenario(name, rng=seed), rng=seed)
    return write_recording(rec, tmp_path / f"{name}.npz")


def _entries(rrd: Path) -> dict[str, list[Any]]:
    """Every row logged per entity path: the text of text logs, else the row's frame index."""
    from rerun.chunk import RrdReader

    out: dict[str, list[Any]] = {}
    for chunk in RrdReader(rrd).stream().to_chunks():
        batch = chunk.to_record_batch()
        names = batch.schema.names
        rows: list[Any]
        if "TextLog:text" in names:
            rows = [cell[0] for cell in batch.column("TextLog:text").to_pylist()]
        elif "frame" in names:
            rows = batch.column("frame").to_pylist()
        else:
            continue
        out.setdefault(chunk.entity_path.lstrip("/"), []).extend(rows)
    return out


@pytest.mark.parametrize(("name", "seed"), [("cube", 0), ("sphere", 1), ("cone", 2)])
def test_rrd_holds_every_frame_event_and_verdict(tmp_path: Path, name: str, seed: int) -> None:
    pytest.importorskip("rerun", reason="the viewer needs the viewer extra")
    src = _roll(tmp_path, name, seed)
    out = tmp_path / "view.rrd"
    assert run(["recognize", str(src), "--save-view", str(out)]) == 0
    result = recognise(read_recording(src))
    entries = _entries(out)
    assert sorted(entries["sensor/frames"]) == list(range(result.classes.size))
    assert entries["sensor/contact_class"] == result.class_names()
    kinds = [e.kind for e in result.events]
    assert len(entries["sensor/contact"]) == kinds.count("contact")
    assert len(entries["sensor/tactemes"]) == kinds.count("tacteme")
    assert len(entries["sensor/candidates"]) == kinds.count("candidates")
    verdicts = [
        f"{e.kind}: {e.value if isinstance(e.value, str) else ', '.join(e.value)}"
        for e in result.events
        if e.kind in ("identified", "unknown", "lifted")
    ]
    assert verdicts, "a roll ends in a verdict"
    final = result.identified or f"undecided among {', '.join(result.candidates)}"
    assert sorted(entries["sensor/verdicts"]) == sorted([*verdicts, f"result: {final}"])


def test_save_view_refuses_existing_file_and_wrong_suffix(tmp_path: Path) -> None:
    pytest.importorskip("rerun", reason="the viewer needs the viewer extra")
    src = _roll(tmp_path)
    out = tmp_path / "view.rrd"
    out.write_bytes(b"keep")
    errors: list[str] = []
    assert run(["recognize", str(src), "--save-view", str(out)], echo_err=errors.append) == 2
    assert out.read_bytes() == b"keep" and "exists" in errors[-1]
    assert run(["recognize", str(src), "--save-view", str(out), "--force"]) == 0
    assert out.stat().st_size > 1000
    assert run(["recognize", str(src), "--save-view", "v.png"], echo_err=errors.append) == 2
    assert "must end in .rrd" in errors[-1]


def test_without_rerun_the_option_says_how_to_install(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    src = write_recording(
        read_recording(_roll(tmp_path)), tmp_path / "again.npz"
    )  # any valid recording
    monkeypatch.setitem(sys.modules, "rerun", None)  # import rerun -> ImportError
    errors: list[str] = []
    code = run(
        ["recognize", str(src), "--save-view", str(tmp_path / "v.rrd")], echo_err=errors.append
    )
    assert code == 2 and len(errors) == 1
    assert 'pip install "taxelkit[viewer]"' in errors[0] and "\n" not in errors[0]
    assert not (tmp_path / "v.rrd").exists()


def test_frames_are_logged_as_float32_tensors(tmp_path: Path) -> None:
    pytest.importorskip("rerun", reason="the viewer needs the viewer extra")
    from rerun.chunk import RrdReader

    from taxelkit.viewer import RerunView

    view = RerunView(save_path=tmp_path / "f.rrd")
    frame = np.arange(12, dtype=np.float64).reshape(3, 4) / 10
    view.log_frame(0, 0.0, frame, 2)
    view.close()
    chunks = [c for c in RrdReader(tmp_path / "f.rrd").stream().to_chunks()]
    paths = {c.entity_path for c in chunks}
    assert {"/sensor/frames", "/sensor/contact_class"} <= paths


def test_live_save_view_holds_every_verdict(tmp_path: Path) -> None:
    pytest.importorskip("rerun", reason="the viewer needs the viewer extra")
    from taxelkit.io.frame_protocol import encode_frame

    rec = read_recording(_roll(tmp_path, "cylinder", 3))
    capture = tmp_path / "roll.bin"
    frames = np.asarray(rec.frames, dtype=np.float32)
    capture.write_bytes(
        b"".join(
            encode_frame(f, index=k, t_s=float(t))
            for k, (f, t) in enumerate(zip(frames, rec.t_s, strict=True))
        )
    )
    out = tmp_path / "live.rrd"
    args = ["recognize", "--live", f"file:{capture}", "--pitch-mm", str(rec.pitch_mm)]
    assert run([*args, "--save-view", str(out)]) == 0
    entries = _entries(out)
    assert len(entries["sensor/frames"]) == rec.n_frames
    expected = recognise(TactileFrames(frames, rec.t_s, rec.pitch_mm))
    verdicts = [
        f"{e.kind}: {e.value if isinstance(e.value, str) else ', '.join(e.value)}"
        for e in expected.events
        if e.kind in ("identified", "unknown", "lifted")
    ]
    assert sorted(entries["sensor/verdicts"]) == sorted([*verdicts, "result: cylinder"])
    errors: list[str] = []
    assert run([*args, "--save-view", str(out)], echo_err=errors.append) == 2
    assert "exists" in errors[0]
