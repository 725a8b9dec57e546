"""Out-of-core recognition: a day-long recording in bounded memory.

A recording of ``--frames`` 16 x 16 contact frames at 240 frames/s (20 M
frames is 23 h) is written with :class:`taxelkit.io.chunked_write.RecordingAppender`
(contact frames packed 8 taxels to a byte, 32 bytes per frame, gzip level 1:
see ``docs/recording-format.md``), by repeating a block of randomised rolling
scenarios of the six objects (each contact is touched, rolled and lifted).
It is then recognised, each in a fresh subprocess whose CPU time
(``time.process_time``, so that other work on a shared machine does not count)
and peak resident memory (``VmHWM`` of ``/proc/self/status``, the process's
own high-water mark; ``ru_maxrss`` where there is no ``/proc``: on Linux it
keeps the peak of the parent the child was forked from, which holds the
frames this script writes) are reported:

* out-of-core: :func:`taxelkit.io.chunked_read.open_chunks` read chunk by chunk
  into :class:`taxelkit.smart.recognise_chunks.ChunkRecogniser` (the rows kept
  packed as stored: ``packed_chunks`` into ``push_packed``);
* pipelined on two cores: :func:`taxelkit.smart.recognise_pipeline.recognise_pipelined`
  with :class:`taxelkit.io.file_chunks.FileChunks` (a worker process reads the
  file, runs Levels 1-2 and computes the motion tactemes of the segments it
  foresees, the caller runs the rest of Levels 3-4): its wall time
  (``time.perf_counter``, the two processes overlap), the CPU time of both
  processes and the peak resident memory of each (the worker's is
  ``ru_maxrss`` of the children: it is a fresh interpreter, nothing inherited);
  its events are checked to be those of the one-core run;
* the ``taxelkit recognize FILE --json`` command on the long file (once):
  besides the single-object recogniser it tracks every contact region and
  recognises each track (:class:`taxelkit.smart.objects.ObjectRecogniser`),
  and prints the whole JSON document;
* in memory (the baseline): ``read_recording`` then ``recognise`` (the path
  ``taxelkit recognize`` took before), on the first ``--compare-frames``
  frames, a file that fits; the out-of-core path is run on the same file and
  its events are checked to be identical.

The long file is recognised ``--runs`` times (the range is quoted);
``--record`` writes the README row (``docs/results/bench/bench_out_of_core.json``).

Usage: ``python benchmarks/bench_out_of_core.py [--frames 20000000] [--compare-frames 2000000]
[--runs 2] [--record]``.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import json  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from _record import add_record_option, record  # noqa: E402
from _rolls import roll_images  # noqa: E402
from taxelkit.experiments.readme_tables import span  # noqa: E402
from taxelkit.io.chunked_write import RecordingAppender  # noqa: E402
from taxelkit.sensors import BONNEVILLE_16X16  # noqa: E402

RATE_HZ = BONNEVILLE_16X16.max_rate_hz

_PEAK = """
import resource
def peak_mb():
    try:
        with open("/proc/self/status") as fh:
            return int(fh.read().split("VmHWM:")[1].split()[0]) / 1024
    except (OSError, IndexError, ValueError):
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
"""

_OUT_OF_CORE = (
    _PEAK
    + """
import json, resource, sys, time
from taxelkit.io.chunked_read import open_chunks
from taxelkit.smart.recognise_chunks import ChunkRecogniser
t0 = time.process_time()
with open_chunks(sys.argv[1]) as rec:
    recogniser = ChunkRecogniser(rec.shape, pitch_mm=1.7625)
    if rec.packed:  # the rows as stored: the cleaning starts from them
        for packed in rec.packed_chunks(int(sys.argv[2])):
            recogniser.push_packed(packed.rows, packed.t_s)
    else:
        for chunk in rec.chunks(int(sys.argv[2])):
            recogniser.push(chunk.frames, chunk.t_s)
result = recogniser.result()
seconds = time.process_time() - t0
print(json.dumps({
    "frames": result.n_frames, "seconds": seconds, "events": len(result.events),
    "digest": [(e.kind, e.frame, str(e.value)) for e in result.events[-50:]],
    "identified": result.identified, "segments": int(result.segments.class_code.size),
    "maxrss_mb": peak_mb(),
}))
"""
)

_PIPELINED = (
    _PEAK
    + """
import json, resource, sys, time
from taxelkit.io.file_chunks import FileChunks
from taxelkit.smart.recognise_pipeline import recognise_pipelined
if __name__ == "__main__":
    w0, t0 = time.perf_counter(), time.process_time()
    result = recognise_pipelined(
        FileChunks(sys.argv[1], chunk_frames=int(sys.argv[2])), pitch_mm=1.7625
    )
    wall, cpu = time.perf_counter() - w0, time.process_time() - t0
    child = resource.getrusage(resource.RUSAGE_CHILDREN)
    print(json.dumps({
        "frames": result.n_frames, "wall_s": wall, "cpu_s": cpu,
        "worker_cpu_s": child.ru_utime + child.ru_stime, "events": len(result.events),
        "digest": [(e.kind, e.frame, str(e.value)) for e in result.events[-50:]],
        "identified": result.identified, "maxrss_mb": peak_mb(),
        "worker_maxrss_mb": child.ru_maxrss / 1024,
    }))
