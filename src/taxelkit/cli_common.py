"""Helpers shared by the command-line modules: argument parsing and safe output."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from taxelkit.errors import InputError

__all__ = [
    "check_figure_suffix",
    "check_outputs",
    "pair",
    "save_figure",
    "triple",
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


def pair(value: str | None, name: str) -> tuple[float, float] | None:
    if value is None:
        return None
    try:
        a, b = (float(v) for v in value.split(","))
    except ValueError:
        raise InputError(f"{name} must be two numbers X,Y, got {value!r}") from None
    if not (np.isfinite(a) and np.isfinite(b)):
        raise InputError(f"{name} must be finite, got {value!r}")
    return (a, b)


def triple(value: str, name: str) -> tuple[float, float, float]:
    try:
        a, b, c = (float(v) for v in value.split(","))
    except ValueError:
        raise InputError(f"{name} must be three numbers A,B,C, got {value!r}") from None
    return (a, b, c)


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
