"""Units of work on a local process pool or a Dask cluster (shared by the sweeps).

An experiment cuts its work into picklable *units* and a module-level
function that runs one; :func:`run_units` runs them in-process, on a
:class:`~concurrent.futures.ProcessPoolExecutor`, or on a Dask scheduler
(``dask.distributed``, optional extra ``taxelkit[dask]``) and yields
``(index, result)`` as units finish. Callers store results by index, so the
outcome never depends on where or in which order units ran.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from typing import Any, TypeVar

from taxelkit.errors import InputError

__all__ = ["map_in_order", "run_units"]

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
    fn: Callable[[U], R],
    units: Sequence[U],
    *,
    workers: int = 1,
    scheduler: str | None = None,
) -> Iterator[tuple[int, R]]:
    """Run ``fn`` on every unit; yield ``(index, result)`` as each finishes.

    Parameters
    ----------
    fn : callable
        A module-level function (picklable) of one unit.
    units : sequence
        Picklable units.
    workers : int
        Local worker processes (1 runs in this process, in order).
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://HOST:PORT``); overrides ``workers``.

    Raises
    ------
    InputError
        If a scheduler is given and ``distributed`` is not installed.
    """
    if scheduler:
        return _dask(fn, units, scheduler)
    return _local(fn, units, max(1, int(workers)))


def map_in_order(
    fn: Callable[[U], R],
    jobs: Sequence[U],
    *,
    workers: int,
    chunksize: int = 1,
    progress: Callable[[int, int], None] | None = None,
) -> list[R]:
    """``[fn(job) for job in jobs]``, in this process or on a local process pool.

    Parameters
    ----------
    fn, jobs
        As ``fn`` and ``units`` of :func:`run_units`.
    workers : int
        Local worker processes; 1 runs in this process.
    chunksize : int
        Jobs sent to a worker at a time (``ProcessPoolExecutor.map``).
    progress : callable, optional
        ``progress(done, total)`` after each result, in the jobs' order.
    """
    if workers == 1:
        return _collect(map(fn, jobs), len(jobs), progress)
    with ProcessPoolExecutor(max_workers=workers) as pool:
        return _collect(pool.map(fn, jobs, chunksize=chunksize), len(jobs), progress)


def _collect(
    results: Iterable[R], total: int, progress: Callable[[int, int], None] | None
) -> list[R]:
    out: list[R] = []
    for res in results:
        out.append(res)
        if progress is not None:
            progress(len(out), total)
    return out
