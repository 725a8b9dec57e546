"""ROS 2 bags (rosbag2 folders) and MCAP files as recordings, and ``taxelkit convert``."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

pytest.importorskip("rosbags", reason="ROS 2 bag support needs the ros extra")
pytest.importorskip("mcap", reason="MCAP support needs the ros extra")

from rosbags.rosbag2 import Writer

from taxelkit.cli import run
from taxelkit.errors import (
    CorruptRecordingError,
    EmptyRecordingError,
    InputError,
    InvalidRecordingError,
    OutputExistsError,
)
from taxelkit.frames import TactileFrames
from taxelkit.io.bags import is_rosbag2_folder, write_rosbag2
from taxelkit.io.recordings import read_recording, write_recording
from taxelkit.io.ros_messages import BagTopicError, typestore
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import make_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart.recogniser import recognise

DTYPES = [np.float64, np.float32, np.float16, np.bool_]
FORMATS = ["npz", "h5", "csv", "mcap", "rosbag2"]
SOLIDS = ["cube", "sphere", "cone", "truncated-cone", "cylinder", "tetrahedron"]


def _recording(dtype: Any, *, seed: int = 0) -> TactileFrames:
    rng = np.random.default_rng(seed)
    shape = (7, 5, 3)
    frames = rng.random(shape) > 0.5 if dtype == np.bool_ else rng.normal(size=shape).astype(dtype)
    # Irregular times with a negative origin: not on a nanosecond grid.
    t_s = np.cumsum(rng.random(shape[0]) + 0.01) - 1.2345678901234567
    return TactileFrames(frames, t_s, pitch_mm=1.7625, sensor="bonneville-16x16")


def _path(folder: Path, name: str, fmt: str) -> Path:
    return folder / (name if fmt == "rosbag2" else f"{name}.{fmt}")


def _write(rec: TactileFrames, path: Path, fmt: str, **kwargs: Any) -> Path:
    if fmt == "rosbag2":
        return write_rosbag2(rec, path, **kwargs)
    return write_recording(rec, path, **kwargs)


def _handwritten_bag(path: Path, messages: list[tuple[str, str, Any]]) -> Path:
    """A rosbag2 folder from ``(topic, msgtype, message)`` tuples, one per ns."""
    store = typestore()
    with Writer(path, version=9) as writer:
        connections: dict[str, Any] = {}
        for k, (topic, msgtype, msg) in enumerate(messages):
            if topic not in connections:
                connections[topic] = writer.add_connection(topic, msgtype, typestore=store)
            writer.write(connections[topic], 1000 + k, store.serialize_cdr(msg, msgtype))
    return path


def _image(rows: int, cols: int, *, encoding: str = "32FC1", sec: int = 0, data: Any = None) -> Any:
    types = typestore().types
    itemsize = {"mono8": 1, "mono16": 2, "32FC1": 4, "64FC1": 8, "rgb8": 3}[encoding]
    if data is None:
        data = np.zeros(rows * cols * itemsize, np.uint8)
    header = types["std_msgs/msg/Header"](
        stamp=types["builtin_interfaces/msg/Time"](sec=sec, nanosec=500), frame_id="skin"
    )
    return types["sensor_msgs/msg/Image"](
        header=header,
        height=rows,
        width=cols,
        encoding=encoding,
        is_bigendian=0,
        step=cols * itemsize,
        data=np.asarray(data, np.uint8),
    )


# ----------------------------------------------------------------------------- round trips
@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("fmt", ["mcap", "rosbag2"])
def test_round_trip_is_exact(tmp_path: Path, dtype: Any, fmt: str) -> None:
    rec = _recording(dtype)
    out = _write(rec, _path(tmp_path, "rec", fmt), fmt)
    back = read_recording(out)
    assert back.equals(rec)
    assert back.frames.dtype == rec.frames.dtype


@pytest.mark.parametrize("dtype", [np.float32, np.float16, np.bool_])
@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_multiarray_round_trip_is_exact(tmp_path: Path, dtype: Any, storage: str) -> None:
    rec = _recording(dtype, seed=3)
    out = write_rosbag2(rec, tmp_path / "bag", message="multiarray", storage=storage)
    assert read_recording(out).equals(rec)


def test_multiarray_refuses_float64(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="float32"):
        write_rosbag2(_recording(np.float64), tmp_path / "bag", message="multiarray")
    assert list(tmp_path.iterdir()) == []


def test_custom_topic_and_pitch_override(tmp_path: Path) -> None:
    rec = _recording(np.float32)
    out = write_recording(rec, tmp_path / "r.mcap", topic="/left/skin")
    assert read_recording(out, topic="/left/skin").equals(rec)
    assert read_recording(out, pitch_mm=2.5).pitch_mm == 2.5


@pytest.mark.parametrize("source", FORMATS)
@pytest.mark.parametrize("target", FORMATS)
def test_convert_every_pair_is_lossless(tmp_path: Path, source: str, target: str) -> None:
    rec = _recording(np.float64, seed=7)
    src = _write(rec, _path(tmp_path, "in", source), source)
    dst = _path(tmp_path, "out", target)
    assert run(["convert", str(src), str(dst)]) == 0
    back = read_recording(dst)
    assert back.equals(rec)
    assert back.t_s.tobytes() == rec.t_s.tobytes()


def test_convert_refuses_existing_output_then_forces(tmp_path: Path) -> None:
    rec = _recording(np.float32)
    src = write_recording(rec, tmp_path / "in.npz")
    bag = write_rosbag2(_recording(np.float32, seed=9), tmp_path / "bag")
    errors: list[str] = []
    assert run(["convert", str(src), str(bag)], echo_err=errors.append) == 2
    assert "exists" in errors[0]
    assert not read_recording(bag).equals(rec)
    assert run(["convert", str(src), str(bag), "--force"]) == 0
    assert read_recording(bag).equals(rec)
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == []


def test_force_never_replaces_a_plain_folder(tmp_path: Path) -> None:
    folder = tmp_path / "photos"
    folder.mkdir()
    (folder / "keep.txt").write_text("mine")
    with pytest.raises(OutputExistsError, match="not a rosbag2 folder"):
        write_rosbag2(_recording(np.float32), folder, force=True)
    assert (folder / "keep.txt").read_text() == "mine"


# ----------------------------------------------------------------------------- foreign bags
def test_foreign_mono16_bag_without_info(tmp_path: Path) -> None:
    counts = np.arange(2 * 3 * 4, dtype="<u2").reshape(2, 3, 4)
    bag = _handwritten_bag(
        tmp_path / "bag",
        [
            (
                "/cam",
                "sensor_msgs/msg/Image",
                _image(3, 4, encoding="mono16", sec=10 + k, data=counts[k].view(np.uint8).ravel()),
            )
            for k in range(2)
        ],
    )
    rec = read_recording(bag)
    assert rec.units == "counts" and rec.sensor == "skin" and rec.pitch_mm == 1.0
    np.testing.assert_array_equal(rec.frames, counts)
    np.testing.assert_array_equal(rec.t_s, [10.0000005, 11.0000005])


def test_image_rows_with_padding(tmp_path: Path) -> None:
    values = np.array([[1.0, 2.0], [3.0, 4.0]], "<f4")
    padded = np.zeros((2, 12), np.uint8)  # step 12 bytes for 2 float32 taxels
    padded[:, :8] = values.view(np.uint8)
    msg = _image(2, 2, data=padded.ravel())
    msg.step = 12
    bag = _handwritten_bag(tmp_path / "bag", [("/t", "sensor_msgs/msg/Image", msg)])
    np.testing.assert_array_equal(read_recording(bag).frames[0], values)


# ----------------------------------------------------------------------------- bad bags
def test_missing_topic_lists_the_topics(tmp_path: Path) -> None:
    out = write_recording(_recording(np.float32), tmp_path / "r.mcap")
    with pytest.raises(BagTopicError) as info:
        read_recording(out, topic="/nope")
    message = str(info.value)
    assert message.startswith(str(out)) and "\n" not in message
    assert "/tactile (sensor_msgs/msg/Image)" in message


def test_wrong_message_type(tmp_path: Path) -> None:
    out = write_rosbag2(_recording(np.float32), tmp_path / "bag")
    with pytest.raises(BagTopicError, match="carries std_msgs/msg/String"):
        read_recording(out, topic="/tactile/info")


def test_no_and_several_frame_topics(tmp_path: Path) -> None:
    string = typestore().types["std_msgs/msg/String"](data="hi")
    only_text = _handwritten_bag(tmp_path / "a", [("/chat", "std_msgs/msg/String", string)])
    with pytest.raises(BagTopicError, match=r"no topic of .*/chat \(std_msgs/msg/String\)"):
        read_recording(only_text)
    two = _handwritten_bag(
        tmp_path / "b",
        [
            ("/l", "sensor_msgs/msg/Image", _image(2, 2)),
            ("/r", "sensor_msgs/msg/Image", _image(2, 2)),
        ],
    )
    with pytest.raises(BagTopicError, match=r"several topics .* choose one with --topic"):
        read_recording(two)
    assert read_recording(two, topic="/r").shape == (1, 2, 2)


def test_mismatched_sizes(tmp_path: Path) -> None:
    bag = _handwritten_bag(
        tmp_path / "bag",
        [
            ("/t", "sensor_msgs/msg/Image", _image(4, 4, sec=0)),
            ("/t", "sensor_msgs/msg/Image", _image(4, 3, sec=1)),
        ],
    )
    with pytest.raises(
        CorruptRecordingError, match="message 1 is 4 x 3 taxels, message 0 was 4 x 4"
    ):
        read_recording(bag)


def test_data_shorter_than_the_image(tmp_path: Path) -> None:
    msg = _image(4, 4, data=np.zeros(10, np.uint8))
    bag = _handwritten_bag(tmp_path / "bag", [("/t", "sensor_msgs/msg/Image", msg)])
    with pytest.raises(CorruptRecordingError, match="holds 10 bytes"):
        read_recording(bag)


def test_unknown_encoding(tmp_path: Path) -> None:
    bag = _handwritten_bag(
        tmp_path / "bag", [("/t", "sensor_msgs/msg/Image", _image(2, 2, encoding="rgb8"))]
    )
    with pytest.raises(CorruptRecordingError, match="encoding 'rgb8'; expected one of mono8"):
        read_recording(bag)


def test_multiarray_with_wrong_layout(tmp_path: Path) -> None:
    types = typestore().types
    dim = types["std_msgs/msg/MultiArrayDimension"]
    layout = types["std_msgs/msg/MultiArrayLayout"](
        dim=[dim(label="rows", size=3, stride=9), dim(label="cols", size=3, stride=3)],
        data_offset=0,
    )
    msg = types["std_msgs/msg/Float32MultiArray"](layout=layout, data=np.zeros(8, np.float32))
    bag = _handwritten_bag(tmp_path / "bag", [("/t", "std_msgs/msg/Float32MultiArray", msg)])
    with pytest.raises(CorruptRecordingError, match="holds 8 values"):
        read_recording(bag)


def test_info_that_is_not_json(tmp_path: Path) -> None:
    bad = typestore().types["std_msgs/msg/String"](data="{pitch")
    bag = _handwritten_bag(
        tmp_path / "bag",
        [("/t/info", "std_msgs/msg/String", bad), ("/t", "sensor_msgs/msg/Image", _image(2, 2))],
    )
    with pytest.raises(InvalidRecordingError, match="info message is not JSON"):
        read_recording(bag)


def test_info_that_contradicts_the_stamps_is_not_used(tmp_path: Path) -> None:
    info = typestore().types["std_msgs/msg/String"](data=json.dumps({"t_s": [99.0]}))
    bag = _handwritten_bag(
        tmp_path / "bag",
        [("/t/info", "std_msgs/msg/String", info), ("/t", "sensor_msgs/msg/Image", _image(2, 2))],
    )
    assert read_recording(bag).t_s.tolist() == [5e-7]


def test_topic_without_messages(tmp_path: Path) -> None:
    store = typestore()
    with Writer(tmp_path / "bag", version=9) as writer:
        writer.add_connection("/t", "sensor_msgs/msg/Image", typestore=store)
    with pytest.raises(EmptyRecordingError, match="no messages"):
        read_recording(tmp_path / "bag")


def test_truncated_mcap(tmp_path: Path) -> None:
    out = write_recording(_recording(np.float32), tmp_path / "r.mcap")
    data = out.read_bytes()
    out.write_bytes(data[: len(data) // 2])
    with pytest.raises(CorruptRecordingError, match="unreadable MCAP file") as info:
        read_recording(out)
    assert "\n" not in str(info.value)


def test_npz_renamed_to_mcap(tmp_path: Path) -> None:
    out = write_recording(_recording(np.float32), tmp_path / "r.npz")
    renamed = out.rename(tmp_path / "r.mcap")
    with pytest.raises(CorruptRecordingError, match=r"holds an \.npz archive, not an MCAP file"):
        read_recording(renamed)


def test_topic_is_refused_for_plain_files(tmp_path: Path) -> None:
    out = write_recording(_recording(np.float32), tmp_path / "r.npz")
    with pytest.raises(InputError, match="topic applies only"):
        read_recording(out, topic="/tactile")


def test_a_plain_folder_is_still_not_a_recording(tmp_path: Path) -> None:
    assert not is_rosbag2_folder(tmp_path)
    errors: list[str] = []
    assert run(["info", str(tmp_path)], echo_err=errors.append) == 2
    assert "folder" in errors[0]


def test_cli_bad_bag_is_one_line_exit_2(tmp_path: Path) -> None:
    bag = write_rosbag2(_recording(np.float32), tmp_path / "bag")
    for args in (
        ["info", str(bag), "--topic", "/x"],
        ["show", str(bag), "--topic", "/x", "--out", str(tmp_path / "s.png")],
        ["recognize", str(bag), "--topic", "/x"],
        ["convert", str(bag), str(tmp_path / "o.npz"), "--topic", "/x"],
    ):
        errors: list[str] = []
        assert run(args, echo_err=errors.append) == 2
        assert len(errors) == 1 and "no topic '/x'" in errors[0] and "\n" not in errors[0]


# ----------------------------------------------------------------------------- acceptance
@pytest.mark.parametrize("name", SOLIDS)
def test_bags_give_the_npz_verdicts(tmp_path: Path, name: str) -> None:
    """The six solids' rolls, as .npz, .mcap and rosbag2: identical recognition."""
    rec = frames_from_scenario(BONNEVILLE_16X16, make_scenario(name, rng=2), rng=2)
    npz = write_recording(rec, tmp_path / "roll.npz")
    expected = recognise(read_recording(npz))
    for path in (
        write_recording(rec, tmp_path / "roll.mcap"),
        write_rosbag2(rec, tmp_path / "roll-bag"),
        write_rosbag2(rec, tmp_path / "roll-bag-mcap", storage="mcap"),
    ):
        got = recognise(read_recording(path))
        assert got.identified == expected.identified
        assert got.candidates == expected.candidates
        assert got.to_json() == expected.to_json()


