"""The receive loop of ``taxelkit recognize --live``: batches in, lines out, clean stops.

SIGINT (Ctrl-C) and SIGTERM set a flag instead of killing the run; the loop
notices it within one read (at most :data:`POLL_S`), also while it waits for
data, and the run ends with its summary and exit code 130 or 143.
"""

from __future__ import annotations

import contextlib
import signal
import threading
import time
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, Any

import numpy as np

from taxelkit.io.live_sources import FrameSource, LiveTimeoutError

if TYPE_CHECKING:
    from taxelkit.cli.live import _LiveRun
    from taxelkit.cli.live_bank import BankRun

__all__ = ["EXIT_INTERRUPTED", "EXIT_OK", "EXIT_TERMINATED", "POLL_S", "run_live"]

#: Exit code after ``max_frames`` frames, the end of the stream, or a quiet device.
EXIT_OK = 0
#: Exit code after Ctrl-C or SIGINT (128 + 2), once the summary has been printed.
EXIT_INTERRUPTED = 130
#: Exit code after SIGTERM (128 + 15), once the summary has been printed.
EXIT_TERMINATED = 143
#: Longest wait in one read, s: how soon a signal or a timeout is noticed.
POLL_S = 0.1
_STOPS = {signal.SIGINT: ("interrupted", EXIT_INTERRUPTED)}
if hasattr(signal, "SIGTERM"):
    _STOPS[signal.SIGTERM] = ("terminated", EXIT_TERMINATED)


class _Stop:
    """The signal that asked the run to stop, if any."""

    def __init__(self) -> None:
        self.signum: int | None = None

    def __call__(self, signum: int, frame: Any) -> None:
        self.signum = signum


@contextlib.contextmanager
def _stop_on_signals() -> Iterator[_Stop]:
    """SIGINT and SIGTERM set a flag instead of killing the run (main thread only).

    The handlers are installed whatever the inherited disposition: a command
    started in the background by a shell inherits SIGINT ignored, and would
    otherwise never stop on it.
    """
    stop = _Stop()
    if threading.current_thread() is not threading.main_thread():
        yield stop
        return
    previous = {sig: signal.signal(sig, stop) for sig in _STOPS}
    try:
        yield stop
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def run_live(
    opener: Callable[[], FrameSource],
    run: _LiveRun | BankRun,
    max_frames: int | None,
    idle: float | None,
    echo: Callable[[str], None],
) -> int:
    """The receive loop: batches to the sensor, lines to ``echo``, then the summary."""
    with _stop_on_signals() as stop, opener() as src:
        why, code = "end of stream", EXIT_OK
        try:
            why, code = _receive(src, run, max_frames, idle, echo, stop)
        except KeyboardInterrupt:  # SIGINT outside the main thread's handler
            why, code = "interrupted", EXIT_INTERRUPTED
        finally:
            recorded = "" if run.recorder is None else f"; {run.recorder.close()}"
        for line in run.finish():
            echo(line)
        s = src.stats
        counts = (
            f"damaged packets skipped: {s.corrupted}, frame indices missing: {s.missing}, "
            f"bytes skipped: {s.bytes_skipped}"
        )
        dropped = int(getattr(src, "dropped", 0))  # a BackgroundReceiver's full queue
        if dropped:
            counts += f", datagrams dropped by a full queue: {dropped}"
        echo(run.summary(counts, why) + recorded)
    return code


def _receive(
    src: FrameSource,
    run: _LiveRun | BankRun,
    max_frames: int | None,
    idle: float | None,
    echo: Callable[[str], None],
    stop: _Stop,
) -> tuple[str, int]:
    """Read until the end, a limit, a quiet device or a signal; why it ended and the code."""
    last = time.monotonic()
    while True:
        if stop.signum is not None:
            return _STOPS[signal.Signals(stop.signum)]
        wait = POLL_S if idle is None else max(0.0, min(POLL_S, last + idle - time.monotonic()))
        batches = src.poll_batches(wait)
        if not batches:
            if src.at_end:
                return "end of stream", EXIT_OK
            if idle is not None and time.monotonic() - last >= idle:
                if run.sensor is None:
                    s = src.stats
                    raise LiveTimeoutError(
                        f"no frame from {src.description} for {idle:g} s ({s.bytes_received} "
                        f"bytes received, {s.frames} frames, {s.corrupted} damaged packets)"
                    )
                return f"no frame for {idle:g} s", EXIT_OK
            continue
        for batch in batches:
            if max_frames is not None and run.frames + batch.n_frames >= max_frames:
                keep = max_frames - run.frames
                batch = batch.take(np.arange(keep))
                for line in run.push(batch):
                    echo(line)
                return f"stopped after {max_frames} frames", EXIT_OK
            for line in run.push(batch):
                echo(line)
        last = time.monotonic()  # the wait starts once the frames are processed
