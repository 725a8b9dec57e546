"""The ``taxelkit`` command line: the only layer that prints or writes files for the user.

Every error a user can cause ends as one line on stderr and exit code 2.
Outputs are written to a temporary file and renamed into place; an existing
output is kept unless ``--force`` is given.
"""

from __future__ import annotations

import json
import logging
import math
import sys
import warnings
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import click
import numpy as np

from taxelkit._version import __version__
from taxelkit.cli.common import (
    check_figure_suffix,
    save_figure,
)
from taxelkit.cli.options import MAX_MB, PITCH_MM, THRESHOLD
from taxelkit.cli.view import ViewTarget, view_options, with_view
from taxelkit.errors import InputError, TaxelkitError
from taxelkit.frames import TactileFrames
from taxelkit.io._raw import describe_exception, one_line
from taxelkit.io.limits import DEFAULT_MAX_MB, MAX_MB_ENV, read_limit

EXIT_BAD_INPUT = 2
_TOPIC_HELP = "Frames topic of a ROS 2 bag or MCAP file (default: its only frames topic)."

logger = logging.getLogger("taxelkit")


# ----------------------------------------------------------------------------- helpers
def _summary(rec: TactileFrames, path: Path) -> dict[str, Any]:
    frames = rec.frames
    out: dict[str, Any] = {
        "file": str(path),
        "sensor": rec.sensor,
        "frames": rec.n_frames,
        "rows": rec.shape[1],
        "cols": rec.shape[2],
        "pitch_mm": rec.pitch_mm,
        "units": rec.units,
        "dtype": str(frames.dtype),
        "duration_s": rec.duration_s,
        "rate_hz": rec.rate_hz,
    }
    if rec.is_contact:
        out["contact_fraction"] = float(frames.mean())
        out["min"], out["max"] = int(frames.min()), int(frames.max())
    else:
        out["min"], out["max"] = float(frames.min()), float(frames.max())
    return out


_CHUNKED_SUFFIXES = (".h5", ".hdf5", ".npz")


def _chunked_summary(path: Path, pitch_mm: float | None) -> dict[str, Any]:
    """:func:`_summary` of a recording read a chunk at a time (memory bounded by the chunk)."""
    from taxelkit.io.chunked_read import open_chunks

    total, n, lo, hi = 0.0, 0, math.inf, -math.inf
    first: TactileFrames | None = None
    t_first = t_last = 0.0
    with open_chunks(path, pitch_mm=pitch_mm) as opened:
        for chunk in opened.chunks():
            if first is None:
                first, t_first = chunk, float(chunk.t_s[0])
            t_last = float(chunk.t_s[-1])
            total += float(np.count_nonzero(chunk.frames)) if chunk.is_contact else 0.0
            lo, hi = min(lo, float(chunk.frames.min())), max(hi, float(chunk.frames.max()))
            n += chunk.n_frames
    assert first is not None  # open_chunks refuses zero frames
    duration = t_last - t_first if n > 1 else 0.0
    out: dict[str, Any] = {
        "file": str(path),
        "sensor": first.sensor,
        "frames": n,
        "rows": first.shape[1],
        "cols": first.shape[2],
        "pitch_mm": first.pitch_mm,
        "units": first.units,
        "dtype": str(first.frames.dtype),
        "duration_s": duration,
        "rate_hz": (n - 1) / duration if n > 1 else None,
    }
    if first.is_contact:
        out["contact_fraction"] = total / (n * first.shape[1] * first.shape[2])
        out["min"], out["max"] = int(lo), int(hi)
    else:
        out["min"], out["max"] = lo, hi
    return out


# ----------------------------------------------------------------------------- commands
@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="taxelkit")
@click.option("-v", "--verbose", is_flag=True, help="Log diagnostics to stderr.")
@click.option(
    "--max-mb",
    type=MAX_MB,
    default=None,
    envvar=MAX_MB_ENV,
    help=f"Read limit per input file, MiB (default {DEFAULT_MAX_MB:g}; env {MAX_MB_ENV}). "
    "Files, and arrays they declare, beyond it are refused before reading (docs/security.md).",
)
@click.pass_context
def cli(ctx: click.Context, verbose: bool, max_mb: float | None) -> None:
    """taxelkit: sense and recognise shapes by touch with array tactile sensors.

    Simulate tactile arrays, read and inspect recordings, and run the
    recognition systems of the two reference papers.
    """
    if max_mb is not None:
        ctx.with_resource(read_limit(max_mb))
    if verbose:
        logging.basicConfig(level=logging.INFO, format="%(name)s: %(message)s")


