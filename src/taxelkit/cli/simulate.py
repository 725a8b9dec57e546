"""``taxelkit simulate`` and ``taxelkit demo``: recordings and figures from the simulator."""

from __future__ import annotations

import time
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import click
import numpy as np
from tqdm import tqdm

from taxelkit.cli.common import save_figure, specimen_from_options
from taxelkit.cli.options import (
    ANGLE_DEG,
    COORDINATE_MM,
    EULER_DEG,
    INDENT_MM,
    RATE_HZ,
    SCALE,
    SEED,
    SENSOR,
    SOLID,
    relief_options,
)
from taxelkit.errors import InputError
from taxelkit.frames import TactileFrames

__all__ = ["demo", "simulate"]


def _write(rec: TactileFrames, out: Path, force: bool) -> None:
    from taxelkit.io.recordings import write_recording

    write_recording(rec, out, force=force)
    click.echo(
        f"wrote {out} ({rec.n_frames} frames of {rec.shape[1]} x {rec.shape[2]}, {rec.units})"
    )


_common = [
    click.option(
        "--sensor",
        "sensor_name",
        type=SENSOR,
        default=None,
        help="Sensor preset ('taxelkit sensors'; default: the command's paper's sensor).",
    ),
    click.option(
        "--frames",
        "n_frames",
        type=click.IntRange(1, 1_000_000),
        default=None,
        help="Number of frames (default 1; press with --to: 30).",
    ),
    click.option(
        "--rate-hz", type=RATE_HZ, default=None, help="Frame rate, Hz; default: the sensor's."
    ),
    click.option("--contact", is_flag=True, help="Write binary contact images instead of mm."),
    click.option("--no-noise", is_flag=True, help="Noise-free frames."),
    click.option("--seed", type=SEED, default=0, show_default=True, help="Noise seed."),
    click.option(
        "--out",
        type=click.Path(path_type=Path),
        required=True,
        help="Recording to write: .npz, .h5, .csv or .mcap (by the suffix).",
    ),
    click.option("--force", is_flag=True, help="Overwrite an existing output."),
]


F = TypeVar("F", bound=Callable[..., Any])


def _with_common(f: F) -> F:
    """Add the options shared by every ``simulate`` command."""
    for option in reversed(_common):
        f = option(f)
    return f


def _finish(
    disp: np.ndarray,
    sensor_name: str,
    rate_hz: float | None,
    contact: bool,
    out: Path,
    force: bool,
    active_only: bool = False,
) -> None:
    from taxelkit.sensors.presets import get_sensor

    sensor = get_sensor(sensor_name)
    if active_only:
        rows, cols = sensor.array.active_region.slices
        disp = disp[:, rows, cols]
    rate = sensor.max_rate_hz if rate_hz is None else rate_hz
    if not (np.isfinite(rate) and rate > 0):
        raise InputError(f"--rate-hz must be > 0, got {rate_hz!r}")
    t_s = np.arange(disp.shape[0]) / rate
    frames = sensor.contact_from_displacement(disp) if contact else disp
    _write(TactileFrames(frames, t_s, sensor.array.pitch_mm, "mm", sensor.name), out, force)


@click.group()
def simulate() -> None:
    """Produce recordings from the simulated sensors.

    Frames are skin displacements in mm (or 0/1 contact images with
    --contact) on the array's grid: taxel (row i, column j) sits at
    x = (j - (cols - 1)/2) * pitch, y = (i - (rows - 1)/2) * pitch, mm from
    the array centre, so columns run along +x and rows along +y.
    """


