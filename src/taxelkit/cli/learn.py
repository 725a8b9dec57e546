"""``taxelkit learn-object``: a new object's row of the tacteme-object table from its mesh."""

from __future__ import annotations

import re
from pathlib import Path

import click

from taxelkit.cli.options import SCALE, SEED
from taxelkit.errors import InputError

__all__ = ["learn_object"]

_NAME = re.compile(r"^[a-z0-9][a-z0-9-]{0,47}$")


@click.command("learn-object")
@click.argument("mesh", type=click.Path(path_type=Path))
@click.option("--name", required=True, help="Name of the object (lowercase letters, digits, '-').")
@click.option(
    "--out",
    "out",
    type=click.Path(path_type=Path),
    default=Path("objects.json"),
    show_default=True,
    help="User object table to add the object to (created if missing).",
)
@click.option(
    "--scale",
    type=SCALE,
    default=1.0,
    show_default=True,
    help="mm per mesh unit (1 for a mesh in mm, 1000 for one in m, 25.4 for inches).",
)
@click.option(
    "--checks",
    type=click.IntRange(0, 1000),
    default=24,
    show_default=True,
    help="Simulated rolls that check the derived row (0: no check).",
)
@click.option("--seed", type=SEED, default=0, show_default=True, help="Seed of the check.")
@click.option(
    "--hull", is_flag=True, help="Use the convex hull of a mesh that is not closed or not convex."
)
@click.option("--force", is_flag=True, help="Replace an object of the same name in --out.")
def learn_object(
    mesh: Path,
    name: str,
    out: Path,
    scale: float,
    checks: int,
    seed: int,
    hull: bool,
    force: bool,
) -> int:
    """Learn a convex object from its MESH (STL, OBJ, PLY, OFF, glTF) for `recognize --objects`.

    Derives which tactemes the object can produce from its flat faces, edges,
    vertices and curved surfaces, checks that by rolling it on the simulated
    sensor, adds it to the table file --out, and says which objects it cannot
    always be told apart from.
    """
    from taxelkit.io.atomic import atomic_write
    from taxelkit.learn.check import learn_solid
    from taxelkit.smart.object_table import ObjectTable, dumps, read_object_table
    from taxelkit.smart.tacteme_table import OBJECTS
    from taxelkit.world.mesh_solid import load_mesh_solid

    if not _NAME.match(name):
        raise InputError(f"--name must be 1-48 lowercase letters, digits or '-', got {name!r}")
    if name in OBJECTS:
        raise InputError(f"--name {name!r} is one of the six objects of paper 001")
    table = read_object_table(out) if out.exists() else ObjectTable(())
    if name in table.objects and not force:
        raise InputError(
            f"{out} already holds an object named {name!r}; pass --force to replace it"
        )
    solid = load_mesh_solid(mesh, convex_hull=hull, scale=scale)
    learnt = learn_solid(solid, name, source=mesh.name, n_check=checks, rng=seed, beside=table)
    rows = [learnt.row if r.name == name else r for r in table.rows]
    new = ObjectTable(tuple(rows) if name in table.objects else (*rows, learnt.row))

    def write(tmp: Path) -> None:
        tmp.write_text(dumps(new), encoding="utf-8")

    atomic_write(out, write, force=True)
    f = learnt.features
    click.echo(
        f"{name}: {len(f.faces)} flat face(s), {len(f.ruled)} ruled side(s), "
        f"{f.doubly_curved_mm2:.0f} mm^2 doubly curved"
    )
    for tacteme, reason in learnt.row.reasons:
        click.echo(f"  {tacteme.value:40s} {reason}")
    if checks:
        never = [t.value for t in learnt.row.tactemes if t not in learnt.seen]
        click.echo(f"check: {checks} simulated rolls; never seen: {', '.join(never) or 'none'}")
        for t in learnt.outside:
            kind = "as rare (it never names the object alone)" if t in learnt.rare else "to the row"
            click.echo(
                f"warning: {t.value} was seen in {learnt.seen[t]} roll(s) but not derived; "
                f"added {kind}"
            )
        for t in learnt.left_out:
            click.echo(
                f"warning: {t.value} was seen in {learnt.seen[t]} roll(s) but no object can "
                "produce it; such a roll ends unknown"
            )
    for o in learnt.overlaps:
        click.echo(f"cannot tell apart: {o.sentence}")
    click.echo(
        f"wrote {out} ({len(new.rows)} object(s)); use: taxelkit recognize FILE --objects {out}"
    )
    return 0
