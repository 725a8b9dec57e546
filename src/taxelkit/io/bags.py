"""ROS 2 bags (rosbag2 folders) and MCAP files as recordings.

Reading goes through :func:`taxelkit.io.recordings.read_recording`, which
hands a rosbag2 folder (one holding ``metadata.yaml``) or an ``.mcap`` file to
:func:`raw_from_rosbag2` or :func:`raw_from_mcap`. Writing an ``.mcap`` file
goes through :func:`~taxelkit.io.recordings.write_recording`; a rosbag2
folder is written by :func:`write_rosbag2`. The message layout is described in
:mod:`taxelkit.io.ros_messages` and ``docs/recording-format.md``.

rosbags and mcap are optional (``pip install "taxelkit[ros]"``) and imported
only when a bag is read or written.
"""

from __future__ import annotations

import contextlib
import os
import secrets
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any, Literal

from taxelkit.errors import (
    CorruptRecordingError,
    EmptyRecordingError,
    InputError,
    OutputExistsError,
    OutputWriteError,
    TaxelkitError,
    UnsafeFileError,
)
from taxelkit.frames import TactileFrames
from taxelkit.io._raw import RawRecording, describe_exception, fail
from taxelkit.io.limits import ReadBudget
from taxelkit.io.ros_encode import encode_recording
from taxelkit.io.ros_messages import (
    DEFAULT_TOPIC,
    BagDependencyError,
    raw_from_messages,
    select_topic,
    typestore,
)

__all__ = [
    "BAG_METADATA",
    "MCAP_SUFFIX",
    "ROSBAG2_STORAGES",
    "is_rosbag2_folder",
    "raw_from_mcap",
    "raw_from_rosbag2",
    "write_mcap_file",
    "write_rosbag2",
]

#: The file that makes a folder a rosbag2 bag.
BAG_METADATA = "metadata.yaml"
#: Extension of MCAP files (matched case-insensitively).
MCAP_SUFFIX = ".mcap"
#: Storage plugins a rosbag2 folder can be written with.
ROSBAG2_STORAGES = ("sqlite3", "mcap")
#: rosbag2 format version written (read: every version rosbags reads).
_ROSBAG2_VERSION: Literal[8, 9] = 9
_SCHEMA_ENCODING = "ros2msg"
_MESSAGE_ENCODING = "cdr"
_INSTALL_HINT = 'pip install "taxelkit[ros]"'


def is_rosbag2_folder(path: Path) -> bool:
    """True if ``path`` is a folder holding a rosbag2 ``metadata.yaml``."""
    return path.is_dir() and (path / BAG_METADATA).is_file()


def _import_error() -> BagDependencyError:
    return BagDependencyError(f"ROS 2 bags and MCAP files need rosbags and mcap: {_INSTALL_HINT}")


# ----------------------------------------------------------------------------- rosbag2
def _check_folder_size(path: Path) -> None:
    """Refuse a bag folder whose files together exceed the read limit.

    Only regular files directly in the folder count; a symbolic link is refused,
    so the bag cannot make taxelkit read a file elsewhere.
    """
    budget = ReadBudget(path)
    total = 0
    for entry in path.iterdir():
        if entry.is_symlink():
            raise fail(
                UnsafeFileError, path, f"{entry.name!r} is a symbolic link; bag files must be files"
            )
        if entry.is_file():
            total += entry.stat().st_size
    budget.check_file_size(total)


def raw_from_rosbag2(path: Path, *, topic: str | None = None) -> RawRecording:
    """Raw recording fields from the frames topic of a rosbag2 folder.

    Parameters
    ----------
    path : pathlib.Path
        The bag folder (sqlite3 or mcap storage, any compression rosbags reads).
    topic : str, optional
        Frames topic; default the bag's only ``Image``/``Float32MultiArray`` topic.

    Returns
    -------
    RawRecording
        For :func:`taxelkit.io.recordings.read_recording` to validate.

    Raises
    ------
    BagDependencyError
        If rosbags is not installed.
    BagTopicError
        If the topic is missing, ambiguous or of another type (the message lists the topics).
    CorruptRecordingError
        If rosbags cannot open or read the bag, or a message is malformed.
    EmptyRecordingError
        If the topic has no messages.
    """
    typestore()  # a clear error before anything else when rosbags is missing
    _check_folder_size(path)
    try:
        from rosbags.rosbag2 import Reader
    except ImportError:
        raise _import_error() from None
    with _unreadable_as_corrupt(path, "rosbag2 bag"), Reader(path) as reader:
        topics = {c.topic: c.msgtype for c in reader.connections}
        chosen = select_topic(path, topics, topic)
        wanted = [c for c in reader.connections if c.topic in (chosen, chosen + "/info")]
        stream = ((c.topic, t, bytes(data)) for c, t, data in reader.messages(wanted))
        return raw_from_messages(path, topics, stream, chosen)