def test_info_message_keys_are_documented() -> None:
    """Every key taxelkit writes in the info message has a row in docs/recording-format.md."""
    from taxelkit.io.ros_encode import info_json

    doc = (Path(__file__).resolve().parents[2] / "docs" / "recording-format.md").read_text()
    section = doc.split("### The info message", 1)[1].split("\n### ", 1)[0]
    documented = {
        line.split("|")[1].strip().strip("`")
        for line in section.splitlines()
        if line.startswith("| `")
    }
    written = set(json.loads(info_json(_recording(np.float32))))
    assert written == documented


def test_convert_options_message_storage_and_topic(tmp_path: Path) -> None:
    rec = _recording(np.float32, seed=11)
    src = write_recording(rec, tmp_path / "in.npz")
    out = tmp_path / "ma.mcap"
    assert run(["convert", str(src), str(out), "--message", "multiarray", "--topic", "/s"]) == 0
    assert read_recording(out, topic="/s").equals(rec)
    bag = tmp_path / "bag"
    assert run(["convert", str(out), str(bag), "--storage", "mcap", "--topic", "/s"]) == 0
    assert (bag / "metadata.yaml").read_text().count("storage_identifier: mcap") == 1
    assert read_recording(bag, topic="/s").equals(rec)
    errors: list[str] = []
    plain = ["convert", str(src), str(tmp_path / "o.csv"), "--topic", "/s"]
    assert run(plain, echo_err=errors.append) == 2
    assert "--topic applies only" in errors[0]
    f64 = write_recording(_recording(np.float64), tmp_path / "f64.npz")
    multi = ["convert", str(f64), str(tmp_path / "f.mcap"), "--message", "multiarray"]
    assert run(multi, echo_err=errors.append) == 2
    assert "float32" in errors[1] and not (tmp_path / "f.mcap").exists()
