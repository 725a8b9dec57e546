"""Tactile frames as ROS 2 messages: the layout shared by rosbag2 folders and MCAP files.

A recording lives on one *frames topic* (default :data:`DEFAULT_TOPIC`) and an
optional *info topic* beside it (``<topic>/info``). The full schema is in
``docs/recording-format.md``; in short:

``sensor_msgs/msg/Image`` (written by default)
    One message per frame, ``height = rows``, ``width = cols``, row-major
    ``data``. Encodings read: ``mono8``, ``mono16`` (integer counts),
    ``32FC1``, ``64FC1`` (deflection in ``units``). ``header.stamp`` is the
    frame time; ``header.frame_id`` the sensor name. taxelkit writes float64
    frames as ``64FC1``, float32 and float16 as ``32FC1`` and contact images
    as ``mono8`` (0 or 255), so nothing is lost.
``std_msgs/msg/Float32MultiArray``
    One message per frame with two layout dimensions labelled ``rows`` and
    ``cols`` (``stride`` = ``rows*cols`` and ``cols``, ``data_offset`` = 0).
    It has no header: the frame time is the bag's log time.
``std_msgs/msg/String`` on ``<topic>/info`` (optional)
    One JSON object: ``pitch_mm``, ``units``, ``sensor``, ``dtype`` and the
    exact float64 ``t_s`` (nanosecond stamps cannot hold every float64 time).
    Absent fields fall back to the defaults of the recording format.

Everything here works on serialised CDR bytes through the rosbags typestore
(pure Python, no ROS installation); :mod:`taxelkit.io.bags` moves those bytes
in and out of rosbag2 folders and MCAP files. Problems with a bag are
:class:`~taxelkit.errors.RecordingError` subclasses whose one-line message
names the file.
"""

from __future__ import annotations

import functools
import json
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import (
    CorruptRecordingError,
    EmptyRecordingError,
    InvalidRecordingError,
    TaxelkitError,
)
from taxelkit.frames import CONTACT_UNITS
from taxelkit.io._raw import RawRecording, describe_exception, fail
from taxelkit.io.limits import ReadBudget

if TYPE_CHECKING:
    from rosbags.typesys.store import Typestore

__all__ = [
    "DEFAULT_TOPIC",
    "IMAGE_MSGTYPE",
    "INFO_SUFFIX",
    "MESSAGE_KINDS",
    "MULTIARRAY_MSGTYPE",
    "STRING_MSGTYPE",
    "BagDependencyError",
    "BagTopicError",
    "raw_from_messages",
    "select_topic",
    "typestore",
]

#: Topic of the frames when none is named.
DEFAULT_TOPIC = "/tactile"
#: The info topic is the frames topic with this suffix.
INFO_SUFFIX = "/info"
IMAGE_MSGTYPE = "sensor_msgs/msg/Image"
MULTIARRAY_MSGTYPE = "std_msgs/msg/Float32MultiArray"
STRING_MSGTYPE = "std_msgs/msg/String"
#: Frame message types by the short name used in
#: :func:`~taxelkit.io.ros_encode.encode_recording` and the CLI.
MESSAGE_KINDS = {"image": IMAGE_MSGTYPE, "multiarray": MULTIARRAY_MSGTYPE}
_FRAME_MSGTYPES = (IMAGE_MSGTYPE, MULTIARRAY_MSGTYPE)
#: Image encodings read, with the element type of their ``data`` (little-endian).
_IMAGE_DTYPES: dict[str, np.dtype[Any]] = {
    "mono8": np.dtype(np.uint8),
    "mono16": np.dtype("<u2"),
    "32FC1": np.dtype("<f4"),
    "64FC1": np.dtype("<f8"),
}
#: Units of integer images when the bag has no info message.
_COUNT_UNITS = "counts"
#: A contact taxel in a ``mono8`` image written by taxelkit (any non-zero reads as contact).
_CONTACT_VALUE = 255
_NS_PER_S = 1_000_000_000
#: Range of ``builtin_interfaces/msg/Time.sec`` (int32), s.
_SEC_MIN, _SEC_MAX = -(2**31), 2**31 - 1
#: Largest gap between an exact ``t_s`` in the info message and the stamp it
#: explains, s: the stamp is the time rounded to 1 ns, plus float64 rounding.
_STAMP_TOLERANCE_S = 2e-9
_INSTALL_HINT = 'pip install "taxelkit[ros]"'
_INFO_VERSION = 1


class BagDependencyError(TaxelkitError, ImportError):
    """rosbags or mcap, needed for ROS 2 bags and MCAP files, is not installed."""


class BagTopicError(CorruptRecordingError):
    """The bag has no usable frames topic: missing, ambiguous, or of another message type."""


