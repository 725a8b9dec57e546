"""README blocks rendered from the benchmark records and the experiment timings.

Like the results blocks of :mod:`taxelkit.experiments.report`, these are never
typed by hand: a block between ``<!-- generated:NAME -->`` and
``<!-- /generated:NAME -->`` is rendered from files under ``docs/results/``
by ``python benchmarks/render_readme.py``, and a test checks that the
committed README matches them.

- ``bench``: one row per ``docs/results/bench/SCRIPT.json``, written by the
  benchmark script itself (``python benchmarks/SCRIPT.py --record``) from the
  figures it measured. A record with ``"generated": false`` holds a row copied
  by hand from an earlier run of a script not yet converted; it is marked so.
- ``timings``: the wall-clock time of the committed ``reproduce`` run, from
  ``docs/results/NAME.timing.json``; ``taxelkit reproduce ... --readme``
  rewrites it too (:func:`update_timings`).
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import Any

from taxelkit.errors import InputError

__all__ = [
    "bench_markdown",
    "replace_generated_block",
    "span",
    "timings_markdown",
    "update_timings",
]

#: Order of the benchmark rows (scripts not listed follow, by name).
BENCH_ORDER: tuple[str, ...] = (
    "bench_solids.py",
    "bench_relief.py",
    "bench_neuron.py",
    "bench_associatron.py",
    "bench_smart.py",
    "bench_level12.py",
    "bench_large_arrays.py",
    "bench_cleaning.py",
    "bench_out_of_core.py",
    "bench_live_udp.py",
    "bench_live_soak.py",
    "bench_streaming_flat.py",
    "bench_bank.py",
    "bench_segment_track.py",
)


def _order(doc: Mapping[str, Any]) -> tuple[int, str]:
    script = str(doc["script"])
    return (BENCH_ORDER.index(script) if script in BENCH_ORDER else len(BENCH_ORDER), script)


def span(
    values: Sequence[float],
    digits: int = 0,
    step: float = 0.0,
    sign: str = "",
    *,
    scale: float = 1.0,
) -> str:
    """``lo-hi`` (or one value) of ``values / scale`` for a benchmark row, thousands separated.

    Rounded to ``step`` if given; with ``sign="+"`` the range reads ``+lo to +hi``.

    >>> span([1234.0, 987.6], step=10), span([0.5, 1.5], 1, sign="+"), span([2.0, 2.0], scale=4)
    ('990-1,230', '+0.5 to +1.5', '0')
    """
    fmt = f"{{:{sign},.{digits}f}}"
    a, b = min(values) / scale, max(values) / scale
    if step:
        a, b = step * round(a / step), step * round(b / step)
    lo, hi = fmt.format(a), fmt.format(b)
    return lo if lo == hi else f"{lo}{' to ' if sign else '-'}{hi}"


def bench_markdown(docs: Sequence[Mapping[str, Any]]) -> str:
    """The benchmark table from the records of ``docs/results/bench/``.

    Parameters
    ----------
    docs : sequence of mapping
        Records with ``script``, ``figure``, ``ratio``, ``generated`` and, for
        generated ones, ``date`` and ``machine`` (``cpus``, ``load_average_1min``
        and, recorded since 2026-11-28, the processor's model ``cpu``).
    """
    lines = [
        "| script | figure | ratio to the baseline of the same run |",
        "| --- | --- | --- |",
    ]
    for doc in sorted(docs, key=_order):
        if doc.get("generated"):
            m = doc["machine"]
            cpus = f"{m['cpus']} CPUs" + (f" ({m['cpu']})" if m.get("cpu") else "")
            when = f" [{doc['date']}, {cpus}, load average {m['load_average_1min']:g}]"
        else:
            when = " [copied by hand from an earlier run]"
        lines.append(f"| `{doc['script']}` | {doc['figure']}{when} | {doc['ratio']} |")
    return "\n".join(lines)


def timings_markdown(seconds: Mapping[str, float], *, longest: int = 3) -> str:
    """One sentence: the committed run's total wall time and its longest experiments.

    Parameters
    ----------
    seconds : mapping of str to float
        Wall-clock seconds per experiment (``NAME.timing.json``).
    longest : int
        How many of the longest experiments to name.
    """
    total_min = sum(seconds.values()) / 60.0
    top = sorted(seconds.items(), key=lambda kv: -kv[1])[:longest]
    named = ", ".join(f"`{n}` {s / 60.0:.0f} min" for n, s in top)
    n = len(seconds)
    return (
        f"The {n} experiment{'s' if n != 1 else ''} took {total_min:.0f} min of wall-clock time "
        f"in all in the run whose results are committed (longest: {named}); each one's time is "
        "in `NAME.timing.json` beside its results."
    )


def replace_generated_block(text: str, name: str, body: str) -> str:
    """``text`` with the block ``<!-- generated:NAME -->`` ... ``<!-- /generated:NAME -->`` set.

    Raises
    ------
    InputError
        If the block is missing or has no closing marker.
    """
    start, end = f"<!-- generated:{name} -->", f"<!-- /generated:{name} -->"
    if start not in text or end not in text:
        raise InputError(f"the README has no block {start} ... {end}")
    pattern = re.compile(re.escape(start) + r".*?" + re.escape(end), re.DOTALL)
    block = f"{start}\n{body}\n{end}"
    return pattern.sub(lambda _m: block, text, count=1)


def update_timings(text: str, seconds: Mapping[str, float]) -> str:
    """``text`` with its ``timings`` block rendered from ``seconds``; unchanged without one."""
    if "<!-- generated:timings -->" not in text or not seconds:
        return text
    return replace_generated_block(text, "timings", timings_markdown(seconds))
