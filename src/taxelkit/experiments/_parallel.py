"""Run an experiment's independent units in-process, in worker processes or on a Dask cluster.

Each unit carries its own seed (a :class:`numpy.random.SeedSequence` child or
entropy), so the results do not depend on where or in which order the units
run; the caller puts each result back at its unit's index.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Any, TypeVar

from taxelkit.errors import InputError

__all__ = ["run_units"]

U = TypeVar("U")
R = TypeVar("R")


def _local(fn: Callable[[U], R], units: Sequence[U], workers: int) -> Iterator[tuple[int, R]]:
    if workers == 1:
        for i, u in enumerate(units):
            yield i, fn(u)
        return
    with ProcessPoolExecutor(max_workers=workers) as pool:
        futures = {pool.submit(fn, u): i for i, u in enumerate(units)}
        for f in as_completed(futures):
            yield futures[f], f.result()


def _dask(fn: Callable[[U], R], units: Sequence[U], scheduler: str) -> Iterator[tuple[int, R]]:
    try:
        import distributed
    except ImportError:
        raise InputError(
            'a Dask scheduler needs the dask extra: pip install "taxelkit[dask]"'
        ) from None
    dask: Any = distributed  # untyped: its calls are checked by the tests on a local cluster
    with dask.Client(scheduler) as client:
        futures = client.map(fn, list(units), pure=False)
        index = {f.key: i for i, f in enumerate(futures)}
        for f in dask.as_completed(futures):
            yield index[f.key], f.result()


def run_units(
    fn: Callable[[U], R], units: Sequence[U], *, workers: int, scheduler: str | None = None
) -> Iterator[tuple[int, R]]:
    """``(index, fn(unit))`` for every unit, in the order they finish.

    Parameters
    ----------
    fn : callable
        A module-level function (it is pickled to the workers).
    units : sequence
        Its arguments, one call each.
    workers : int
        Local worker processes; 1 runs in this process, in order.
    scheduler : str, optional
        Address of a Dask scheduler: run the units there instead.

    Raises
    ------
    InputError
        For a scheduler without the dask extra installed.
    """
    return _dask(fn, units, scheduler) if scheduler else _local(fn, units, workers)
