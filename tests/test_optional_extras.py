"""The core stays lean: the optional extras are imported only by the modules that need them."""

from __future__ import annotations

import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

from taxelkit.cli import run
from taxelkit.frames import TactileFrames
from taxelkit.io import ros_messages

ROOT = Path(__file__).resolve().parents[1]
OPTIONAL = ("rosbags", "mcap", "gymnasium", "rerun", "mkdocs", "mkdocstrings")


def test_core_dependencies_exclude_the_extras() -> None:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    core = " ".join(project["dependencies"]).lower()
    assert not any(name in core for name in ("rosbags", "mcap", "gymnasium", "rerun", "mkdocs"))
    extras = project["optional-dependencies"]
    assert {"ros", "gym", "docs", "viewer"} <= set(extras)
    test_extra = " ".join(extras["test"])
    for package in ("scikit-image", "rosbags", "mcap", "gymnasium", "rerun-sdk"):
        assert package in test_extra


def test_core_and_cli_import_no_optional_package() -> None:
    code = (
        "import sys\n"
        "import taxelkit.cli, taxelkit.io.recordings, taxelkit.io.bags, taxelkit.io.ros_messages\n"
        "import taxelkit.io.source_plugins, taxelkit.smart.recogniser, taxelkit.cli.live\n"
        "from taxelkit.cli import run\n"
        "assert run(['sensors']) == 0 and run(['sources']) == 0\n"
        f"print(sorted(m for m in sys.modules if m.split('.')[0] in {OPTIONAL!r}))\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=ROOT
    ).stdout
    assert out.strip().splitlines()[-1] == "[]"


def test_a_bag_without_the_ros_extra_says_how_to_install(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    ros_messages.typestore.cache_clear()
    monkeypatch.setitem(sys.modules, "rosbags", None)
    monkeypatch.setitem(sys.modules, "rosbags.typesys", None)
    try:
        rec = TactileFrames(np.zeros((2, 2, 2)))
        errors: list[str] = []
        path = tmp_path / "a.mcap"
        np.savez(tmp_path / "a.npz", frames=rec.frames)
        assert run(["convert", str(tmp_path / "a.npz"), str(path)], echo_err=errors.append) == 2
        assert 'pip install "taxelkit[ros]"' in errors[0] and "\n" not in errors[0]
        assert not path.exists()
        (tmp_path / "bag").mkdir()
        (tmp_path / "bag" / "metadata.yaml").write_text("rosbag2_bagfile_information: {}\n")
        assert run(["info", str(tmp_path / "bag")], echo_err=errors.append) == 2
        assert 'pip install "taxelkit[ros]"' in errors[1]
    finally:
        ros_messages.typestore.cache_clear()


def test_envs_without_gymnasium_says_how_to_install() -> None:
    code = "import sys\nsys.modules['gymnasium'] = None\nimport taxelkit.envs\n"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode != 0
    assert 'pip install "taxelkit[gym]"' in proc.stderr
