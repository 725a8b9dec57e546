"""Helpers shared by the command-line modules: argument parsing and safe output."""

from __future__ import annotations

import json
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from taxelkit.errors import InputError

__all__ = [
    "check_figure_suffix",
    "check_outputs",
    "progress_bar",
    "read_timings",
    "save_figure",
    "specimen_from_options",
    "write_text",
]


def save_figure(fig: Any, out: Path, *, force: bool, dpi: int = 130) -> None:
    from taxelkit.io.atomic import atomic_write

    def writer(tmp: Path) -> None:
        fig.savefig(tmp, dpi=dpi, bbox_inches="tight")

    try:
        atomic_write(out, writer, force=force)
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)


def check_figure_suffix(out: Path) -> None:
    if out.suffix.lower() not in {".png", ".pdf", ".svg", ".jpg", ".jpeg"}:
        raise InputError(f"--out must end in .png, .pdf, .svg or .jpg, got {out.name!r}")


def write_text(path: Path, text: str, force: bool) -> None:
    from taxelkit.io.atomic import atomic_write

    def writer(tmp: Path) -> None:
        tmp.write_text(text)

    atomic_write(path, writer, force=force)


def check_outputs(paths: list[Path], force: bool) -> None:
    if force:
        return
    for p in paths:
        if p.exists():
            raise InputError(f"{p} exists; pass --force to overwrite")


def specimen_from_options(
    shape: str | None,
    specimen: Path | None,
    rotate_deg: float,
    offset_mm: tuple[float, float],
    diameter_mm: float,
    step_height_um: float,
) -> tuple[Any, tuple[float, float]]:
    """The relief named by ``--shape``/``--specimen`` and the point to search its edge from.

    With ``--specimen`` the shape options given on the command line act on the
    heightmap (:class:`~taxelkit.world.placed.PlacedRelief`, no resampling):
    ``--diameter-mm`` scales it about the centroid of its raised relief so
    that the circle about that centroid holding the relief has this diameter
    (the circumscribed circle of a named shape), ``--rotate-deg`` turns it
    about that centroid, ``--offset-mm`` moves it by X,Y, and
    ``--step-height-um`` scales every height so that the highest is this
    step. Options left at their defaults leave the heightmap as it is.

    Raises
    ------
    InputError
        Unless exactly one of ``shape`` and ``specimen`` is given, or if the
        heightmap has no raised relief to size.
    """
    from taxelkit.world.base import Relief
    from taxelkit.world.relief import load_heightmap, relief_shape

    relief: Relief
    if (shape is None) == (specimen is None):
        raise InputError("give exactly one of --shape NAME or --specimen FILE.npz")
    if specimen is not None:
        return _placed_heightmap(
            load_heightmap(specimen), rotate_deg, offset_mm, diameter_mm, step_height_um
        )
    relief = relief_shape(
        str(shape),
        diameter_mm=diameter_mm,
        step_height_um=step_height_um,
        rotation_deg=rotate_deg,
        offset_mm=offset_mm,
    )
    return relief, offset_mm


def _given(name: str) -> bool:
    """Whether the option ``name`` of the running command was given (not its default)."""
    import click
    from click.core import ParameterSource

    ctx = click.get_current_context(silent=True)
    if ctx is None:
        return True  # called from Python: every value counts
    return ctx.get_parameter_source(name) not in (ParameterSource.DEFAULT, None)


def _placed_heightmap(
    heightmap: Any,
    rotate_deg: float,
    offset_mm: tuple[float, float],
    diameter_mm: float,
    step_height_um: float,
) -> tuple[Any, tuple[float, float]]:
    """A heightmap placed by the shape options given, and the centre of its raised relief."""
    from taxelkit.world.placed import PlacedRelief, raised_extent_mm

    given = {n for n in ("rotate_deg", "offset_mm", "diameter_mm", "step_height_um") if _given(n)}
    x0, x1, y0, y1 = heightmap.extent_mm
    if not given:
        return heightmap, ((x0 + x1) / 2, (y0 + y1) / 2)
    centre, diameter, peak_mm = raised_extent_mm(heightmap)
    placed = PlacedRelief(
        heightmap,
        centre_mm=centre,
        rotation_deg=rotate_deg if "rotate_deg" in given else 0.0,
        offset_mm=offset_mm if "offset_mm" in given else (0.0, 0.0),
        scale=diameter_mm / diameter if "diameter_mm" in given else 1.0,
        height_scale=step_height_um / (1000.0 * peak_mm) if "step_height_um" in given else 1.0,
    )
    return placed, placed.placed_centre_mm


@contextmanager
def progress_bar(description: str, unit: str) -> Iterator[Callable[[int, int], None]]:
    """A ``progress(done, total)`` callback that draws a bar on stderr.

    The bar opens at the first report, so it always shows a known total
    (``fig8: 3/5 shape``); a run that reports nothing draws nothing. It is
    removed when the block ends, leaving the command's own summary line.

    Parameters
    ----------
    description : str
        What runs (an experiment's name).
    unit : str
        What one step counts (``"trial"``, ``"shape"``).
    """
    from tqdm import tqdm

    bars: list[Any] = []

    def progress(done: int, total: int) -> None:
        if not bars:
            bars.append(tqdm(total=total, desc=description, unit=unit, leave=False))
        bar = bars[0]
        bar.total = total
        bar.update(done - bar.n)

    try:
        yield progress
    finally:
        for bar in bars:
            bar.close()


def read_timings(folder: Path) -> dict[str, float]:
    """Wall-clock seconds of every experiment whose NAME.timing.json is in ``folder``."""
    out = {}
    for path in sorted(folder.glob("*.timing.json")):
        try:
            doc = json.loads(path.read_text(encoding="utf-8"))
            out[str(doc["experiment"])] = float(doc["seconds"])
        except (OSError, ValueError, KeyError, TypeError):
            continue  # not ours, or damaged: the block is about the runs it can read
    return out
