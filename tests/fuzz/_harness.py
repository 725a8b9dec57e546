"""Run the CLI in-process and check the contract for bad input.

The contract (issue 13): exit code 2, exactly one line on stderr starting
with ``taxelkit: error:``, no traceback, and no output file left behind.
"""

from __future__ import annotations

import contextlib
import io
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from taxelkit.cli import run

__all__ = ["Result", "assert_refused", "files_under", "invoke"]


@dataclass(frozen=True)
class Result:
    """Exit code and captured streams of one CLI run."""

    code: int
    out: str
    err: str


def invoke(argv: Sequence[str | Path]) -> Result:
    """Run ``taxelkit ARGV`` in this process, capturing stdout and stderr."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = run([str(a) for a in argv])
    return Result(code, out.getvalue(), err.getvalue())


def assert_refused(result: Result, *, contains: str | None = None) -> str:
    """Assert the bad-input contract; return the error line."""
    lines = result.err.splitlines()
    assert result.code == 2, f"exit {result.code}, stderr {result.err!r}"
    assert len(lines) == 1, f"expected exactly one line on stderr, got {result.err!r}"
    assert lines[0].startswith("taxelkit: error: "), lines[0]
    assert "Traceback" not in result.err + result.out
    if contains is not None:
        assert contains in lines[0], lines[0]
    return lines[0]


def files_under(folder: Path) -> set[Path]:
    """Every file and folder under ``folder``, hidden temporary files included."""
    return set(folder.rglob("*"))
