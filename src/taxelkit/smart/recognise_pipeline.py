"""Out-of-core recognition on two cores: reading and Levels 1-2 in a worker process.

:class:`~taxelkit.smart.recognise_chunks.ChunkRecogniser` reads, cleans,
classifies (Levels 1-2) and recognises (Levels 3-4) each chunk one after the
other on one core. :func:`recognise_pipelined` gives the reading and Levels
1-2 (the checks, the image cleaning, the moments, the contact classes and
their limits, with their state carried from chunk to chunk) to a worker
process, and runs Levels 3-4 in the caller's: while the caller works on the
classes of one chunk, the worker reads and classifies the next ones (up to
four chunks ahead). Levels 1-2 take about a third of the one-core time, so
the worker also takes a share of Level 3: it foresees the segments each
chunk will close (:class:`~taxelkit.smart.whole_segments.WholeSegments`)
and computes the motion tactemes of their points, faces and half their lines
(``line_share``), which the caller's stream then takes instead of computing
them. Nothing is decided twice or differently: both processes keep the
chunks' order, a precomputed tacteme list is the one the caller would have
computed from the same inputs, and a segment the worker did not foresee is
computed by the caller, so the events, tactemes and verdict are those of
:func:`~taxelkit.smart.recognise_chunks.recognise_chunks` bit for bit
(tested). Each chunk's classes and statistics (81 bytes per frame) pass
once through a pipe as raw bytes.

The source is a picklable callable that the worker calls to get the chunks,
so the frames never pass through the caller's process: for a file,
:class:`~taxelkit.io.file_chunks.FileChunks`. The worker is started with the
``spawn`` method: a script that calls :func:`recognise_pipelined` must guard
its main code with ``if __name__ == "__main__":``.
"""

from __future__ import annotations

import multiprocessing as mp
import pickle
import queue
import threading
from collections.abc import Callable, Iterable
from multiprocessing.connection import Connection
from typing import Any

import numpy as np
from numpy.typing import NDArray

from taxelkit.errors import InputError
from taxelkit.smart.class_segments import ChunkRecognition
from taxelkit.smart.elimination import Event
from taxelkit.smart.recognise_chunks import ChunkRecogniser, levels12_of, push_chunk
from taxelkit.smart.whole_segments import WholeSegments

__all__ = ["LINE_SHARE", "recognise_pipelined"]

#: Bytes the pipe from the worker holds where the system allows (Linux's default limit).
_PIPE_BYTES = 1 << 20
#: Share of the lines whose tactemes the worker computes (set on the benchmark's rolls).
LINE_SHARE = 0.5
#: Chunks the worker may run ahead of the caller (each about 81 bytes a frame).
_AHEAD = 4
#: Seconds the worker is given to end before it is killed.
_JOIN_S = 5.0


class _Sender:
    """The worker's messages, sent from a thread: the worker runs up to ``ahead`` chunks ahead.

    Each chunk is a header (pickled) and arrays sent as raw bytes (no
    pickling: one copy at each end). Sending waits for the caller to read,
    so a short stall of either process no longer stalls the other.
    """

    def __init__(self, conn: Connection, ahead: int) -> None:
        self._conn = conn
        self._queue: queue.Queue[tuple[tuple[Any, ...], tuple[NDArray[Any], ...]] | None] = (
            queue.Queue(maxsize=ahead)
        )
        self.failed: OSError | None = None
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def put(self, header: tuple[Any, ...], arrays: tuple[NDArray[Any], ...] = ()) -> None:
        if self.failed is not None:
            raise self.failed
        self._queue.put((header, arrays))

    def _run(self) -> None:
        while (item := self._queue.get()) is not None:
            if self.failed is not None:
                continue  # the caller is gone: drained until closed
            header, arrays = item
            try:
                self._conn.send(header)
                for a in arrays:
                    self._conn.send_bytes(np.ascontiguousarray(a).reshape(-1).view(np.uint8).data)
            except OSError as exc:
                self.failed = exc

    def close(self) -> None:
        """Send what is queued, then stop the thread."""
        self._queue.put(None)
        self._thread.join()


class _Front(ChunkRecogniser):
    """The worker's side of :func:`recognise_pipelined`: checks and Levels 1-2, sent on."""

    def __init__(
        self, shape: tuple[int, int], out: _Sender, line_share: float, **options: Any
    ) -> None:
        super().__init__(shape, **options)
        self._out = out
        self._whole = WholeSegments(self.config, self.pitch_mm, line_share)

    def _next(self, kind: str, data: NDArray[Any], t: NDArray[np.float64]) -> list[Event]:
        classes, rows = levels12_of(self._levels12, kind, data, t)
        found = self._whole.tactemes(classes[0], rows[0], t)
        self._out.put(("chunk", int(t.size), found), (classes, rows, t))
        return []