@simulate.command("press")
@relief_options
@click.option(
    "--at",
    "at_mm",
    type=COORDINATE_MM,
    default="0,0",
    show_default=True,
    help="Sensor centre X,Y (mm).",
)
@click.option(
    "--to", "to_mm", type=COORDINATE_MM, default=None, help="Slide the sensor to X,Y over --frames."
)
@click.option(
    "--indent-mm",
    type=INDENT_MM,
    default=0.1,
    show_default=True,
    help="How far the sensor is pressed into the plate, mm.",
)
@click.option(
    "--yaw-deg",
    type=ANGLE_DEG,
    default=0.0,
    show_default=True,
    help="Rotation of the array about the vertical, degrees counter-clockwise (0: columns "
    "along x).",
)
@click.option("--active-only", is_flag=True, help="Keep only the sensor's active block.")
@_with_common
def press(
    shape: str | None,
    specimen: Path | None,
    diameter_mm: float,
    step_height_um: float,
    rotate_deg: float,
    offset_mm: tuple[float, float],
    at_mm: tuple[float, float],
    to_mm: tuple[float, float] | None,
    indent_mm: float,
    yaw_deg: float,
    active_only: bool,
    sensor_name: str | None,
    n_frames: int | None,
    rate_hz: float | None,
    contact: bool,
    no_noise: bool,
    seed: int,
    out: Path,
    force: bool,
) -> None:
    """Press (or slide) a sensor flat on a relief specimen (paper 000)."""
    from taxelkit.sensors.presets import get_sensor
    from taxelkit.sensors.press import displacement_from_relief

    relief, _ = specimen_from_options(
        shape, specimen, rotate_deg, offset_mm, diameter_mm, step_height_um
    )
    name = sensor_name or "optical-3axis"
    sensor = get_sensor(name)
    start = np.array(at_mm)
    stop = to_mm
    n = n_frames or (1 if stop is None else 30)
    end = start if stop is None else np.array(stop)
    positions = start + np.linspace(0.0, 1.0, n)[:, None] * (end - start)
    disp = displacement_from_relief(
        sensor,
        relief,
        positions,
        indent_mm=indent_mm,
        yaw_deg=yaw_deg,
        add_noise=not no_noise,
        rng=seed,
    )
    _finish(disp, name, rate_hz, contact, out, force, active_only)


@simulate.command("solid")
@click.option(
    "--object", "object_name", type=SOLID, default=None, help="A solid of paper 001 (or --mesh)."
)
@click.option(
    "--mesh",
    type=click.Path(path_type=Path),
    default=None,
    help="Your own convex body: an STL or OBJ mesh in mm, instead of --object.",
)
@click.option(
    "--scale",
    type=SCALE,
    default=1.0,
    show_default=True,
    help="Size multiplier of the --object (1: the paper-sized default).",
)
@click.option(
    "--euler-deg",
    type=EULER_DEG,
    default="0,0,0",
    show_default=True,
    help="Body orientation RX,RY,RZ, degrees: extrinsic x-y-z, i.e. turned about the fixed "
    "x axis, then y, then z (R = Rz Ry Rx); z points out of the sensor.",
)
@click.option(
    "--at",
    "at_mm",
    type=COORDINATE_MM,
    default="0,0",
    show_default=True,
    help="Where the body's centroid sits over the array X,Y, mm from the array centre.",
)
@click.option(
    "--indent-mm",
    type=INDENT_MM,
    default=0.3,
    show_default=True,
    help="Final depth of the lowest point, mm; with --frames N > 1 a press from 0.",
)
@_with_common
def solid(
    object_name: str | None,
    mesh: Path | None,
    scale: float,
    euler_deg: tuple[float, float, float],
    at_mm: tuple[float, float],
    indent_mm: float,
    sensor_name: str | None,
    n_frames: int | None,
    rate_hz: float | None,
    contact: bool,
    no_noise: bool,
    seed: int,
    out: Path,
    force: bool,
) -> None:
    """Press a solid onto the sensor in a given pose (paper 001).

    Conventions: lengths in mm, angles in degrees. The body frame has its
    origin at the centroid (the cylinder's and cone's axis along +z); --euler-deg
    turns it about the fixed sensor axes x, then y, then z (extrinsic x-y-z,
    R = Rz Ry Rx); then the body is lowered until its lowest point is
    --indent-mm into the skin, with its centroid above --at.
    """
    from taxelkit.sensors.presets import get_sensor
    from taxelkit.sensors.press import displacement_from_solid
    from taxelkit.world.mesh_solid import load_mesh_solid
    from taxelkit.world.pose import matrix_from_euler_xyz_deg
    from taxelkit.world.solids import make_solid

    if (object_name is None) == (mesh is None):
        raise InputError("give exactly one of --object NAME or --mesh FILE")
    body = load_mesh_solid(mesh) if mesh is not None else make_solid(str(object_name), scale=scale)
    name = sensor_name or "bonneville-16x16"
    sensor = get_sensor(name)
    n = n_frames or 1
    depth = np.full(n, indent_mm) if n == 1 else np.linspace(0.0, indent_mm, n)
    rot = np.repeat(matrix_from_euler_xyz_deg(euler_deg)[None], n, 0)
    pos = np.repeat(np.array(at_mm)[None], n, 0)
    disp = displacement_from_solid(
        sensor, body, rot, pos, indent_mm=depth, add_noise=not no_noise, rng=seed
    )
    _finish(disp, name, rate_hz, contact, out, force)