@cli.command()
@click.argument("file", type=click.Path(path_type=Path, dir_okay=True))
@click.option(
    "--pitch-mm", type=PITCH_MM, default=None, help="Override the file's taxel pitch, mm."
)
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@click.option("--topic", default=None, help=_TOPIC_HELP)
def info(file: Path, pitch_mm: float | None, as_json: bool, topic: str | None) -> None:
    """Summarise a recording FILE (.npz, .h5, .csv, .mcap, rosbag2): frames, shape, rate, values.

    .h5 and .npz files are read a chunk at a time, whatever their size.
    """
    from taxelkit.io.recordings import read_recording

    if topic is None and file.suffix.lower() in _CHUNKED_SUFFIXES:
        s = _chunked_summary(file, pitch_mm)
    else:
        s = _summary(read_recording(file, pitch_mm=pitch_mm, topic=topic), file)
    if as_json:
        click.echo(json.dumps(s))
        return
    rate = f"{s['rate_hz']:.4g} Hz" if s["rate_hz"] is not None else "n/a (one frame)"
    click.echo(f"file      {file}")
    click.echo(f"sensor    {s['sensor']}")
    click.echo(f"frames    {s['frames']} x {s['rows']} x {s['cols']} ({s['dtype']}, {s['units']})")
    click.echo(f"pitch     {s['pitch_mm']:.6g} mm")
    click.echo(f"duration  {s['duration_s']:.6g} s at {rate}")
    if "contact_fraction" in s:
        click.echo(f"contact   {100 * s['contact_fraction']:.2f} % of taxel-frames")
    else:
        click.echo(f"values    {s['min']:.6g} .. {s['max']:.6g} {s['units']}")


@cli.command()
@click.argument("file", type=click.Path(path_type=Path))
@click.option(
    "--out",
    type=click.Path(path_type=Path),
    default=None,
    help="Image file (.png, .pdf, .svg, .jpg); needed unless the frames go to rerun.",
)
@click.option(
    "--max-frames",
    type=click.IntRange(1, 200),
    default=12,
    show_default=True,
    help="Most frames in the strip, evenly spaced over --start..--stop.",
)
@click.option("--start", type=click.IntRange(0), default=0, help="First frame to consider.")
@click.option("--stop", type=click.IntRange(1), default=None, help="One past the last frame.")
@click.option("--threshold", type=THRESHOLD, default=None, help="Draw contact images frames > T.")
@click.option("--force", is_flag=True, help="Overwrite an existing output.")
@click.option("--topic", default=None, help=_TOPIC_HELP)
@view_options
def show(
    file: Path,
    out: Path | None,
    max_frames: int,
    start: int,
    stop: int | None,
    threshold: float | None,
    force: bool,
    topic: str | None,
    view: ViewTarget,
) -> None:
    """Draw frames of a recording FILE as an image strip, or send them to rerun.

    With --view, --view-url or --save-view every frame from --start to --stop
    is logged to rerun (sensor/frames, on the frame and time timelines). For
    the strip alone, .h5 and .npz files are read at the drawn frames only.
    """
    from taxelkit.io.chunked_read import open_chunks
    from taxelkit.io.recordings import read_recording
    from taxelkit.plotting.strip import frame_indices_for_strip, plot_frame_strip

    if out is None and not view.wanted:
        raise InputError("give --out IMAGE, or --view / --view-url / --save-view FILE.rrd")
    if out is not None:
        check_figure_suffix(out)
    if not view.wanted and topic is None and file.suffix.lower() in _CHUNKED_SUFFIXES:
        with open_chunks(file) as opened:
            stop = opened.n_frames if stop is None else min(stop, opened.n_frames)
            if start >= stop:
                raise InputError(f"--start ({start}) must be below the number of frames ({stop})")
            idx = start + frame_indices_for_strip(stop - start, max_frames)
            rec = opened.frames_at(idx.tolist())
        if threshold is not None:
            rec = TactileFrames(rec.contact(threshold), rec.t_s, rec.pitch_mm, sensor=rec.sensor)
        labels = [f"#{i}  {t:.3g} s" for i, t in zip(idx.tolist(), rec.t_s.tolist(), strict=True)]
        fig = plot_frame_strip(rec, labels=labels, title=f"{file.name} ({rec.sensor})")
        assert out is not None
        save_figure(fig, out, force=force)
        click.echo(f"wrote {out}")
        return
    rec = read_recording(file, topic=topic)
    stop = rec.n_frames if stop is None else min(stop, rec.n_frames)
    if start >= stop:
        raise InputError(f"--start ({start}) must be below the number of frames ({stop})")
    if threshold is not None:
        rec = TactileFrames(rec.contact(threshold), rec.t_s, rec.pitch_mm, sensor=rec.sensor)
    if view.wanted:
        from taxelkit.viewer.rerun_view import view_frames

        def log(where: ViewTarget) -> int:
            return view_frames(
                rec,
                start=start,
                stop=stop,
                save_path=where.save_path,
                spawn=where.spawn,
                connect_url=where.url,
            )

        n = with_view(view, log, force=force)
        click.echo(f"logged {n} frames to {view.save_path or view.url or 'the rerun viewer'}")
    if out is None:
        return
    idx = start + frame_indices_for_strip(stop - start, max_frames)
    fig = plot_frame_strip(rec, indices=idx, title=f"{file.name} ({rec.sensor})")
    save_figure(fig, out, force=force)
    click.echo(f"wrote {out}")


