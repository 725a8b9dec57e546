"""Tactile recordings as ROS 2 messages: the writing side of :mod:`taxelkit.io.ros_messages`.

A recording becomes one ``sensor_msgs/msg/Image`` or
``std_msgs/msg/Float32MultiArray`` message per frame and a JSON info message
(pitch, units, sensor, exact times), ready for a bag writer
(:mod:`taxelkit.io.bags`). Needs the optional ``ros`` extra.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.frames import TactileFrames
from taxelkit.io.ros_messages import (
    _CONTACT_VALUE,
    _INFO_VERSION,
    _NS_PER_S,
    _SEC_MAX,
    _SEC_MIN,
    DEFAULT_TOPIC,
    IMAGE_MSGTYPE,
    INFO_SUFFIX,
    MESSAGE_KINDS,
    MULTIARRAY_MSGTYPE,
    STRING_MSGTYPE,
    typestore,
)

__all__ = ["EncodedRecording", "encode_recording", "info_json"]


@dataclass(frozen=True)
class EncodedRecording:
    """A recording as serialised messages, ready for a bag writer.

    Parameters
    ----------
    connections : tuple of (str, str)
        ``(topic, msgtype)`` of the frames topic and the info topic.
    messages : tuple of (str, int, bytes)
        ``(topic, log_time_ns, cdr_bytes)`` in log-time order: the info
        message, then one message per frame.
    """

    connections: tuple[tuple[str, str], ...]
    messages: tuple[tuple[str, int, bytes], ...]


def _stamps_ns(t_s: NDArray[np.float64]) -> list[int]:
    stamps = [round(float(t) * _NS_PER_S) for t in t_s]
    for t, ns in zip(t_s, stamps, strict=True):
        if not _SEC_MIN <= ns // _NS_PER_S <= _SEC_MAX:
            raise InputError(
                f"t_s must fit a ROS time (int32 seconds) to be stored in a bag, got {float(t)!r}"
            )
    return stamps


def _check_topic(topic: str) -> str:
    if not topic.startswith("/") or topic.endswith("/") or any(c.isspace() for c in topic):
        raise InputError(f"topic must look like /name (no spaces, no trailing /), got {topic!r}")
    return topic


def _image_message(rec: TactileFrames, k: int, ns: int) -> Any:
    types = typestore().types
    frame = rec.frames[k]
    if rec.is_contact:
        pixels = frame.astype(np.uint8) * np.uint8(_CONTACT_VALUE)
        encoding = "mono8"
    elif frame.dtype == np.float64:
        pixels, encoding = frame.astype("<f8"), "64FC1"
    else:
        pixels, encoding = frame.astype("<f4"), "32FC1"
    rows, cols = frame.shape
    header = types["std_msgs/msg/Header"](
        stamp=types["builtin_interfaces/msg/Time"](sec=ns // _NS_PER_S, nanosec=ns % _NS_PER_S),
        frame_id=rec.sensor,
    )
    return types[IMAGE_MSGTYPE](
        header=header,
        height=rows,
        width=cols,
        encoding=encoding,
        is_bigendian=0,
        step=cols * pixels.dtype.itemsize,
        data=np.ascontiguousarray(pixels).view(np.uint8).reshape(-1),
    )


def _multiarray_message(rec: TactileFrames, k: int) -> Any:
    types = typestore().types
    rows, cols = rec.shape[1:]
    dim = types["std_msgs/msg/MultiArrayDimension"]
    layout = types["std_msgs/msg/MultiArrayLayout"](
        dim=[
            dim(label="rows", size=rows, stride=rows * cols),
            dim(label="cols", size=cols, stride=cols),
        ],
        data_offset=0,
    )
    data = rec.frames[k].astype(np.float32).reshape(-1)
    return types[MULTIARRAY_MSGTYPE](layout=layout, data=data)


def info_json(rec: TactileFrames) -> str:
    """The info message's JSON text for ``rec`` (exact float64 times and pitch).

    Examples
    --------
    >>> import numpy as np
    >>> rec = TactileFrames(np.zeros((2, 1, 1)), [0.0, 0.5], pitch_mm=2.0)
    >>> info_json(rec)  # doctest: +NORMALIZE_WHITESPACE
    '{"taxelkit_info": 1, "pitch_mm": 2.0, "units": "mm", "sensor": "unknown",
      "dtype": "float64", "t_s": [0.0, 0.5]}'
    """
    return json.dumps(
        {
            "taxelkit_info": _INFO_VERSION,
            "pitch_mm": rec.pitch_mm,
            "units": rec.units,
            "sensor": rec.sensor,
            "dtype": str(rec.frames.dtype),
            "t_s": [float(t) for t in rec.t_s],
        }
    )


def encode_recording(
    rec: TactileFrames, *, topic: str = DEFAULT_TOPIC, message: str = "image"
) -> EncodedRecording:
    """Serialise a recording as frame messages on ``topic`` plus its info message.

    Parameters
    ----------
    rec : TactileFrames
        The recording.
    topic : str, optional
        Frames topic (``/name``); the info goes to ``topic + "/info"``.
    message : {"image", "multiarray"}, optional
        ``sensor_msgs/msg/Image`` (lossless for every frame dtype) or
        ``std_msgs/msg/Float32MultiArray`` (float32 values: refused for
        float64 frames, which it would round).

    Returns
    -------
    EncodedRecording
        Log times are the frame times in ns, shifted to start at >= 0 if
        ``t_s`` has negative values (bag log times are unsigned).

    Raises
    ------
    InputError
        On an unknown ``message``, a malformed ``topic``, float64 frames with
        ``"multiarray"``, or times outside the int32 seconds of a ROS stamp.
    """
    if message not in MESSAGE_KINDS:
        raise InputError(f"message must be one of {', '.join(MESSAGE_KINDS)}, got {message!r}")
    _check_topic(topic)
    msgtype = MESSAGE_KINDS[message]
    if msgtype == MULTIARRAY_MSGTYPE and rec.frames.dtype == np.float64:
        raise InputError(
            "float64 frames would be rounded to float32 in a Float32MultiArray; "
            "use the image message type (64FC1), or convert the frames to float32 first"
        )
    store = typestore()
    stamps = _stamps_ns(rec.t_s)
    shift = -min(0, stamps[0])
    info = store.types[STRING_MSGTYPE](data=info_json(rec))
    messages = [
        (topic + INFO_SUFFIX, stamps[0] + shift, bytes(store.serialize_cdr(info, STRING_MSGTYPE)))
    ]
    for k, ns in enumerate(stamps):
        msg = _image_message(rec, k, ns) if message == "image" else _multiarray_message(rec, k)
        messages.append((topic, ns + shift, bytes(store.serialize_cdr(msg, msgtype))))
    return EncodedRecording(
        connections=((topic, msgtype), (topic + INFO_SUFFIX, STRING_MSGTYPE)),
        messages=tuple(messages),
    )