@functools.cache
def typestore() -> Typestore:
    """The ROS 2 Humble type store of rosbags (messages without a ROS installation).

    Raises
    ------
    BagDependencyError
        If rosbags is not installed.
    """
    try:
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise BagDependencyError(
            f"ROS 2 bags and MCAP files need rosbags and mcap: {_INSTALL_HINT}"
        ) from None
    return get_typestore(Stores.ROS2_HUMBLE)


# ----------------------------------------------------------------------------- reading
def _describe_topics(topics: Mapping[str, str]) -> str:
    if not topics:
        return "no topics"
    return ", ".join(f"{name} ({msgtype})" for name, msgtype in sorted(topics.items()))


def select_topic(path: Path, topics: Mapping[str, str], topic: str | None) -> str:
    """The frames topic: ``topic`` if given, else the bag's only frame-message topic.

    Parameters
    ----------
    path : pathlib.Path
        The bag, for messages.
    topics : mapping of str to str
        Every topic of the bag and its message type.
    topic : str or None
        The topic asked for.

    Returns
    -------
    str

    Raises
    ------
    BagTopicError
        If ``topic`` is absent or carries another message type, or, with no
        ``topic``, if the bag has none or several frame topics. The message
        lists the bag's topics.
    """
    if topic is None:
        found = [name for name, msgtype in topics.items() if msgtype in _FRAME_MSGTYPES]
        if len(found) == 1:
            return found[0]
        problem = "no topic of" if not found else "several topics of"
        hint = "" if not found else "; choose one with --topic"
        raise fail(
            BagTopicError,
            path,
            f"{problem} {' or '.join(_FRAME_MSGTYPES)} (the bag holds: "
            f"{_describe_topics(topics)}){hint}",
        )
    if topic not in topics:
        raise fail(
            BagTopicError,
            path,
            f"no topic {topic!r} (the bag holds: {_describe_topics(topics)})",
        )
    if topics[topic] not in _FRAME_MSGTYPES:
        raise fail(
            BagTopicError,
            path,
            f"topic {topic!r} carries {topics[topic]}, expected {' or '.join(_FRAME_MSGTYPES)}",
        )
    return topic


@dataclass(frozen=True)
class _Frame:
    """One decoded frame: its taxels and its time (header stamp or log time), ns."""

    taxels: NDArray[Any]
    t_ns: int
    frame_id: str = ""


def _deserialize(path: Path, data: bytes, msgtype: str, index: int) -> Any:
    try:
        return typestore().deserialize_cdr(data, msgtype)
    except TaxelkitError:
        raise
    except Exception as exc:
        raise fail(
            CorruptRecordingError,
            path,
            f"message {index} is not a valid {msgtype} ({describe_exception(exc)})",
        ) from exc


def _frame_from_image(path: Path, msg: Any, index: int) -> _Frame:
    encoding = str(msg.encoding)
    known = _IMAGE_DTYPES.get(encoding)
    if known is None:
        raise fail(
            CorruptRecordingError,
            path,
            f"message {index} has image encoding {encoding!r}; expected one of "
            f"{', '.join(_IMAGE_DTYPES)}",
        )
    dtype: np.dtype[Any] = known.newbyteorder(">") if msg.is_bigendian else known
    rows, cols, step = int(msg.height), int(msg.width), int(msg.step)
    data = np.asarray(msg.data, dtype=np.uint8)
    if step < cols * dtype.itemsize or data.size != rows * step:
        raise fail(
            CorruptRecordingError,
            path,
            f"message {index} ({rows} x {cols} {encoding}, step {step}) holds {data.size} "
            f"bytes, expected step >= {cols * dtype.itemsize} and height * step",
        )
    taxels = data.reshape(rows, step)[:, : cols * dtype.itemsize].copy().view(dtype)
    stamp = msg.header.stamp
    t_ns = int(stamp.sec) * _NS_PER_S + int(stamp.nanosec)
    return _Frame(taxels.astype(dtype.newbyteorder("=")), t_ns, str(msg.header.frame_id))


def _frame_from_multiarray(path: Path, msg: Any, index: int, log_ns: int) -> _Frame:
    dims = list(msg.layout.dim)
    data = np.asarray(msg.data, dtype=np.float32)
    offset = int(msg.layout.data_offset)
    if len(dims) != 2:
        raise fail(
            CorruptRecordingError,
            path,
            f"message {index} has a layout of {len(dims)} dimension(s), expected 2 (rows, cols)",
        )
    rows, cols = int(dims[0].size), int(dims[1].size)
    if data.size != offset + rows * cols:
        raise fail(
            CorruptRecordingError,
            path,
            f"message {index} holds {data.size} values, expected data_offset + rows * cols = "
            f"{offset} + {rows} * {cols}",
        )
    return _Frame(data[offset:].reshape(rows, cols), log_ns)


