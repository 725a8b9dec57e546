"""Peak memory of reading hostile files, measured in a fresh interpreter.

The whole crafted corpus runs through the CLI in one subprocess, whose
``ru_maxrss`` (its own peak resident set, interpreter included) must stay
under 200 MB. A second subprocess reads the largest recordings the default
limit accepts, to show that the limit itself keeps readers under that bound.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

from taxelkit.frames import TactileFrames
from taxelkit.io.csv_format import write_csv_recording
from taxelkit.io.limits import DEFAULT_MAX_MB
from tests.fuzz.corpus import (
    CSV_CASES,
    H5_CASES,
    HEIGHTMAP_CASES,
    MCAP_CASES,
    MEMORY_CASES,
    MESH_CASES,
    NPZ_CASES,
    RECORDING_NPZ_CASES,
)

#: The bound of issue 13, bytes.
PEAK_LIMIT_BYTES = 200 * 10**6

#: Runs each argv of a JSON list through the CLI; prints exit codes and the
#: peak resident set. VmHWM is the high-water mark of this process's own
#: address space; ru_maxrss (the fallback off Linux) also counts the parent's
#: memory at fork time, which would measure pytest instead.
_CHILD = """
import contextlib, io, json, resource, sys
from taxelkit.cli import run
codes = []
for argv in json.load(open(sys.argv[1])):
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        codes.append(run(argv))
try:
    status = open("/proc/self/status").read().split("VmHWM:")[1]
    peak = int(status.split()[0]) * 1024
except (OSError, IndexError):
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
print(json.dumps({"codes": codes, "peak_bytes": peak}))
"""


def _run_child(tmp_path: Path, argvs: list[list[str]]) -> dict[str, list[int] | int]:
    script = tmp_path / "argv.json"
    script.write_text(json.dumps(argvs))
    done = subprocess.run(
        [sys.executable, "-c", _CHILD, str(script)],
        capture_output=True,
        text=True,
        timeout=300,
        check=True,
    )
    return json.loads(done.stdout.splitlines()[-1])  # type: ignore[no-any-return]


def test_peak_memory_on_every_crafted_file_stays_under_200_mb(tmp_path: Path) -> None:
    folder = tmp_path / "corpus"
    folder.mkdir()
    out = tmp_path / "out"
    argvs: list[list[str]] = []

    def add(name: str, write, argv: list[str]) -> None:  # type: ignore[no-untyped-def]
        path = folder / name
        write(path)
        argvs.append([a.format(f=path, d=out) for a in argv])

    for corpus, suffix in (
        (MCAP_CASES, ".mcap"),
        (NPZ_CASES["recording"], ".npz"),
        (RECORDING_NPZ_CASES, ".npz"),
        (H5_CASES, ".h5"),
        (CSV_CASES, ".csv"),
    ):
        for case, write in corpus.items():
            add(f"rec-{case}{suffix}", write, ["info", "{f}"])
    for corpus in (NPZ_CASES["heightmap"], HEIGHTMAP_CASES):
        for case, write in corpus.items():
            add(
                f"hm-{case}.npz",
                write,
                ["simulate", "press", "--specimen", "{f}", "--out", "{d}/p.npz"],
            )
    for corpus in (NPZ_CASES["memory"], MEMORY_CASES):
        for case, write in corpus.items():
            add(f"mem-{case}.npz", write, ["trace", "--shape", "circle", "--memory", "{f}"])
    for case, (suffix, write) in MESH_CASES.items():
        add(
            f"mesh-{case}{suffix}",
            write,
            ["simulate", "solid", "--mesh", "{f}", "--out", "{d}/s.npz"],
        )
    report = _run_child(tmp_path, argvs)
    assert report["codes"] == [2] * len(argvs)
    assert len(argvs) > 100
    assert report["peak_bytes"] < PEAK_LIMIT_BYTES, report["peak_bytes"]
    assert not out.exists()


def test_peak_memory_at_the_default_limit_stays_under_200_mb(tmp_path: Path) -> None:
    limit = int(DEFAULT_MAX_MB * 2**20)
    n_float32 = int(0.97 * limit) // (16 * 16 * 4)
    frames = np.zeros((n_float32, 16, 16), np.float32)
    npz, h5 = tmp_path / "big.npz", tmp_path / "big.h5"
    np.savez_compressed(npz, frames=frames)
    with h5py.File(h5, "w") as root:
        root.create_dataset("frames", data=frames, compression="gzip")
    del frames
    # CSV: the parsed table and its copy are charged at 16 bytes per cell.
    n_csv = int(0.97 * limit) // (16 * (16 * 16 + 1))
    csv = tmp_path / "big.csv"
    write_csv_recording(TactileFrames(np.zeros((n_csv, 16, 16), np.float32)), csv)
    report = _run_child(tmp_path, [["info", str(p)] for p in (npz, h5, csv)])
    assert report["codes"] == [0, 0, 0]
    assert report["peak_bytes"] < PEAK_LIMIT_BYTES, report["peak_bytes"]
