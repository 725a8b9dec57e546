"""``taxelkit simulate roll``: a simulated object rolled on the 16 x 16 Bonneville array."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import click

from taxelkit.cli.options import DURATION_S, RATE_HZ, ROLL_OBJECT, SCALE, SEED
from taxelkit.errors import InputError

__all__ = ["roll"]


@click.command("roll")
@click.option(
    "--object",
    "object_name",
    type=ROLL_OBJECT,
    default=None,
    help="A solid of paper 001 to roll, or sliding (a body dragged without rolling).",
)
@click.option(
    "--mesh",
    type=click.Path(path_type=Path),
    default=None,
    help="Or your own convex mesh (STL, OBJ, ...; kinematic engine), as for learn-object.",
)
@click.option(
    "--mesh-scale",
    type=SCALE,
    default=1.0,
    show_default=True,
    help="With --mesh: mm per mesh unit.",
)
@click.option(
    "--engine",
    type=click.Choice(["kinematic", "mujoco"]),
    default="kinematic",
    show_default=True,
    help='Pose engine: closed-form scripts, or MuJoCo physics (pip install "taxelkit[mujoco]").',
)
@click.option(
    "--rate-hz",
    type=RATE_HZ,
    default=20.0,
    show_default=True,
    help="Frame rate (mujoco: 1-1000 Hz, the same motion at every rate).",
)
@click.option(
    "--lift-gap-s",
    type=DURATION_S,
    default=0.0,
    show_default=True,
    help="Lift the body clear once mid-script for this long (mujoco only).",
)
@click.option(
    "--seed",
    type=SEED,
    default=0,
    show_default=True,
    help="Seed of the randomised script (sizes, speeds) and the noise.",
)
@click.option(
    "--handlings",
    type=click.IntRange(1, 100),
    default=1,
    show_default=True,
    help="Roll the same object this many times, lifted off between (handling k draws its "
    "script from --seed + k), into one recording: for recognize --one-object.",
)
@click.option("--contact", is_flag=True, help="Write binary contact images instead of mm.")
@click.option("--no-noise", is_flag=True, help="Noise-free frames.")
@click.option(
    "--out",
    type=click.Path(path_type=Path),
    required=True,
    help="Recording to write: .npz, .h5, .csv or .mcap (by the suffix).",
)
@click.option("--force", is_flag=True, help="Overwrite an existing output.")
def roll(
    object_name: str | None,
    mesh: Path | None,
    mesh_scale: float,
    engine: str,
    rate_hz: float,
    lift_gap_s: float,
    seed: int,
    handlings: int,
    contact: bool,
    no_noise: bool,
    out: Path,
    force: bool,
) -> None:
    """Roll a simulated object on the 16 x 16 Bonneville array (a randomised script or scene)."""
    from taxelkit.frames import TactileFrames
    from taxelkit.io.recordings import write_recording
    from taxelkit.motion.engines import scenario_from_engine
    from taxelkit.motion.rolling import frames_from_scenario
    from taxelkit.sensors.presets import BONNEVILLE_16X16

    if (object_name is None) == (mesh is None):
        raise InputError("give exactly one of --object NAME or --mesh FILE")
    if mesh is not None and engine != "kinematic":
        raise InputError("--mesh rolls with the kinematic engine only")
    name = mesh.name if mesh is not None else str(object_name)
    recs = []
    for k in range(handlings):
        if mesh is not None:
            scenario = _mesh_scenario(mesh, mesh_scale, seed + k, rate_hz)
        else:
            scenario = scenario_from_engine(
                engine, name, rng=seed + k, rate_hz=rate_hz, lift_gap_s=lift_gap_s
            )
        recs.append(
            frames_from_scenario(BONNEVILLE_16X16, scenario, rng=seed + k, add_noise=not no_noise)
        )
    rec = recs[0] if handlings == 1 else _one_after_another(recs)
    if contact:
        rec = TactileFrames(
            BONNEVILLE_16X16.contact_from_displacement(rec.frames),
            rec.t_s,
            rec.pitch_mm,
            sensor=rec.sensor,
        )
    write_recording(rec, out, force=force)
    click.echo(
        f"wrote {out} ({rec.n_frames} frames, {rec.duration_s:.1f} s, {name}, {engine}"
        + (f", {handlings} handlings)" if handlings > 1 else ")")
    )


def _mesh_scenario(mesh: Path, scale: float, seed: int, rate_hz: float) -> Any:
    """A randomised kinematic script for a convex mesh (:mod:`taxelkit.motion.mesh_scenarios`)."""
    import trimesh

    from taxelkit.motion.mesh_scenarios import make_mesh_scenario
    from taxelkit.world.mesh_features import mesh_features
    from taxelkit.world.mesh_solid import load_mesh_solid

    solid = load_mesh_solid(mesh, scale=scale)
    features = mesh_features(trimesh.Trimesh(solid.vertices_mm).convex_hull)
    return make_mesh_scenario(solid, features, name=mesh.stem, rng=seed, rate_hz=rate_hz)


def _one_after_another(recs: list[Any]) -> Any:
    """Recordings of one array back to back, each starting a frame interval after the last."""
    import numpy as np

    from taxelkit.frames import TactileFrames

    times, t0 = [], 0.0
    for r in recs:
        t = np.asarray(r.t_s) - float(r.t_s[0])
        times.append(t + t0)
        dt = float(t[1]) if t.size > 1 else 1.0 / max(r.rate_hz, 1e-9)
        t0 += float(t[-1]) + dt
    first = recs[0]
    return TactileFrames(
        np.concatenate([r.frames for r in recs]),
        np.concatenate(times),
        first.pitch_mm,
        units=first.units,
        sensor=first.sensor,
    )