def _parse_info(path: Path, data: bytes) -> dict[str, Any]:
    text = str(_deserialize(path, data, STRING_MSGTYPE, 0).data)
    try:
        info = json.loads(text)
    except ValueError as exc:
        raise fail(
            InvalidRecordingError, path, f"the info message is not JSON ({describe_exception(exc)})"
        ) from exc
    if not isinstance(info, dict):
        raise fail(InvalidRecordingError, path, "the info message must be a JSON object")
    return info


def _exact_times(info: Mapping[str, Any], t_s: NDArray[np.float64], *, relative: bool) -> Any:
    """The info message's exact ``t_s`` if it explains the stamps read, else ``t_s``."""
    exact = info.get("t_s")
    if not isinstance(exact, list) or len(exact) != t_s.size:
        return t_s
    try:
        candidate = np.asarray(exact, dtype=np.float64)
    except (TypeError, ValueError):
        return t_s
    if candidate.ndim != 1 or not np.all(np.isfinite(candidate)):
        return t_s
    if relative:  # log times were shifted to start at >= 0
        a, b = candidate - candidate[0], t_s - t_s[0]
    else:
        a, b = candidate, t_s
    tolerance = _STAMP_TOLERANCE_S + 4 * np.finfo(np.float64).eps * np.abs(b)
    return candidate if np.all(np.abs(a - b) <= tolerance) else t_s


def _taxel_array(path: Path, frames: list[_Frame]) -> NDArray[Any]:
    first = frames[0].taxels.shape
    for k, frame in enumerate(frames):
        if frame.taxels.shape != first:
            raise fail(
                CorruptRecordingError,
                path,
                f"message {k} is {frame.taxels.shape[0]} x {frame.taxels.shape[1]} taxels, "
                f"message 0 was {first[0]} x {first[1]}",
            )
    return np.stack([frame.taxels for frame in frames])


def raw_from_messages(
    path: Path,
    topics: Mapping[str, str],
    messages: Iterable[tuple[str, int, bytes]],
    topic: str,
) -> RawRecording:
    """Decode the frames and info messages of ``topic`` into raw recording fields.

    Parameters
    ----------
    path : pathlib.Path
        The bag, for messages.
    topics : mapping of str to str
        Every topic of the bag and its message type; ``topic`` must be a
        frames topic (see :func:`select_topic`).
    messages : iterable of (str, int, bytes)
        ``(topic, log_time_ns, cdr_bytes)`` in log-time order; other topics are skipped.
    topic : str
        The frames topic.

    Returns
    -------
    RawRecording
        ``frames`` ``(T, rows, cols)`` (uint8/uint16/float32/float64, or bool
        for contact images), ``t_s`` ``(T,)`` float64 s, and the info fields.

    Raises
    ------
    EmptyRecordingError
        If the topic has no messages.
    CorruptRecordingError
        If a message cannot be decoded, has an unknown encoding, a size that
        does not match its data, or other dimensions than the first.
    FileTooLargeError
        If the decoded frames exceed the read limit of :mod:`taxelkit.io.limits`.
    InvalidRecordingError
        If the info message is not a JSON object.
    """
    msgtype = topics[topic]
    info_topic = topic + INFO_SUFFIX
    frames: list[_Frame] = []
    info: dict[str, Any] = {}
    # Every decoded frame is charged to the read limit (taxelkit.io.limits),
    # twice: the list of frames and the stacked array built from it.
    budget = ReadBudget(path)
    for name, log_ns, data in messages:
        if name == topic:
            msg = _deserialize(path, data, msgtype, len(frames))
            if msgtype == IMAGE_MSGTYPE:
                frame = _frame_from_image(path, msg, len(frames))
            else:
                frame = _frame_from_multiarray(path, msg, len(frames), log_ns)
            budget.take(
                f"frame {len(frames)} of topic {topic!r}",
                (2, *frame.taxels.shape),
                frame.taxels.dtype,
            )
            frames.append(frame)
        elif name == info_topic and topics.get(info_topic) == STRING_MSGTYPE and not info:
            info = _parse_info(path, data)
    if not frames:
        raise fail(EmptyRecordingError, path, f"topic {topic!r} has no messages")
    taxels = _taxel_array(path, frames)
    t_ns = np.array([frame.t_ns for frame in frames], dtype=np.int64)
    t_s = _exact_times(info, t_ns / _NS_PER_S, relative=msgtype == MULTIARRAY_MSGTYPE)
    units = info.get("units")
    if units == CONTACT_UNITS:
        taxels = taxels != 0
    elif info.get("dtype") == "float16" and taxels.dtype == np.float32:
        taxels = taxels.astype(np.float16)
    elif units is None and taxels.dtype.kind == "u":
        units = _COUNT_UNITS
    sensor = info.get("sensor")
    if sensor is None and frames[0].frame_id:
        sensor = frames[0].frame_id
    found = tuple(sorted(topics))
    return RawRecording(
        frames=taxels,
        t_s=t_s,
        pitch_mm=info.get("pitch_mm"),
        units=units,
        sensor=sensor,
        found=found,
    )
