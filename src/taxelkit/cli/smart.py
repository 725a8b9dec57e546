"""``taxelkit recognize``: the smart sensor of paper 001 on a recording or a live stream."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from taxelkit.cli.common import progress_bar
from taxelkit.cli.options import (
    PITCH_MM,
    THRESHOLD,
    TIMEOUT_S,
)
from taxelkit.cli.recognize_output import (
    echo_json_parts,
    echo_objects,
    one_object_json,
    one_object_line,
    with_objects,
)
from taxelkit.cli.view import ViewTarget, view_options, with_view
from taxelkit.errors import InputError

if TYPE_CHECKING:
    from taxelkit.smart.objects import ObjectRecogniser, ObjectRecognition
    from taxelkit.smart.recognise_chunks import ChunkRecognition

__all__ = ["recognize"]


@click.command()
@click.argument("file", type=click.Path(path_type=Path), required=False)
@click.option(
    "--threshold",
    type=THRESHOLD,
    default=None,
    help="Contact threshold for float frames (default 0.03 mm).",
)
@click.option("--pitch-mm", type=PITCH_MM, default=None, help="Override the recording's pitch.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@click.option(
    "--live",
    default=None,
    help="Read a live stream instead: serial:/dev/ttyUSB0[@baud], udp:HOST:PORT, "
    "file:PATH, or a plugin's KIND:ADDRESS (see 'taxelkit sources').",
)
@click.option(
    "--max-frames",
    type=click.IntRange(1),
    default=None,
    help="Stop a live stream after this many frames.",
)
@click.option(
    "--timeout-s",
    type=TIMEOUT_S,
    default=10.0,
    show_default=True,
    help="Stop a live stream after this long without data.",
)
@click.option(
    "--topic",
    default=None,
    help="Frames topic of a ROS 2 bag or MCAP file (default: its only frames topic).",
)
@click.option(
    "--faithful",
    is_flag=True,
    help="Paper 001's pipeline as printed: no image cleaning, no Level 2 limits, Level 3 in "
    "frames (k = 3). Default: the robust pipeline.",
)
@click.option(
    "--record",
    type=click.Path(path_type=Path),
    default=None,
    help="With --live: also append the received frames to this .h5 recording, flushed "
    "every 4096 frames (a crash loses at most those).",
)
@click.option(
    "--per-frame",
    is_flag=True,
    help="With --json: also list the class of every frame ('classes'); by default classes "
    "come as run-length 'class_segments'.",
)
@click.option(
    "--arrays",
    type=click.IntRange(1, 65536),
    default=1,
    show_default=True,
    help="With --live: the stream carries this many arrays (version 2 packets name each "
    "frame's array); each is recognised in a sensor bank and events name their array.",
)
@click.option(
    "--objects",
    "objects_file",
    type=click.Path(path_type=Path),
    default=None,
    help="A user object table (from 'taxelkit learn-object'): recognise its objects beside "
    "the six of paper 001 (face-shape tactemes on).",
)
@click.option(
    "--one-object",
    is_flag=True,
    help="Every contact in FILE is of one object, handled several times: also give Level 4's "
    "verdict over the tactemes of all its contacts ('one_object' in --json).",
)
@click.option("--force", is_flag=True, help="Overwrite existing --save-view and --record files.")
@view_options
def recognize(
    file: Path | None,
    threshold: float | None,
    pitch_mm: float | None,
    as_json: bool,
    live: str | None,
    max_frames: int | None,
    timeout_s: float,
    topic: str | None,
    faithful: bool,
    record: Path | None,
    per_frame: bool,
    arrays: int,
    objects_file: Path | None,
    one_object: bool,
    force: bool,
    view: ViewTarget,
) -> int:
    """Identify the object rolling on the sensor from a recording FILE (paper 001).

    Works on any valid recording (bool contact images or float deflections, any
    array size and pitch). The recogniser sees only the frames, their
    timestamps and the pitch. .h5 and .npz files are read a chunk at a time,
    so their size is not limited by memory or by --max-mb. With --view,
    --view-url or --save-view, the frames, contact classes, tactemes,
    candidates and verdicts are logged to rerun as they happen (docs/viewer.md).
    """
    if live is not None and objects_file is not None:
        raise InputError("--objects applies to recordings (FILE), not yet to --live streams")
    if live is not None and one_object:
        raise InputError("--one-object applies to recordings (FILE), not to --live streams")
    if live is not None:
        if file is not None:
            raise InputError("give either FILE or --live SOURCE, not both")
        from taxelkit.cli.live import recognize_live

        code: int = recognize_live(
            live,
            pitch_mm=pitch_mm,
            threshold=threshold,
            max_frames=max_frames,
            timeout_s=timeout_s,
            echo=click.echo,
            save_view=view.save_path,
            record=record,
            force=force,
            spawn_view=view.spawn,
            view_url=view.url,
            arrays=arrays,
        )
        return code
    if file is None:
        raise InputError("give a recording FILE or --live SOURCE")
    if record is not None:
        raise InputError("--record applies to --live streams; a FILE is already recorded")
    if arrays != 1:
        raise InputError("--arrays applies to --live streams")
    options: dict[str, Any] = {"threshold": threshold}
    if faithful:
        from taxelkit.smart.tactemes import PAPER_LEVEL3

        options.update(cleaning=None, limits=None, config=PAPER_LEVEL3)
    if objects_file is not None:
        options["config"] = with_objects(options.get("config"), objects_file)
    if not view.wanted and topic is None and file.suffix.lower() in (".h5", ".hdf5", ".npz"):
        result, objects = _recognise_in_chunks(file, pitch_mm, per_frame, options)
    else:
        result, objects = _recognise_whole(file, pitch_mm, topic, view, force, options)
    whole = one_object_json(objects, options.get("config")) if one_object else None
    if as_json:
        parts = result.json_parts(per_frame=per_frame) + objects.json_parts()
        echo_json_parts(parts + ([] if whole is None else [("one_object", whole)]))
        return 0
    echo_objects(objects)
    if whole is not None:
        click.echo(one_object_line(whole))
    return 0


def _recognise_in_chunks(
    file: Path, pitch_mm: float | None, per_frame: bool, options: dict[str, Any]
) -> tuple[ChunkRecognition, ObjectRecognition]:
    """Read and recognise a recording a chunk at a time (memory bounded by the chunk)."""
    from taxelkit.io.chunked_read import DEFAULT_CHUNK_FRAMES, PackedChunk, open_chunks
    from taxelkit.io.packed_chunk import unpack_rows
    from taxelkit.smart.objects import PIECE_FRAMES, ObjectRecogniser
    from taxelkit.smart.recognise_chunks import ChunkRecogniser

    with open_chunks(file, pitch_mm=pitch_mm) as opened, progress_bar(file.name, "frame") as bar:
        recogniser: ChunkRecogniser | None = None
        tracks: ObjectRecogniser | None = None
        # packed rows as stored (HDF5) go to the recogniser's cleaning as they are
        pieces = opened.packed_chunks() if opened.packed else opened.chunks()
        done, total = 0, opened.n_frames
        for chunk in pieces:
            if total > DEFAULT_CHUNK_FRAMES:  # a bar on stderr where it takes a while
                bar(done, total)
            done += chunk.n_frames
            if recogniser is None or tracks is None:
                shape = (chunk.shape[1], chunk.shape[2])
                recogniser = ChunkRecogniser(
                    shape, pitch_mm=chunk.pitch_mm, per_frame=per_frame, **options
                )
                tracks = ObjectRecogniser(shape, pitch_mm=chunk.pitch_mm, **options)
            if isinstance(chunk, PackedChunk):
                recogniser.push_packed(chunk.rows, chunk.t_s)
                step = PIECE_FRAMES  # unpacked a piece at a time, as the tracker works
                for a in range(0, chunk.n_frames, step):
                    rows = chunk.rows[a : a + step]
                    tracks.push(unpack_rows(rows, chunk.cols), chunk.t_s[a : a + step])
            else:
                recogniser.push(chunk.frames, chunk.t_s)
                tracks.push(chunk.frames, chunk.t_s)
    assert recogniser is not None and tracks is not None  # open_chunks refuses zero frames
    return recogniser.result(), tracks.result()


def _recognise_whole(
    file: Path,
    pitch_mm: float | None,
    topic: str | None,
    view: ViewTarget,
    force: bool,
    options: dict[str, Any],
) -> tuple[ChunkRecognition, ObjectRecognition]:
    """Read a whole recording (bags, CSV, a rerun view) and recognise it in memory."""
    from taxelkit.io.recordings import read_recording
    from taxelkit.smart.objects import recognise_objects
    from taxelkit.smart.recognise_chunks import ChunkRecognition, class_segments
    from taxelkit.smart.recogniser import recognise

    rec = read_recording(file, pitch_mm=pitch_mm, topic=topic)
    result = recognise(rec, **options)
    if view.wanted:
        from taxelkit.viewer.rerun_view import view_recognition

        def log(where: ViewTarget) -> int:
            return view_recognition(
                rec, result, save_path=where.save_path, spawn=where.spawn, connect_url=where.url
            )

        with_view(view, log, force=force)
    return ChunkRecognition(
        class_segments(result.classes, rec.t_s),
        result.tactemes,
        result.events,
        result.identified,
        result.candidates,
        result.verdict,
        result.classes,
        result.slips,
    ), recognise_objects(rec, **options)