def _receive_chunk(
    conn: Connection, n: int
) -> tuple[NDArray[np.int8], NDArray[np.float64], NDArray[np.float64]]:
    """The classes ``(1, n)``, rows ``(1, n, 9)`` and times ``(n,)`` that :class:`_Front` sent."""
    classes = np.empty((1, n), np.int8)
    rows = np.empty((1, n, 9))
    t = np.empty(n)
    for a in (classes, rows, t):
        conn.recv_bytes_into(a.reshape(-1).view(np.uint8))
    return classes, rows, t


def _widen(conn: Connection) -> None:
    """Let the pipe hold a megabyte (Linux; else as it is): fewer hand-offs per chunk."""
    try:
        import fcntl

        fcntl.fcntl(conn.fileno(), fcntl.F_SETPIPE_SZ, _PIPE_BYTES)
    except (ImportError, AttributeError, OSError):
        pass


def _portable(exc: BaseException) -> BaseException:
    """``exc`` if it pickles (to be raised again by the caller), else a RuntimeError naming it."""
    try:
        pickle.loads(pickle.dumps(exc))
    except Exception:  # any failure to round-trip
        return RuntimeError(f"{type(exc).__name__}: {exc}")
    return exc


def _serve_source(
    conn: Connection,
    source: Callable[[], Iterable[Any]],
    pitch_mm: float | None,
    options: dict[str, Any],
    line_share: float,
) -> None:
    """The worker of :func:`recognise_pipelined`: read ``source``, send each chunk's Levels 1-2."""
    out = _Sender(conn, _AHEAD)
    front: _Front | None = None
    try:
        for chunk in source():
            if front is None:
                shape = (int(chunk.shape[1]), int(chunk.shape[2]))
                pitch = float(chunk.pitch_mm if pitch_mm is None else pitch_mm)
                front = _Front(shape, out, line_share, pitch_mm=pitch, **options)
                out.put(("start", shape, pitch))
            push_chunk(front, chunk)
        if front is None:
            raise InputError("the source gave no chunk of frames")
        out.put(("end",))
    except Exception as exc:  # raised again in the caller's process
        if out.failed is None:
            out.put(("error", _portable(exc)))
    finally:
        out.close()
        conn.close()


def recognise_pipelined(
    source: Callable[[], Iterable[Any]],
    *,
    pitch_mm: float | None = None,
    line_share: float = LINE_SHARE,
    **options: Any,
) -> ChunkRecognition:
    """Recognise a recording read by a worker process: Levels 1-2 there, Levels 3-4 here.

    Parameters
    ----------
    source : callable
        Picklable, called once in the worker: it yields consecutive chunks,
        :class:`~taxelkit.frames.TactileFrames` or packed chunks (objects
        with ``rows``, ``t_s``, ``shape`` and ``pitch_mm``, as
        :class:`~taxelkit.io.packed_chunk.PackedChunk`), for example
        :class:`~taxelkit.io.file_chunks.FileChunks`.
    pitch_mm : float, optional
        Overrides the chunks' pitch, mm.
    line_share : float
        The share of the lines ending within a chunk whose motion tactemes
        the worker computes beforehand (:class:`~taxelkit.smart.whole_segments.WholeSegments`;
        it computes those of every point and face): it balances the two
        processes' work and changes no result.
    **options
        ``threshold``, ``network``, ``confidence``, ``config``, ``cleaning``,
        ``limits``, ``per_frame`` of
        :class:`~taxelkit.smart.recognise_chunks.ChunkRecogniser`.

    Returns
    -------
    ChunkRecognition
        That of :func:`~taxelkit.smart.recognise_chunks.recognise_chunks`
        over the same chunks (tested).

    Raises
    ------
    TaxelkitError
        What reading or checking the chunks raised in the worker (an
        :class:`~taxelkit.errors.InputError` if there were none), raised here.
    RuntimeError
        If the worker process ended without a word.
    """
    ctx = mp.get_context("spawn")
    conn, child = ctx.Pipe(duplex=False)
    _widen(conn)
    process = ctx.Process(
        target=_serve_source,
        args=(child, source, pitch_mm, options, line_share),
        daemon=True,
        name="taxelkit-levels12",
    )
    process.start()
    child.close()
    recogniser: ChunkRecogniser | None = None
    try:
        while True:
            try:
                message = conn.recv()
            except EOFError:
                process.join(_JOIN_S)
                raise RuntimeError(
                    f"the Levels 1-2 worker process ended (exit code {process.exitcode})"
                ) from None
            kind = message[0]
            if kind == "chunk":
                assert recogniser is not None
                chunk = _receive_chunk(conn, message[1])
                recogniser.push_levels12(*chunk, precomputed=message[2])
            elif kind == "start":
                recogniser = ChunkRecogniser(message[1], pitch_mm=message[2], **options)
            elif kind == "end":
                assert recogniser is not None
                return recogniser.result()
            else:
                raise message[1]
    finally:
        conn.close()
        process.join(_JOIN_S)
        if process.is_alive():
            process.kill()
            process.join()
