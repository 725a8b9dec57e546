"""Throughput of 6 x 6 displacement frames over a relief specimen (paper 000 sensor).

Prints frames per second of the batched simulator and of baselines measured
in the same run:

* ``shapely contains_xy`` (the baseline): shapely's vectorised point-in-polygon
  test on a prepared polygon, one call for every sample point of every pose,
  then the same box average and skin model: the best a shapely user would write;
* ``per-frame call``: the same vectorised code called once per frame;
* ``per-point shapely``: the straightforward approach, one shapely
  ``contains`` query per sample point, one frame at a time (measured on a
  small subset and extrapolated).

Usage: ``python benchmarks/bench_relief.py [--poses N] [--shape star]``.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"  # one core, as the target says

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
import shapely  # noqa: E402

from _record import add_record_option, record  # noqa: E402
from taxelkit.sensors.presets import OPTICAL_3AXIS  # noqa: E402
from taxelkit.sensors.press import displacement_from_relief, sample_offsets_mm  # noqa: E402
from taxelkit.sensors.skin import (  # noqa: E402
    coupling_margin_taxels,
    displacement_from_penetration,
)
from taxelkit.world.relief import relief_shape  # noqa: E402


def _best_of(fn, repeat: int) -> float:  # type: ignore[no-untyped-def]
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return float(best)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--poses", type=int, default=20_000)
    ap.add_argument("--shape", default="star")
    ap.add_argument("--oversample", type=int, default=3)
    ap.add_argument("--repeat", type=int, default=3)
    add_record_option(ap)
    args = ap.parse_args()

    sensor = OPTICAL_3AXIS
    relief = relief_shape(args.shape, diameter_mm=90.0, step_height_um=200.0)
    rng = np.random.default_rng(0)
    angle = rng.uniform(0, 2 * np.pi, args.poses)
    radius = rng.uniform(10, 45, args.poses)
    pos = np.stack([radius * np.cos(angle), radius * np.sin(angle)], axis=1)
    kw = {"indent_mm": 0.1, "oversample": args.oversample, "active_only": True, "rng": 1}

    def batched() -> None:
        displacement_from_relief(sensor, relief, pos, **kw)

    n_loop = min(args.poses, 2000)

    def per_frame() -> None:
        for k in range(n_loop):
            displacement_from_relief(sensor, relief, pos[k : k + 1], **kw)

    # Straightforward baseline: one shapely point-in-polygon call per sample point.
    poly = shapely.Polygon(relief.outline_mm())
    margin = coupling_margin_taxels(sensor.skin, sensor.array.pitch_mm)
    xs, ys = sample_offsets_mm(sensor.array, margin=margin, oversample=args.oversample)
    block = sensor.array.active_region
    n = args.oversample
    xs = xs[block.col0 * n : (block.col0 + block.cols + 2 * margin) * n]
    ys = ys[block.row0 * n : (block.row0 + block.rows + 2 * margin) * n]
    step = relief.step_height_mm
    n_naive = min(args.poses, 20)

    def per_point() -> None:
        for k in range(n_naive):
            pen = np.empty((ys.size, xs.size))
            for i, y in enumerate(ys):
                for j, x in enumerate(xs):
                    inside = poly.contains(shapely.Point(pos[k, 0] + x, pos[k, 1] + y))
                    pen[i, j] = 0.1 + (step if inside else 0.0)
            pen = pen.reshape(ys.size // n, n, xs.size // n, n).mean(axis=(1, 3))
            displacement_from_penetration(pen, pitch_mm=sensor.array.pitch_mm, skin=sensor.skin)

    # The best a shapely user would write: one vectorised contains_xy call for the
    # sample points of all poses at once (prepared polygon), then the same skin model.
    shapely.prepare(poly)
    gx, gy = np.meshgrid(xs, ys)

    def shapely_vectorised() -> None:
        inside = shapely.contains_xy(
            poly, pos[:, 0, None, None] + gx[None], pos[:, 1, None, None] + gy[None]
        )
        pen = 0.1 + step * inside
        pen = pen.reshape(-1, ys.size // n, n, xs.size // n, n).mean(axis=(2, 4))
        displacement_from_penetration(pen, pitch_mm=sensor.array.pitch_mm, skin=sensor.skin)

    t_batch = _best_of(batched, args.repeat) / args.poses
    t_vector = _best_of(shapely_vectorised, args.repeat) / args.poses
    t_frame = _best_of(per_frame, 1) / n_loop
    t_point = _best_of(per_point, 1) / n_naive
    print(f"relief frames: {args.shape}, 6 x 6 active block, oversample {n}, one core")
    print(f"{'method':34s} {'frames/s':>12s} {'batched speed-up':>18s}")
    print(f"{'batched (taxelkit)':34s} {1 / t_batch:12,.0f} {'1.0 x':>18s}")
    print(
        f"{'shapely contains_xy, all (baseline)':34s} {1 / t_vector:12,.0f} "
        f"{t_vector / t_batch:16.1f} x"
    )
    print(f"{'per-frame call':34s} {1 / t_frame:12,.0f} {t_frame / t_batch:16.1f} x")
    print(f"{'per-point shapely (naive)':34s} {1 / t_point:12,.0f} {t_point / t_batch:16.0f} x")
    if args.record:
        faster = " (shapely is faster)" if t_vector < t_batch else ""
        record(
            __file__,
            figure=f"6 x 6 relief frames: {1 / t_batch:,.0f}/s",
            ratio=f"{t_vector / t_batch:.1f}x shapely's vectorised `contains_xy` over every "
            f"sample point at once{faster}; {t_frame / t_batch:.1f}x per-frame calls, "
            f"{t_point / t_batch:.0f}x shapely per point",
            measured={
                "batched_s": t_batch,
                "shapely_vectorised_s": t_vector,
                "per_frame_s": t_frame,
                "per_point_s": t_point,
                "poses": args.poses,
            },
        )


if __name__ == "__main__":
    main()
