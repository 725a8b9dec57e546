"""Live sources as plugins: the ``taxelkit.sources`` entry-point group and ``taxelkit sources``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from taxelkit.cli import run
from taxelkit.cli.live import recognize_live
from taxelkit.io import source_plugins
from taxelkit.io.frame_protocol import encode_frame
from taxelkit.io.live_sources import FrameSource, LiveSourceError, SourceSpecError
from taxelkit.io.source_plugins import (
    BUILTIN_SOURCES,
    open_plugin_source,
    register_source,
    resolve_source,
)
from taxelkit.io.source_plugins import (
    source_plugins as list_plugins,
)
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import make_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16

PLUGIN_MODULE = '''
from taxelkit.io.source_plugins import open_file


def open_fake(address, *, shape=None, max_taxels=65536):
    """A fake vendor array (replays a capture file)."""
    return open_file(address, shape=shape, max_taxels=max_taxels)


def not_a_source(address, *, shape=None, max_taxels=65536):
    """Returns the wrong thing."""
    return 42
'''


@pytest.fixture(autouse=True)
def _no_registered_sources(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(source_plugins, "_REGISTERED", {})


def _install_fake_distribution(folder: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """A distribution on sys.path declaring entry points, as ``pip install`` would leave it."""
    (folder / "fake_vendor_plugin.py").write_text(PLUGIN_MODULE)
    info = folder / "fake_vendor-1.0.dist-info"
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: fake-vendor\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text(
        "[taxelkit.sources]\n"
        "fake = fake_vendor_plugin:open_fake\n"
        "wrong = fake_vendor_plugin:not_a_source\n"
        "broken = no_such_module_anywhere:open\n"
        "udp = fake_vendor_plugin:open_fake\n"
    )
    monkeypatch.syspath_prepend(str(folder))


def _capture(path: Path) -> Path:
    """The bytes a device would send for a simulated cylinder roll."""
    rec = frames_from_scenario(BONNEVILLE_16X16, make_scenario("cylinder", rng=3), rng=3)
    frames = np.asarray(rec.frames, dtype=np.float32)
    packets = [
        encode_frame(f, index=k, t_s=float(t))
        for k, (f, t) in enumerate(zip(frames, rec.t_s, strict=True))
    ]
    path.write_bytes(b"".join(packets))
    return path


def test_builtins_are_listed(capsys: pytest.CaptureFixture[str]) -> None:
    assert set(BUILTIN_SOURCES) <= set(list_plugins())
    assert run(["sources"]) == 0
    out = capsys.readouterr().out
    for name in ("serial", "udp", "file"):
        assert any(line.startswith(name) for line in out.splitlines())


def test_file_source_replays_a_capture(tmp_path: Path) -> None:
    capture = _capture(tmp_path / "roll.bin")
    lines: list[str] = []
    assert recognize_live(f"file:{capture}", pitch_mm=1.7625, echo=lines.append) == 0
    assert any("identified cylinder" in line for line in lines)


def test_missing_file_is_one_line(tmp_path: Path) -> None:
    errors: list[str] = []
    code = run(
        ["recognize", "--live", f"file:{tmp_path / 'none.bin'}", "--pitch-mm", "1"],
        echo_err=errors.append,
    )
    assert code == 2 and "cannot open file:" in errors[0] and "\n" not in errors[0]


def test_unknown_kind_lists_the_known_ones() -> None:
    with pytest.raises(SourceSpecError, match="KIND one of file, serial, udp") as info:
        resolve_source("usb:0")
    assert str(info.value).endswith("got 'usb:0'")
    with pytest.raises(SourceSpecError, match="empty or blank address"):
        resolve_source("file:")
    with pytest.raises(SourceSpecError, match="PORT must be an integer"):
        resolve_source("udp:localhost:http")


def test_entry_point_plugin_is_found_and_used(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    _install_fake_distribution(tmp_path, monkeypatch)
    plugins = list_plugins()
    assert plugins["fake"].origin == "fake-vendor"
    assert plugins["udp"].origin == "taxelkit (built-in)"  # a plugin cannot replace a built-in
    capture = _capture(tmp_path / "roll.bin")
    lines: list[str] = []
    assert recognize_live(f"fake:{capture}", pitch_mm=1.7625, echo=lines.append) == 0
    assert any("identified cylinder" in line for line in lines)
    assert run(["sources"]) == 0
    out = capsys.readouterr().out
    assert "A fake vendor array (replays a capture file).  [fake-vendor]" in out
    assert "broken" in out and "(cannot be loaded)" in out


def test_broken_and_wrong_plugins_fail_in_one_line(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    _install_fake_distribution(tmp_path, monkeypatch)
    with pytest.raises(LiveSourceError, match=r"'broken' from fake-vendor cannot be loaded"):
        resolve_source("broken:x")
    with pytest.raises(LiveSourceError, match="returned int, not a FrameSource"):
        open_plugin_source("wrong:x")
    errors: list[str] = []
    assert run(["recognize", "--live", "broken:x", "--pitch-mm", "1"], echo_err=errors.append) == 2
    assert len(errors) == 1 and "\n" not in errors[0]


def test_register_source_in_process(tmp_path: Path) -> None:
    calls: list[str] = []

    def open_mine(address: str, *, shape: object, max_taxels: int) -> FrameSource:
        calls.append(address)
        return source_plugins.open_file(str(_capture(tmp_path / "c.bin")))

    register_source("mine", open_mine)
    lines: list[str] = []
    assert recognize_live("mine:abc", pitch_mm=1.7625, echo=lines.append) == 0
    assert calls == ["abc"]
    with pytest.raises(SourceSpecError, match="built-in"):
        register_source("serial", open_mine)
    with pytest.raises(SourceSpecError, match="lower-case identifier"):
        register_source("My Device", open_mine)