@cli.command()
def sensors() -> None:
    """List the sensor presets."""
    from taxelkit.sensors.presets import SENSORS

    for name, s in SENSORS.items():
        a = s.array
        click.echo(
            f"{name:18s} {a.rows} x {a.cols} at {a.pitch_mm:.4g} mm, "
            f"max {s.max_rate_hz:g} Hz  {s.description}"
        )


from taxelkit.cli.convert import convert  # noqa: E402  (sub-commands)
from taxelkit.cli.learn import learn_object  # noqa: E402
from taxelkit.cli.paper000 import memorise, trace  # noqa: E402
from taxelkit.cli.reproduce import reproduce  # noqa: E402
from taxelkit.cli.simulate import demo, simulate  # noqa: E402
from taxelkit.cli.simulate_roll import roll  # noqa: E402
from taxelkit.cli.smart import recognize  # noqa: E402
from taxelkit.cli.sources import sources  # noqa: E402

simulate.add_command(roll)
for _command in (
    simulate,
    demo,
    reproduce,
    trace,
    memorise,
    recognize,
    convert,
    sources,
    learn_object,
):
    cli.add_command(_command)


# ----------------------------------------------------------------------------- entry point
def run(argv: Sequence[str] | None = None, *, echo_err: Callable[[str], None] | None = None) -> int:
    """Run the CLI and return the exit code instead of exiting.

    Parameters
    ----------
    argv : sequence of str, optional
        Arguments (default: ``sys.argv[1:]``).
    echo_err : callable, optional
        Where one-line error messages go (default: stderr).

    Returns
    -------
    int
        0 on success, 2 on bad input, 1 on an unexpected internal error.
    """

    def err(msg: str) -> None:
        (echo_err or (lambda m: click.echo(m, err=True)))(msg)

    try:
        # Numerical trouble (overflow, invalid values) is an error, never a
        # warning printed before one: numpy raises FloatingPointError and any
        # RuntimeWarning becomes an exception, both reported in one line.
        with np.errstate(divide="raise", over="raise", invalid="raise"), warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)
            result = cli.main(args=list(argv) if argv is not None else None, standalone_mode=False)
    except click.exceptions.Exit as e:
        return int(e.exit_code)
    except click.exceptions.Abort as e:
        if isinstance(e.__cause__, EOFError):  # click turns an EOFError into Abort
            err(f"taxelkit: error: unexpected end of input ({describe_exception(e.__cause__)})")
            return EXIT_BAD_INPUT
        err("taxelkit: aborted")
        return 130
    except click.ClickException as e:
        err(f"taxelkit: error: {one_line(e.format_message())} (see --help)")
        return EXIT_BAD_INPUT if isinstance(e, click.UsageError) else e.exit_code
    except TaxelkitError as e:
        err(f"taxelkit: error: {one_line(str(e))}")
        return EXIT_BAD_INPUT
    except (FloatingPointError, RuntimeWarning) as e:
        err(
            f"taxelkit: error: numerical overflow or invalid value ({describe_exception(e)}); "
            "check that the inputs are in range"
        )
        return EXIT_BAD_INPUT
    except MemoryError:
        err(
            "taxelkit: error: not enough memory for this input; "
            "use smaller inputs or a lower --max-mb"
        )
        return EXIT_BAD_INPUT
    except OSError as e:  # unreadable input or unwritable output
        where = f": {e.filename}" if getattr(e, "filename", None) else ""
        err(f"taxelkit: error: {one_line(str(e.strerror or e))}{where}")
        return EXIT_BAD_INPUT
    return int(result) if isinstance(result, int) else 0


def main() -> None:
    """Console-script entry point."""
    sys.exit(run())