@contextlib.contextmanager
def _unreadable_as_corrupt(path: Path, what: str) -> Iterator[None]:
    """Any error but taxelkit's own, raised inside, as :class:`CorruptRecordingError`."""
    try:
        yield
    except TaxelkitError:
        raise
    except Exception as exc:
        raise fail(
            CorruptRecordingError, path, f"unreadable {what} ({describe_exception(exc)})"
        ) from exc


def _temp_folder_for(target: Path) -> Path:
    """A free hidden name beside ``target`` (rosbags creates the folder itself)."""
    for _ in range(100):
        tmp = target.with_name(f".{target.name}.tmp-{secrets.token_hex(4)}")
        if not os.path.lexists(tmp):
            return tmp
    raise OutputWriteError(f"{target}: no free temporary folder name")


def write_rosbag2(
    rec: TactileFrames,
    path: str | os.PathLike[str],
    *,
    topic: str = DEFAULT_TOPIC,
    message: str = "image",
    storage: str = "sqlite3",
    force: bool = False,
) -> Path:
    """Write a recording as a rosbag2 folder (through a temporary folder, then a rename).

    Parameters
    ----------
    rec : TactileFrames
        The recording.
    path : str or os.PathLike
        The bag folder to create. Its parent must exist.
    topic : str, optional
        Frames topic; the info message goes to ``topic + "/info"``.
    message : {"image", "multiarray"}, optional
        Frame message type (see :func:`taxelkit.io.ros_encode.encode_recording`).
    storage : {"sqlite3", "mcap"}, optional
        rosbag2 storage plugin.
    force : bool, optional
        Replace an existing bag folder (a folder without ``metadata.yaml`` is never removed).

    Returns
    -------
    pathlib.Path
        The bag folder; :func:`~taxelkit.io.recordings.read_recording` of it
        ``equals`` ``rec``.

    Raises
    ------
    BagDependencyError
        If rosbags is not installed.
    InputError
        On a bad ``topic``, ``message`` or ``storage``, or frames the message type cannot hold.
    OutputExistsError
        If ``path`` exists and ``force`` is false, or is not a bag folder.
    OutputWriteError
        If the parent folder is missing or the system refuses the write.
    """
    target = Path(path)
    if storage not in ROSBAG2_STORAGES:
        raise InputError(f"storage must be one of {', '.join(ROSBAG2_STORAGES)}, got {storage!r}")
    if rec.n_frames == 0:
        raise fail(EmptyRecordingError, target, "refusing to write a recording with zero frames")
    encoded = encode_recording(rec, topic=topic, message=message)
    try:
        from rosbags.rosbag2 import StoragePlugin, Writer
    except ImportError:
        raise _import_error() from None
    if os.path.lexists(target):
        if not force:
            raise OutputExistsError(f"{target}: exists; pass --force to overwrite")
        if not is_rosbag2_folder(target):
            raise OutputExistsError(
                f"{target}: exists and is not a rosbag2 folder; refusing to replace it"
            )
    if not target.parent.is_dir():
        raise OutputWriteError(f"{target}: folder {str(target.parent)!r} does not exist")
    tmp = _temp_folder_for(target)
    plugin = StoragePlugin.MCAP if storage == "mcap" else StoragePlugin.SQLITE3
    store = typestore()
    try:
        with Writer(tmp, version=_ROSBAG2_VERSION, storage_plugin=plugin) as writer:
            connections = {
                name: writer.add_connection(name, msgtype, typestore=store)
                for name, msgtype in encoded.connections
            }
            for name, log_ns, data in encoded.messages:
                writer.write(connections[name], log_ns, data)
        _publish_folder(tmp, target)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            shutil.rmtree(tmp)
        if isinstance(exc, TaxelkitError) or not isinstance(exc, Exception):
            raise
        raise OutputWriteError(f"{target}: cannot write ({describe_exception(exc)})") from exc
    return target


