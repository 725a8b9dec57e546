"""``--view``, ``--view-url`` and ``--save-view`` on recognize, show and trace."""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from taxelkit.cli import run
from taxelkit.io.frame_protocol import encode_frame
from taxelkit.io.recordings import read_recording, write_recording
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import make_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16

rr = pytest.importorskip("rerun", reason="the viewer needs the viewer extra")


def _roll(tmp_path: Path, name: str = "cube", seed: int = 0) -> Path:
    rec = frames_from_scenario(BONNEVILLE_16X16, make_scenario(name, rng=seed), rng=seed)
    return write_recording(rec, tmp_path / f"{name}.npz")


def _capture(tmp_path: Path, src: Path) -> tuple[Path, float]:
    rec = read_recording(src)
    frames = np.asarray(rec.frames, dtype=np.float32)
    capture = tmp_path / "roll.bin"
    packets = [
        encode_frame(f, index=k, t_s=float(t))
        for k, (f, t) in enumerate(zip(frames, rec.t_s, strict=True))
    ]
    capture.write_bytes(b"".join(packets))
    return capture, rec.pitch_mm


def _rows(rrd: Path) -> dict[str, list[dict[str, Any]]]:
    """Every row logged per entity path, as ``{column: value}`` (timelines and components)."""
    from rerun.chunk import RrdReader

    out: dict[str, list[dict[str, Any]]] = {}
    for chunk in RrdReader(rrd).stream().to_chunks():
        batch = chunk.to_record_batch()
        keep = [n for n in batch.schema.names if n not in ("log_time", "rerun.controls.RowId")]
        out.setdefault(chunk.entity_path.lstrip("/"), []).extend(batch.select(keep).to_pylist())
    return out


