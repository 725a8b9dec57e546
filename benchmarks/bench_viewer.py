"""Throughput of the smart sensor streaming with the rerun view attached.

Run: ``python benchmarks/bench_viewer.py [--frames 10000]``. Streams simulated
rolls frame by frame through :class:`~taxelkit.smart.recogniser.SmartSensor`,
once alone (the baseline, same run) and once logging every frame, contact
class and event to a :class:`~taxelkit.viewer.RerunView` saved to an ``.rrd``
file. Then runs ``taxelkit recognize --live file:CAPTURE --save-view OUT.rrd``
(the live command, reading the frames as live-protocol packets from a capture
file) without and with the view. Prints frames/s, ratios, whether the 240 frames/s
target is met, and checks that the live ``.rrd`` holds every verdict. Needs the
viewer extra.
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from _record import add_record_option, record
from taxelkit.cli.live import recognize_live
from taxelkit.io.frame_protocol import encode_frame
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import SCENARIO_NAMES, make_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart.recogniser import SmartSensor
from taxelkit.viewer import ENTITY_PATHS, RerunView
from taxelkit.viewer.rerun_view import VERDICT_KINDS

#: The acceptance target of issue 11: the live viewer keeps up with the 240 Hz array.
TARGET_FRAMES_S = 240.0


def _frames(n: int) -> tuple[np.ndarray, np.ndarray, float]:
    chunks, times, t0, seed = [], [], 0.0, 0
    while sum(c.shape[0] for c in chunks) < n:
        name = SCENARIO_NAMES[seed % len(SCENARIO_NAMES)]
        rec = frames_from_scenario(BONNEVILLE_16X16, make_scenario(name, rng=seed), rng=seed)
        chunks.append(np.asarray(rec.frames))
        times.append(np.asarray(rec.t_s) - rec.t_s[0] + t0)
        t0 = float(times[-1][-1]) + 1.0
        seed += 1
    return np.concatenate(chunks)[:n], np.concatenate(times)[:n], rec.pitch_mm


def _stream(frames: np.ndarray, t_s: np.ndarray, pitch_mm: float, view: RerunView | None) -> int:
    sensor = SmartSensor(frames.shape[1:], pitch_mm=pitch_mm)
    n_events = 0
    for k in range(frames.shape[0]):
        t = float(t_s[k])
        events = sensor.push(frames[k], t)
        n_events += len(events)
        if view is not None:
            view.log_frame(k, t, frames[k], sensor.classes[-1])
            view.log_events(events, t)
    if view is not None:
        view.close()
    return n_events


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=10_000)
    add_record_option(parser)
    args = parser.parse_args()
    frames, t_s, pitch = _frames(args.frames)
    start = time.perf_counter()
    events = _stream(frames, t_s, pitch, None)
    alone = args.frames / (time.perf_counter() - start)
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "bench.rrd"
        start = time.perf_counter()
        _stream(frames, t_s, pitch, RerunView(save_path=out))
        viewed = args.frames / (time.perf_counter() - start)
        size_mb = out.stat().st_size / 1e6
        capture = Path(folder) / "capture.bin"
        capture.write_bytes(
            b"".join(
                encode_frame(f.astype(np.float32), index=k, t_s=float(t))
                for k, (f, t) in enumerate(zip(frames, t_s, strict=True))
            )
        )
        live = {}
        for label, view in (("live", None), ("live+view", Path(folder) / "live.rrd")):
            lines: list[str] = []
            start = time.perf_counter()
            recognize_live(f"file:{capture}", pitch_mm=pitch, echo=lines.append, save_view=view)
            live[label] = args.frames / (time.perf_counter() - start)
            summary = lines[-1]
        printed = sum(line.split()[4] in VERDICT_KINDS for line in lines[:-1])
        logged = _verdicts_in(Path(folder) / "live.rrd")
    print(f"frames: {args.frames} (16 x 16), events: {events}")
    print(f"smart sensor alone:        {alone:10.0f} frames/s (baseline, same run)")
    print(f"with the rerun view (rrd): {viewed:10.0f} frames/s ({viewed / alone:.2f} x baseline)")
    print(f".rrd size: {size_mb:.1f} MB")
    print(f"recognize --live file:     {live['live']:10.0f} frames/s")
    print(
        f"recognize --live file: --save-view: {live['live+view']:10.0f} frames/s "
        f"({live['live+view'] / live['live']:.2f} x live without view)"
    )
    print(f"last line: {summary}")
    met = "met" if live["live+view"] >= TARGET_FRAMES_S else "NOT met"
    print(f"target >= {TARGET_FRAMES_S:g} frames/s with the view: {met}")
    print(f"verdicts printed: {printed}; in the .rrd: {logged} (+1 'result:' line expected)")
    if args.record:
        record(
            __file__,
            figure=(
                f"`recognize --live file: --save-view` on {args.frames:,} frames of rolls: "
                f"{live['live+view']:,.0f} frames/s (target >= {TARGET_FRAMES_S:g}: {met}); "
                f"{logged} verdicts in the .rrd for {printed} printed (+1 'result:' line); "
                f"SmartSensor with the rerun view {viewed:,.0f} frames/s, .rrd {size_mb:.1f} MB"
            ),
            ratio=(
                f"{live['live+view'] / live['live']:.2f}x the live path without the view; "
                f"{viewed / alone:.2f}x the smart sensor alone"
            ),
            measured={
                "frames": args.frames,
                "alone_fps": round(alone, 1),
                "viewed_fps": round(viewed, 1),
                "live_fps": round(live["live"], 1),
                "live_view_fps": round(live["live+view"], 1),
                "rrd_mb": round(size_mb, 2),
                "verdicts_printed": printed,
                "verdicts_logged": logged,
            },
        )


def _verdicts_in(rrd: Path) -> int:
    """Rows logged under ``sensor/verdicts`` in an ``.rrd`` file."""
    from rerun.chunk import RrdReader

    return sum(
        chunk.num_rows
        for chunk in RrdReader(rrd).stream().to_chunks()
        if chunk.entity_path.lstrip("/") == ENTITY_PATHS["verdicts"]
    )


if __name__ == "__main__":
    main()
