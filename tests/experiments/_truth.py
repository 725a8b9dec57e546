"""Compare an experiment's JSON with the committed one, leaf by leaf, within seeded tolerances.

A JSON document is flattened into ``{path: leaf}`` (``"tracing_error_mm/star/mean"``,
``"abs_r/3"``). Numeric leaves are compared within a tolerance taken from the
seed-to-seed spread measured by ``tests/experiments/_seed_spread.py`` and
stored in ``tests/experiments/seed_spread.json``; every other leaf (strings,
booleans, None, and numbers whose spread over the seeds was zero) must be
equal.

How the tolerance is chosen: the experiment is run at seeds 0-5; for each
numeric leaf, ``sigma`` is the sample standard deviation over those seeds,
and the tolerance is ``3 * sqrt(2) * sigma`` (the difference of two
independent draws has standard deviation ``sqrt(2) * sigma``; three of those).
A change to the code that only moves a figure as much as another seed would is
tolerated; a regression beyond that fails. A leaf that did not move over six
seeds gets the float floor :data:`FLOOR` (rounding across platforms), so it
must stay as it is.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[2]
RESULTS = ROOT / "docs" / "results"
SPREAD_FILE = Path(__file__).with_name("seed_spread.json")

#: Seeds whose spread sets the tolerances.
SPREAD_SEEDS = (0, 1, 2, 3, 4, 5)
#: Multiplier on the seed-to-seed standard deviation: 3 standard deviations of
#: the difference of two independent draws.
SIGMAS = 3.0 * math.sqrt(2.0)
#: Tolerance of a leaf that did not move over the seeds: float rounding only.
FLOOR = 1e-9


def flatten(doc: Any, prefix: str = "") -> dict[str, Any]:
    """``{path: leaf}`` of a JSON document (lists indexed by position)."""
    if isinstance(doc, dict):
        out: dict[str, Any] = {}
        for k, v in doc.items():
            out.update(flatten(v, f"{prefix}{k}/"))
        return out
    if isinstance(doc, list):
        out = {}
        for i, v in enumerate(doc):
            out.update(flatten(v, f"{prefix}{i}/"))
        return out
    return {prefix.rstrip("/"): doc}


def is_number(x: Any) -> bool:
    """A JSON number (booleans are not)."""
    return isinstance(x, int | float) and not isinstance(x, bool)


def committed(name: str) -> dict[str, Any]:
    """The committed ``docs/results/NAME.json``."""
    doc: dict[str, Any] = json.loads((RESULTS / f"{name}.json").read_text(encoding="utf-8"))
    return doc


def tolerances(name: str) -> dict[str, float]:
    """Per numeric leaf of experiment ``name``: the tolerance from the measured spread."""
    spread = json.loads(SPREAD_FILE.read_text(encoding="utf-8"))
    return {path: float(row["tolerance"]) for path, row in spread[name]["leaves"].items()}


def differences(
    new: dict[str, Any], old: dict[str, Any], tol: dict[str, float], *, skip: tuple[str, ...] = ()
) -> list[str]:
    """Leaves of ``new`` and ``old`` that differ beyond their tolerance (one line each).

    Parameters
    ----------
    new, old : dict
        JSON documents (the code's result now, the committed one).
    tol : dict
        Tolerance per numeric leaf path; a path not in it must be equal (up to :data:`FLOOR`).
    skip : tuple of str
        Path prefixes not compared (bookkeeping such as ``"seed"``).
    """
    a, b = flatten(new), flatten(old)
    out = []
    for path in sorted(set(a) | set(b)):
        if path.startswith(skip):
            continue
        if path not in a or path not in b:
            out.append(f"{path}: only in {'the new result' if path in a else 'the committed one'}")
            continue
        x, y = a[path], b[path]
        if is_number(x) and is_number(y):
            t = max(tol.get(path, 0.0), FLOOR * max(1.0, abs(float(y))))
            if not abs(float(x) - float(y)) <= t:
                out.append(f"{path}: now {x!r}, committed {y!r} (tolerance {t:.3g})")
        elif x != y:
            out.append(f"{path}: now {x!r}, committed {y!r}")
    return out