def _publish_folder(tmp: Path, target: Path) -> None:
    """Move the finished bag folder into place, replacing an old bag (checked by the caller)."""
    if os.path.lexists(target):
        old = _temp_folder_for(target)
        os.rename(target, old)
        os.rename(tmp, target)
        shutil.rmtree(old, ignore_errors=True)
    else:
        os.rename(tmp, target)


# ----------------------------------------------------------------------------- MCAP
def raw_from_mcap(path: Path, *, topic: str | None = None) -> RawRecording:
    """Raw recording fields from the frames topic of an ``.mcap`` file (ROS 2 CDR messages).

    Parameters
    ----------
    path : pathlib.Path
        The file.
    topic : str, optional
        Frames topic; default the file's only ``Image``/``Float32MultiArray`` topic.

    Returns
    -------
    RawRecording

    Raises
    ------
    BagDependencyError
        If mcap or rosbags is not installed.
    BagTopicError
        If the topic is missing, ambiguous, of another type, or not CDR-encoded.
    CorruptRecordingError
        If the file is not a readable MCAP file or a message is malformed.
    EmptyRecordingError
        If the topic has no messages.
    """
    typestore()
    try:
        from mcap.reader import make_reader
    except ImportError:
        raise _import_error() from None
    with _unreadable_as_corrupt(path, "MCAP file"), path.open("rb") as fh:
        reader = make_reader(fh)
        summary = reader.get_summary()
        if summary is None:
            raise fail(CorruptRecordingError, path, "MCAP file without a summary section")
        # A compressed chunk is inflated whole: check its declared size first.
        budget = ReadBudget(path)
        for index in summary.chunk_indexes:
            budget.check_block("an MCAP chunk", int(index.uncompressed_size))
        topics = _mcap_topics(path, summary)
        chosen = select_topic(path, topics, topic)
        stream = (
            (channel.topic, int(msg.log_time), bytes(msg.data))
            for _, channel, msg in reader.iter_messages(topics=[chosen, chosen + "/info"])
        )
        return raw_from_messages(path, topics, stream, chosen)


def _mcap_topics(path: Path, summary: Any) -> dict[str, str]:
    """Topic -> message type of the CDR channels; other encodings are named as such."""
    topics: dict[str, str] = {}
    for channel in summary.channels.values():
        schema = summary.schemas.get(channel.schema_id)
        if channel.message_encoding != _MESSAGE_ENCODING or schema is None:
            topics[channel.topic] = f"{channel.message_encoding or 'no'}-encoded messages"
        else:
            topics[channel.topic] = str(schema.name)
    del path
    return topics


def write_mcap_file(
    rec: TactileFrames, path: Path, *, topic: str = DEFAULT_TOPIC, message: str = "image"
) -> None:
    """Write ``rec`` to a new ``.mcap`` file at ``path`` (ROS 2 profile, CDR messages).

    Parameters
    ----------
    rec : TactileFrames
        The recording.
    path : pathlib.Path
        Output file; :func:`~taxelkit.io.recordings.write_recording` passes a
        temporary file it then renames.
    topic : str, optional
        Frames topic.
    message : {"image", "multiarray"}, optional
        Frame message type.

    Raises
    ------
    BagDependencyError
        If mcap or rosbags is not installed.
    InputError
        On a bad ``topic`` or ``message``, or frames the message type cannot hold.
    """
    encoded = encode_recording(rec, topic=topic, message=message)
    try:
        from mcap.writer import CompressionType, Writer
    except ImportError:
        raise _import_error() from None
    store = typestore()
    with path.open("wb") as fh:
        writer = Writer(fh, compression=CompressionType.ZSTD)
        writer.start(profile="ros2", library="taxelkit")
        channels: dict[str, int] = {}
        for name, msgtype in encoded.connections:
            msgdef, _ = store.generate_msgdef(msgtype, ros_version=2)
            schema_id = writer.register_schema(
                name=msgtype, encoding=_SCHEMA_ENCODING, data=msgdef.encode("utf-8")
            )
            channels[name] = writer.register_channel(
                topic=name, message_encoding=_MESSAGE_ENCODING, schema_id=schema_id
            )
        for sequence, (name, log_ns, data) in enumerate(encoded.messages):
            writer.add_message(
                channels[name], log_time=log_ns, data=data, publish_time=log_ns, sequence=sequence
            )
        writer.finish()  # type: ignore[no-untyped-call]
