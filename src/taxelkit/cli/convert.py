"""``taxelkit convert IN OUT``: a recording from one format into another.

Formats are chosen by the path: ``.npz``, ``.h5``/``.hdf5``, ``.csv``,
``.mcap``, and a rosbag2 folder (read: a folder holding ``metadata.yaml``;
written: an OUT without an extension). Every conversion keeps frames, their
dtype, timestamps, pitch, units and sensor exactly.
"""

from __future__ import annotations

from pathlib import Path

import click

from taxelkit.cli.options import PITCH_MM
from taxelkit.errors import InputError

__all__ = ["convert"]


def _writes_rosbag2(out: Path) -> bool:
    from taxelkit.io.bags import is_rosbag2_folder

    return out.suffix == "" or is_rosbag2_folder(out)


@click.command()
@click.argument("source", metavar="IN", type=click.Path(path_type=Path))
@click.argument("out", metavar="OUT", type=click.Path(path_type=Path))
@click.option(
    "--topic",
    default=None,
    help="Frames topic of a bag or MCAP input (default: its only frames topic) "
    "and of a bag or MCAP output (default /tactile).",
)
@click.option(
    "--message",
    type=click.Choice(["image", "multiarray"]),
    default="image",
    show_default=True,
    help="Frame message type of a bag or MCAP output: sensor_msgs/Image or "
    "std_msgs/Float32MultiArray (float32 values, so not for float64 frames).",
)
@click.option(
    "--storage",
    type=click.Choice(["sqlite3", "mcap"]),
    default="sqlite3",
    show_default=True,
    help="Storage plugin of a rosbag2 folder output.",
)
@click.option(
    "--pitch-mm", type=PITCH_MM, default=None, help="Override the input's taxel pitch, mm."
)
@click.option("--force", is_flag=True, help="Overwrite an existing output.")
def convert(
    source: Path,
    out: Path,
    topic: str | None,
    message: str,
    storage: str,
    pitch_mm: float | None,
    force: bool,
) -> None:
    """Convert a recording IN to OUT: .npz, .h5, .csv, .mcap or a rosbag2 folder.

    OUT without an extension is written as a rosbag2 folder. Bags and MCAP
    files need the ros extra: pip install "taxelkit[ros]".
    """
    from taxelkit.io.atomic import atomic_write
    from taxelkit.io.bags import MCAP_SUFFIX, is_rosbag2_folder, write_mcap_file, write_rosbag2
    from taxelkit.io.recordings import read_recording, write_recording
    from taxelkit.io.ros_messages import DEFAULT_TOPIC

    source_is_bag = is_rosbag2_folder(source) or source.suffix.lower() == MCAP_SUFFIX
    rec = read_recording(source, pitch_mm=pitch_mm, topic=topic if source_is_bag else None)
    out_topic = DEFAULT_TOPIC if topic is None else topic
    if _writes_rosbag2(out):
        write_rosbag2(rec, out, topic=out_topic, message=message, storage=storage, force=force)
        kind = f"rosbag2 folder, {storage}"
    elif out.suffix.lower() == MCAP_SUFFIX:
        if message == "image":
            write_recording(rec, out, force=force, topic=out_topic)
        else:
            atomic_write(
                out,
                lambda tmp: write_mcap_file(rec, tmp, topic=out_topic, message=message),
                force=force,
            )
        kind = "MCAP"
    else:
        if topic is not None and not source_is_bag:
            raise InputError("--topic applies only to ROS 2 bags and MCAP files")
        write_recording(rec, out, force=force)
        kind = out.suffix.lower().lstrip(".")
    click.echo(f"wrote {out} ({kind}: {rec.n_frames} frames of {rec.shape[1]} x {rec.shape[2]})")