@click.command()
@click.option(
    "--out",
    type=click.Path(path_type=Path),
    default=Path("demo-out"),
    show_default=True,
    help="Output folder for the figures and recordings.",
)
@click.option("--seed", type=SEED, default=0, show_default=True, help="Seed of every random draw.")
@click.option("--force", is_flag=True, help="Overwrite existing outputs.")
def demo(out: Path, seed: int, force: bool) -> None:
    """Run the main job: both papers' systems on the built-in simulated sensors, with figures."""
    from taxelkit.experiments.paper000_common import IMPROVED, reference_memory, trace_shape
    from taxelkit.experiments.paper001 import run_cylinder
    from taxelkit.experiments.simulator_demo import relief_slide, solid_presses
    from taxelkit.io.recordings import write_recording
    from taxelkit.memory.contour_recall import recall_curve
    from taxelkit.motion.rolling import frames_from_scenario
    from taxelkit.motion.scenarios import make_scenario
    from taxelkit.plotting.demo import plot_relief_slide, plot_solid_presses
    from taxelkit.plotting.paper000 import plot_trace_recall
    from taxelkit.plotting.paper001 import plot_cylinder
    from taxelkit.sensors.presets import BONNEVILLE_16X16
    from taxelkit.smart.recogniser import recognise
    from taxelkit.smart.tacteme_table import OBJECTS

    targets = {
        "relief_png": out / "demo-relief.png",
        "relief_rec": out / "demo-relief.npz",
        "solids_png": out / "demo-solids.png",
        "solids_rec": out / "demo-solids.npz",
        "trace_png": out / "demo-trace.png",
        "smart_png": out / "demo-smart.png",
        "smart_rec": out / "demo-cylinder.npz",
    }
    if not force:
        existing = [str(p) for p in targets.values() if p.exists()]
        if existing:
            raise InputError(f"{existing[0]} exists; pass --force to overwrite")
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    lines = []
    with tqdm(total=8, desc="taxelkit demo", unit="step", leave=False) as bar:
        bar.set_postfix_str("simulator: relief slide (paper 000)")
        slide = relief_slide(rng=seed)
        save_figure(plot_relief_slide(slide), targets["relief_png"], force=force)
        write_recording(slide.recording, targets["relief_rec"], force=force)
        bar.update()
        presses = solid_presses(rng=seed, progress=lambda s: bar.set_postfix_str(f"pressing {s}"))
        save_figure(plot_solid_presses(presses), targets["solids_png"], force=force)
        write_recording(presses.recording, targets["solids_rec"], force=force)
        bar.update()
        bar.set_postfix_str("paper 000: tracing the five stored specimens")
        memory = reference_memory(IMPROVED)
        bar.update(2)
        bar.set_postfix_str("paper 000: tracing an unknown specimen")
        trace = trace_shape("star", rotation_deg=23.0, offset_mm=(6.0, -4.0), seed=seed + 7)
        curve = recall_curve(trace.moves_mm, memory, phases=IMPROVED.phases)
        save_figure(
            plot_trace_recall(trace, curve, rule=IMPROVED.rule), targets["trace_png"], force=force
        )
        bar.update(2)
        bar.set_postfix_str("paper 001: the rolling cylinder of Fig. 3")
        cyl = run_cylinder(seed=seed)
        save_figure(plot_cylinder(cyl), targets["smart_png"], force=force)
        write_recording(cyl.recording, targets["smart_rec"], force=force)
        bar.update()
        rolls = []
        for k, name in enumerate(OBJECTS):
            bar.set_postfix_str(f"paper 001: rolling a {name}")
            rng = np.random.default_rng([seed, k])
            scenario = make_scenario(name, rng=rng)
            frames = frames_from_scenario(BONNEVILLE_16X16, scenario, rng=rng)
            rolls.append((name, recognise(frames).identified, frames.n_frames))
        bar.update()
    final = curve.recognised[-1]
    s0 = None if final is None else curve.recognised_from_s(final)
    lines.append(
        f"paper 000: traced a star rotated by 23 deg ({trace.n_sections} sections, "
        f"{'closed' if trace.closed else trace.stop_reason}); recognised as "
        f"{curve.verdicts[-1]!r}, top-ranked from s = {s0}"
    )
    tac = ", ".join(n for n, _ in cyl.recognition.tactemes)
    lines.append(
        f"paper 001: Fig. 3 cylinder -> tactemes {tac}; identified: {cyl.recognition.identified}"
    )
    for name, got, n in rolls:
        lines.append(f"paper 001: rolled a {name} ({n} frames at 20 Hz) -> identified: {got}")
    for p in targets.values():
        click.echo(f"wrote {p}")
    for line in lines:
        click.echo(line)
    click.echo(f"demo finished in {time.perf_counter() - t0:.1f} s")
