"""``taxelkit reproduce``: run registered experiments, write their results, refresh the README."""

from __future__ import annotations

import json
import time
from pathlib import Path
from typing import Any

import click

from taxelkit.cli.common import check_outputs, progress_bar, read_timings, save_figure, write_text
from taxelkit.cli.options import EXPERIMENT, SEED
from taxelkit.errors import InputError
from taxelkit.experiments.registry import EXPERIMENTS

__all__ = ["reproduce"]


def _experiment_list() -> str:
    """The epilog of ``reproduce --help``: every experiment, one line each (unwrapped)."""
    width = max(len(n) for n in EXPERIMENTS) + 2
    rows = [f"  {e.name:{width}s}{e.title}" for e in EXPERIMENTS.values()]
    rows.append(f"  {'all':{width}s}every experiment above, in this order")
    return "\b\nNAME is one of:\n" + "\n".join(rows)


def _trials_help() -> str:
    takes = [e for e in EXPERIMENTS.values() if e.trials is not None]
    defaults = ", ".join(f"{e.name} {e.trials}" for e in takes)
    return (
        "Randomised trials per shape or object (robustness: per cell). Default: each "
        f"experiment's own ({defaults}); a value given is used as given."
    )


def _taking(what: str) -> set[str]:
    """Names of the experiments that take ``trials``, ``workers`` or ``scheduler``."""
    return {e.name for e in EXPERIMENTS.values() if getattr(e, what) not in (None, False)}


def _check_applies(option: str, given: bool, names: list[str], takes: set[str]) -> None:
    """Refuse an option that no experiment being run would use, instead of ignoring it."""
    if given and not takes.intersection(names):
        raise InputError(
            f"{option} applies only to {', '.join(n for n in EXPERIMENTS if n in takes)}; "
            f"{', '.join(names)} takes none"
        )


@click.command(epilog=_experiment_list())
@click.argument("name", type=EXPERIMENT, metavar="NAME")
@click.option(
    "--out",
    type=click.Path(path_type=Path),
    required=True,
    help="Output folder for NAME.json, NAME.png and NAME.timing.json (created if missing).",
)
@click.option("--seed", type=SEED, default=0, show_default=True, help="Seed of every random draw.")
@click.option("--trials", type=click.IntRange(1), default=None, help=_trials_help())
@click.option(
    "--workers",
    type=click.IntRange(1),
    default=None,
    help="Worker processes for the experiments that run trials (default: up to 4, the CPUs).",
)
@click.option(
    "--scheduler",
    default=None,
    metavar="tcp://HOST:PORT",
    help="Run the sweeps that take it (robustness, multi-object, capacity) on this Dask "
    "scheduler (needs taxelkit[dask]).",
)
@click.option(
    "--readme",
    type=click.Path(path_type=Path, dir_okay=False, exists=True),
    default=None,
    help="Also rewrite this README's <!-- results:NAME --> blocks from the new results.",
)
@click.option("--force", is_flag=True, help="Overwrite existing outputs.")
def reproduce(
    name: str,
    out: Path,
    seed: int,
    trials: int | None,
    workers: int | None,
    scheduler: str | None,
    readme: Path | None,
    force: bool,
) -> None:
    """Run a registered experiment NAME (or 'all'): writes OUT/NAME.json and OUT/NAME.png.

    NAME.json holds only results, so the same seed gives byte-identical JSON on
    the same machine and libraries; the wall-clock time and what it ran on
    (versions, CPU, BLAS kernels) go to OUT/NAME.timing.json, which comparisons
    ignore.
    A progress bar on stderr counts each experiment's trials, traces or stages.
    """
    from taxelkit.experiments.run_environment import run_environment
    from taxelkit.plotting.experiments import plot_experiment

    names = list(EXPERIMENTS) if name == "all" else [name]
    _check_applies("--trials", trials is not None, names, _taking("trials"))
    _check_applies("--workers", workers is not None, names, _taking("workers"))
    _check_applies("--scheduler", scheduler is not None, names, _taking("scheduler"))
    exts = (".json", ".png", ".timing.json")
    check_outputs([out / f"{n}{ext}" for n in names for ext in exts], force)
    out.mkdir(parents=True, exist_ok=True)
    env = run_environment()  # this machine's (with --scheduler the workers may differ)
    t_all = time.perf_counter()
    docs: dict[str, dict[str, Any]] = {}
    for k, n in enumerate(names):
        exp = EXPERIMENTS[n]
        kwargs: dict[str, Any] = {"seed": seed}
        if exp.trials is not None:
            kwargs["n_trials"] = exp.trials if trials is None else trials
        if exp.workers:
            kwargs["workers"] = workers
        if exp.scheduler:
            kwargs["scheduler"] = scheduler
        label = n if len(names) == 1 else f"{n} ({k + 1}/{len(names)})"
        t0 = time.perf_counter()
        with progress_bar(label, exp.unit) as progress:
            result = exp.run(progress=progress, **kwargs)
        seconds = round(time.perf_counter() - t0, 2)
        doc = result.to_json()
        doc["seed"] = seed
        write_text(out / f"{n}.json", json.dumps(doc, indent=2) + "\n", force)
        timing = {"experiment": n, "seed": seed, "seconds": seconds, "environment": env}
        write_text(out / f"{n}.timing.json", json.dumps(timing, indent=2) + "\n", force)
        save_figure(plot_experiment(n, result), out / f"{n}.png", force=force)
        click.echo(f"{n}: wrote {out / n}.json, .timing.json and .png in {seconds:.1f} s")
        docs[n] = doc
    if readme is not None:
        from taxelkit.experiments.readme_tables import update_timings
        from taxelkit.experiments.report import update_blocks

        before = readme.read_text(encoding="utf-8")
        docs = _with_companions(docs, out)
        after = update_timings(update_blocks(before, docs), read_timings(out))
        if after != before:
            write_text(readme, after, True)  # the README is rewritten in place by request
        click.echo(f"{readme}: results blocks {'rewritten' if after != before else 'unchanged'}")
    if len(names) > 1:
        click.echo(f"all done in {time.perf_counter() - t_all:.1f} s")


def _with_companions(docs: dict[str, Any], out: Path) -> dict[str, Any]:
    """``docs`` plus the results in ``out`` that a README block needs beside one just run.

    A block such as ``robustness-heldout`` renders two experiments side by
    side; running one of them rewrites the block from the other's committed
    ``out/NAME.json``.
    """
    from taxelkit.experiments.report import BLOCKS

    full = dict(docs)
    for needs, _ in BLOCKS.values():
        if any(n in docs for n in needs):
            for n in needs:
                path = out / f"{n}.json"
                if n not in full and path.is_file():
                    full[n] = json.loads(path.read_text(encoding="utf-8"))
    return full