"""
)

_IN_MEMORY = (
    _PEAK
    + """
import json, resource, sys, time
from taxelkit.io.limits import read_limit
from taxelkit.io.recordings import read_recording
from taxelkit.smart.recogniser import recognise
t0 = time.process_time()
with read_limit(1e6):
    rec = read_recording(sys.argv[1], pitch_mm=1.7625)
result = recognise(rec)
seconds = time.process_time() - t0
print(json.dumps({
    "frames": rec.n_frames, "seconds": seconds, "events": len(result.events),
    "digest": [(e.kind, e.frame, str(e.value)) for e in result.events[-50:]],
    "identified": result.identified,
    "maxrss_mb": peak_mb(),
}))
"""
)


_COMMAND = (
    _PEAK
    + """
import contextlib, json, os, sys, time
from taxelkit.cli.app import run
t0 = time.process_time()
with open(os.devnull, "w") as null, contextlib.redirect_stdout(null):
    rc = run(["recognize", sys.argv[1], "--json", "--pitch-mm", "1.7625"])
print(json.dumps({"rc": rc, "seconds": time.process_time() - t0, "maxrss_mb": peak_mb()}))
"""
)


def base_block(n_scenarios: int) -> np.ndarray:
    """Contact frames of ``n_scenarios`` rolling scenarios, one after another."""
    return np.concatenate(roll_images(n_scenarios, faults=False))


def write_long(path: Path, block: np.ndarray, n_frames: int, chunk_frames: int) -> float:
    """Write ``n_frames`` frames (``block`` repeated) with the appender; seconds taken."""
    t0 = time.perf_counter()
    with RecordingAppender(
        path,
        shape=block.shape[1:],
        pitch_mm=BONNEVILLE_16X16.array.pitch_mm,
        chunk_frames=chunk_frames,
        force=True,
    ) as out:
        done = 0
        while done < n_frames:
            take = min(block.shape[0], n_frames - done)
            out.append(block[:take], (done + np.arange(take)) / RATE_HZ)
            done += take
    return time.perf_counter() - t0


def run(script: str, *args: object) -> dict[str, object]:
    out = subprocess.run(
        [sys.executable, "-c", script, *map(str, args)], capture_output=True, text=True
    )
    if out.returncode:
        raise SystemExit(out.stderr)
    doc: dict[str, object] = json.loads(out.stdout)
    return doc


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=20_000_000)
    ap.add_argument("--compare-frames", type=int, default=2_000_000)
    ap.add_argument("--chunk-frames", type=int, default=65536)
    ap.add_argument("--scenarios", type=int, default=36)
    ap.add_argument("--runs", type=int, default=2, help="runs on the long file (range quoted)")
    ap.add_argument("--workdir", type=Path, default=None)
    add_record_option(ap)
    args = ap.parse_args()
    if args.workdir is not None:
        args.workdir.mkdir(parents=True, exist_ok=True)
    block = base_block(args.scenarios)
    with tempfile.TemporaryDirectory(dir=args.workdir) as tmp:
        small, large = Path(tmp) / "small.h5", Path(tmp) / "large.h5"
        write_long(small, block, args.compare_frames, args.chunk_frames)
        memory = run(_IN_MEMORY, small)
        chunked_small = run(_OUT_OF_CORE, small, args.chunk_frames)
        same = memory["digest"] == chunked_small["digest"] and (
            memory["events"] == chunked_small["events"]
        )
        write_s = write_long(large, block, args.frames, args.chunk_frames)
        size_mb = large.stat().st_size / 2**20
        longs = [run(_OUT_OF_CORE, large, args.chunk_frames) for _ in range(args.runs)]
        piped = [run(_PIPELINED, large, args.chunk_frames) for _ in range(args.runs)]
        command = run(_COMMAND, large)
    n_small, n = args.compare_frames, args.frames
    rate_mem = n_small / float(memory["seconds"])  # type: ignore[arg-type]
    rate_small = n_small / float(chunked_small["seconds"])  # type: ignore[arg-type]
    rates = [n / float(c["seconds"]) for c in longs]  # type: ignore[arg-type]
    rss = [float(c["maxrss_mb"]) for c in longs]  # type: ignore[arg-type]
    rss_mem, rss_small = float(memory["maxrss_mb"]), float(chunked_small["maxrss_mb"])  # type: ignore[arg-type]
    print(
        f"out-of-core recognition of 16 x 16 contact frames at 240 Hz, "
        f"chunks of {args.chunk_frames:,} frames, one core (CPU time)"
    )
    print(
        f"long file: {n:,} frames ({n / RATE_HZ / 3600:.1f} h), {size_mb:,.0f} MiB on disk "
        f"(packed bits + gzip 1), written at {n / write_s:,.0f} frames/s"
    )
    print(f"{'path':44s} {'frames':>12s} {'frames/s':>16s} {'peak RSS MB':>12s}")
    print(f"{'in memory (read_recording + recognise)':44s} {n_small:12,d} {rate_mem:16,.0f} "
          f"{rss_mem:12,.0f}")  # fmt: skip
    print(f"{'out-of-core, same file':44s} {n_small:12,d} {rate_small:16,.0f} "
          f"{rss_small:12,.0f}")  # fmt: skip
    print(f"{f'out-of-core, long file ({args.runs} runs)':44s} {n:12,d} {span(rates):>16s} "
          f"{span(rss):>12s}")  # fmt: skip
    rates_p = [n / float(c["wall_s"]) for c in piped]  # type: ignore[arg-type]
    cpu_p = [float(c["cpu_s"]) + float(c["worker_cpu_s"]) for c in piped]  # type: ignore[arg-type]
    rss_p = [float(c["maxrss_mb"]) + float(c["worker_maxrss_mb"]) for c in piped]  # type: ignore[arg-type]
    same_p = all(c["digest"] == longs[-1]["digest"] and c["events"] == longs[-1]["events"]
                 for c in piped)  # fmt: skip
    print(f"{f'pipelined, 2 processes, wall time ({args.runs} runs)':44s} {n:12,d} "
          f"{span(rates_p):>16s} {span(rss_p):>12s}  (both processes' peaks added; "
          f"CPU {span(cpu_p)} s in all; events as one core: {same_p})")  # fmt: skip
    print(
        f"ratio out-of-core / in memory on the same file: speed {rate_small / rate_mem:.2f}x, "
        f"peak memory {rss_small / rss_mem:.2f}x (events identical: {same})"
    )
    rate_cmd = n / float(command["seconds"])  # type: ignore[arg-type]
    rss_cmd = float(command["maxrss_mb"])  # type: ignore[arg-type]
    print(f"{'taxelkit recognize --json, long file':44s} {n:12,d} {rate_cmd:16,.0f} "
          f"{rss_cmd:12,.0f}  (both recognisers; exit code {command['rc']})")  # fmt: skip
    last = longs[-1]
    print(
        f"long file: {last['events']} events, {last['segments']:,} class segments, "
        f"identified {last['identified']!r}; targets: peak < 300 MB, >= 1,000,000 frames/s"
    )
    if args.record:
        met_mem = "met" if max(rss) < 300 else "missed"
        met_rate = "met" if min(rates) >= 1e6 else "missed"
        met_p = "met" if min(rates_p) >= 1e6 and max(rss_p) < 300 else "missed"
        figure = (
            f"{n / 1e6:g} M frames ({n / RATE_HZ / 3600:.1f} h at 240 Hz, {size_mb:,.0f} MiB "
            f"packed HDF5) recognised out of core: {span(rates, step=1000)} frames/s (CPU time, "
            f"{args.runs} runs), peak RSS {span(rss)} MB (target < 300 MB {met_mem}; "
            f"1,000,000 frames/s {met_rate}); on two cores, reading, Levels 1-2 and part of "
            f"Level 3 in a worker process (`recognise_pipelined`): "
            f"{span(rates_p, step=1000)} frames/s (wall time), peak RSS {span(rss_p)} MB "
            f"for both processes (1,000,000 frames/s and "
            f"300 MB {met_p}; events as on one core: {'yes' if same_p else 'NO'}); "
            f"the `recognize` command on it (the per-track "
            f"recogniser too, `--json`): {rate_cmd:,.0f} frames/s, peak RSS {rss_cmd:,.0f} MB "
            f"({'under' if rss_cmd < 300 else 'over'} 300 MB)"
        )
        ratio = (
            f"{rate_small / rate_mem:.2f}x the speed and {rss_small / rss_mem:.2f}x the memory "
            f"({rss_small:,.0f} MB against {rss_mem:,.0f} MB) of `read_recording` + `recognise` "
            f"on a {n_small / 1e6:g} M-frame file, events "
            f"{'identical' if same else 'DIFFERENT'}"
        )
        measured = {
            "frames": n,
            "rates": rates,
            "maxrss_mb": rss,
            "compare_frames": n_small,
            "in_memory": {"rate": rate_mem, "maxrss_mb": rss_mem},
            "out_of_core_same_file": {"rate": rate_small, "maxrss_mb": rss_small},
            "events_identical": same,
            "pipelined": {
                "rates_wall": rates_p,
                "cpu_s": cpu_p,
                "maxrss_mb_both": rss_p,
                "events_identical": same_p,
            },
            "command": {"rate": rate_cmd, "maxrss_mb": rss_cmd, "exit_code": command["rc"]},
        }
        record(__file__, figure=figure, ratio=ratio, measured=measured)


if __name__ == "__main__":
    main()