class _Viewer:
    """Stands in for rerun's viewer: records spawn/connect calls, keeps file sinks working."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch) -> None:
        self.spawned: list[dict[str, Any]] = []
        self.connected: list[str] = []
        self.sinks: list[str] = []
        stream = rr.RecordingStream
        set_sinks = stream.set_sinks

        def spawn(_self: Any, **kwargs: Any) -> None:
            self.spawned.append(kwargs)

        def connect_grpc(_self: Any, url: str | None = None, **kwargs: Any) -> None:
            self.connected.append(str(url))

        def sinks(_self: Any, *chosen: Any, **kwargs: Any) -> None:
            self.sinks.extend(type(s).__name__ for s in chosen)
            set_sinks(_self, *(s for s in chosen if isinstance(s, rr.FileSink)), **kwargs)

        monkeypatch.setattr(stream, "spawn", spawn)
        monkeypatch.setattr(stream, "connect_grpc", connect_grpc)
        monkeypatch.setattr(stream, "set_sinks", sinks)


def test_trace_save_view_logs_path_edges_and_recall_curve(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "trace.rrd"
    assert run(["trace", "--shape", "star", "--json", "--save-view", str(out)]) == 0
    doc = json.loads(capsys.readouterr().out)
    rows = _rows(out)
    path = np.asarray(doc["trajectory_mm"])
    assert [r["section"] for r in rows["trace/path"]] == list(range(len(path)))
    last_strip = np.asarray(rows["trace/path"][-1]["LineStrips2D:strips"][0])
    np.testing.assert_allclose(last_strip, path, atol=1e-3)  # float32 in the log, 4 dp in JSON
    assert len(rows["trace/probe"]) == len(path)
    edges = rows["trace/edges"][-1]["LineStrips2D:strips"]
    assert len(edges) >= 0.9 * (len(path) - 1) and all(len(e) == 2 for e in edges)
    for name in doc["correlations"]:
        logged = [r["Scalars:scalars"][0] for r in rows[f"recall/correlation/{name}"]]
        expected = [point["correlations"][name] for point in doc["recall_curve"]]
        np.testing.assert_allclose(logged, expected, rtol=1e-12)
    recognised = [r["TextLog:text"][0] for r in rows["recall/recognised"]]
    assert recognised[-1].endswith(": star")
    verdict = rows["trace/verdict"][0]["TextLog:text"][0]
    assert verdict == f"{len(path) - 1} sections (closed); recognised: star"


def test_show_save_view_logs_the_chosen_frames(tmp_path: Path) -> None:
    src = _roll(tmp_path)
    n = read_recording(src).n_frames
    out = tmp_path / "show.rrd"
    assert run(["show", str(src), "--save-view", str(out)]) == 0
    assert [r["frame"] for r in _rows(out)["sensor/frames"]] == list(range(n))
    args = ["show", str(src), "--start", "3", "--stop", "9", "--threshold", "0.03"]
    assert run([*args, "--save-view", str(out), "--force"]) == 0
    rows = _rows(out)["sensor/frames"]
    assert [r["frame"] for r in rows] == list(range(3, 9))
    assert not (tmp_path / "strip.png").exists()


def test_show_needs_an_image_or_a_view(tmp_path: Path) -> None:
    errors: list[str] = []
    assert run(["show", str(_roll(tmp_path))], echo_err=errors.append) == 2
    assert len(errors) == 1 and "--out" in errors[0] and "--view" in errors[0]


@pytest.mark.parametrize("command", ["recognize", "show", "trace", "live"])
def test_view_spawns_a_viewer_and_streams_to_it(
    command: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    viewer = _Viewer(monkeypatch)
    src = _roll(tmp_path)
    capture, pitch = _capture(tmp_path, src)
    argv = {
        "recognize": ["recognize", str(src)],
        "show": ["show", str(src)],
        "trace": ["trace", "--shape", "square"],
        "live": ["recognize", "--live", f"file:{capture}", "--pitch-mm", str(pitch)],
    }[command]
    assert run([*argv, "--view"]) == 0
    assert viewer.spawned == [{}] and not viewer.connected  # spawn(), which also connects


def test_view_url_connects_to_that_viewer(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    viewer = _Viewer(monkeypatch)
    url = "rerun+http://192.0.2.7:9876/proxy"
    assert run(["recognize", str(_roll(tmp_path)), "--view-url", url]) == 0
    assert viewer.connected == [url] and not viewer.spawned


def test_view_and_save_view_together_log_to_both(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    viewer = _Viewer(monkeypatch)
    src = _roll(tmp_path, "sphere", 1)
    capture, pitch = _capture(tmp_path, src)
    out = tmp_path / "live.rrd"
    args = ["recognize", "--live", f"file:{capture}", "--pitch-mm", str(pitch)]
    assert run([*args, "--view", "--save-view", str(out)]) == 0
    assert viewer.spawned == [{"port": 9876, "connect": False}]
    assert viewer.sinks == ["FileSink", "GrpcSink"]
    rows = _rows(out)
    assert len(rows["sensor/frames"]) == read_recording(src).n_frames
    assert rows["sensor/verdicts"][-1]["TextLog:text"][0].startswith("result: ")


@pytest.mark.parametrize(
    "argv",
    [
        ["trace", "--shape", "star", "--view"],
        ["show", "{src}", "--view"],
        ["recognize", "{src}", "--view-url", "rerun+http://h:1/proxy"],
    ],
)
def test_without_rerun_a_view_says_how_to_install(
    argv: list[str], tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    src = str(_roll(tmp_path))
    monkeypatch.setitem(sys.modules, "rerun", None)
    errors: list[str] = []
    assert run([a.replace("{src}", src) for a in argv], echo_err=errors.append) == 2
    assert len(errors) == 1 and 'pip install "taxelkit[viewer]"' in errors[0]


def test_view_and_view_url_together_are_refused(tmp_path: Path) -> None:
    errors: list[str] = []
    argv = ["recognize", str(_roll(tmp_path)), "--view", "--view-url", "rerun+http://h:1/proxy"]
    assert run(argv, echo_err=errors.append) == 2
    assert "not both" in errors[0]


def test_an_unreachable_viewer_is_one_typed_error() -> None:
    from taxelkit.viewer.rerun_view import ViewerConnectionError, close_stream

    class Stream:
        disconnected = False

        def flush(self) -> None:
            raise RuntimeError("gRPC has been unable to connect for 6s,\nuri: rerun+http://h:1")

        def disconnect(self) -> None:
            Stream.disconnected = True

    with pytest.raises(ViewerConnectionError, match=r"unable to connect for 6s, uri") as e:
        close_stream(Stream())
    assert "\n" not in str(e.value) and Stream.disconnected
