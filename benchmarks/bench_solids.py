"""Throughput of 16 x 16 contact frames from the analytic solids, against per-frame baselines.

For each solid of paper 001 (and for a mix of all six) the script draws N
seeded random poses (uniform rotations, positions within +-5 mm, indentation
0.05-0.5 mm) and measures, on one core:

* ``batched``: :func:`taxelkit.sensors.press.displacement_from_solid` on the
  Bonneville 16 x 16 array followed by ``contact_from_displacement``, without
  and with the sensor's noise model;
* ``geometry``: ``solid.bottom_mm`` alone on the same 20 x 20 sample grid;
* ``ray``: a straightforward per-frame baseline on the tessellated body
  (``solid.to_trimesh()``): one upward ray per sample point, first hit =
  bottom, then the same skin model and threshold. trimesh's ray module is used
  when its ``rtree`` dependency is installed; otherwise the rays are cast with
  a vectorised per-frame barycentric test (rays are vertical). Measured on a
  small subset and extrapolated;
* ``rays`` (the baseline, with ``rtree``): the same ray casting as a trimesh
  user would batch it, every ray of every pose of a body in one
  ``intersects_location`` call (rays sent into the body frame);
* ``per-call``: ``displacement_from_solid`` called once per frame (P = 1);
* ``normal``: NumPy's normal generator alone, drawing one float32 16 x 16
  frame of noise per pose as the noise model does (the cost of ``+noise``).

Times are CPU seconds of this process (``time.process_time``, best of
``--repeat``), so that other work on a shared machine does not count.

It also checks that the ray-cast baseline and the batched path give the same
contact images (fraction of equal taxels, expected > 99 %: they differ only by
the tessellation's sagitta).

Run ``python benchmarks/bench_solids.py --help`` for options; ``--record`` writes
the README row (``docs/results/bench/bench_solids.json``).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import importlib.util  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

from _record import add_record_option, record  # noqa: E402
from taxelkit.sensors.presets import BONNEVILLE_16X16, Sensor  # noqa: E402
from taxelkit.sensors.press import displacement_from_solid, sample_offsets_mm  # noqa: E402
from taxelkit.sensors.skin import (  # noqa: E402
    coupling_margin_taxels,
    displacement_from_penetration,
)
from taxelkit.world.pose import matrix_from_axis_angle  # noqa: E402
from taxelkit.world.solids import SOLID_NAMES, make_solid  # noqa: E402

HAVE_RTREE = importlib.util.find_spec("rtree") is not None


def random_poses(rng: np.random.Generator, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Uniform random rotations, positions within +-5 mm, indentations 0.05-0.5 mm."""
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    rot = matrix_from_axis_angle(q[:, :3], 2.0 * np.arccos(np.clip(q[:, 3], -1.0, 1.0)))
    return rot, rng.uniform(-5.0, 5.0, size=(n, 2)), rng.uniform(0.05, 0.5, size=n)


def best_time(fn: Callable[[], Any], repeat: int) -> float:
    """Smallest CPU time of ``repeat`` runs, s (this process only)."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.process_time()
        fn()
        best = min(best, time.process_time() - t0)
    return best


def _vertical_ray_bottom(tri: np.ndarray, px: np.ndarray, py: np.ndarray) -> np.ndarray:
    """Lowest hit of upward vertical rays at (px, py) with triangles (T, 3, 3), or inf."""
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    det = (b[:, 1] - c[:, 1]) * (a[:, 0] - c[:, 0]) + (c[:, 0] - b[:, 0]) * (a[:, 1] - c[:, 1])
    ok = np.abs(det) > 1e-12
    a, b, c, det = a[ok], b[ok], c[ok], det[ok]
    x, y = px[:, None], py[:, None]
    l1 = ((b[:, 1] - c[:, 1]) * (x - c[:, 0]) + (c[:, 0] - b[:, 0]) * (y - c[:, 1])) / det
    l2 = ((c[:, 1] - a[:, 1]) * (x - c[:, 0]) + (a[:, 0] - c[:, 0]) * (y - c[:, 1])) / det
    l3 = 1.0 - l1 - l2
    z = l1 * a[:, 2] + l2 * b[:, 2] + l3 * c[:, 2]
    hit = (l1 >= 0) & (l2 >= 0) & (l3 >= 0)
    return np.where(hit, z, np.inf).min(axis=1)


def _trimesh_ray_bottom(mesh: Any, rot: np.ndarray, px: np.ndarray, py: np.ndarray) -> np.ndarray:
    """First hits through trimesh's ray module (needs rtree), rays sent in the body frame."""
    origins = np.stack([px, py, np.full(px.shape, -100.0)], axis=1) @ rot  # R^T p
    directions = np.tile(rot[2], (px.size, 1))  # R^T e_z
    loc, index_ray, _ = mesh.ray.intersects_location(origins, directions, multiple_hits=False)
    out = np.full(px.size, np.inf)
    out[index_ray] = (loc @ rot.T)[:, 2]
    return out


def _trimesh_ray_bottom_batch(
    mesh: Any, rot: np.ndarray, px: np.ndarray, py: np.ndarray
) -> np.ndarray:
    """First hits for many poses in one trimesh call: ``rot`` (P, 3, 3), ``px``, ``py`` (P, S)."""
    p, n = px.shape
    world = np.stack([px, py, np.full(px.shape, -100.0)], axis=2)  # (P, S, 3)
    origins = np.einsum("psj,pjk->psk", world, rot).reshape(-1, 3)  # R^T p, per pose
    directions = np.repeat(rot[:, 2, :], n, axis=0)  # R^T e_z
    loc, index_ray, _ = mesh.ray.intersects_location(origins, directions, multiple_hits=False)
    pose = index_ray // n
    out = np.full(p * n, np.inf)
    out[index_ray] = np.einsum("rk,rk->r", loc, rot[pose, 2, :])  # back to world z
    return out.reshape(p, n)


def batched_ray_frames(
    sensor: Sensor,
    meshes: list[Any],
    which: np.ndarray,
    rot: np.ndarray,
    pos: np.ndarray,
    indent: np.ndarray,
) -> np.ndarray:
    """Ray casting as a trimesh user would batch it: all rays of all poses of a body at once."""
    margin = coupling_margin_taxels(sensor.skin, sensor.array.pitch_mm)
    xs, ys = sample_offsets_mm(sensor.array, margin=margin, oversample=1)
    gx, gy = np.meshgrid(xs, ys)
    frames = np.empty((rot.shape[0], *sensor.array.shape), dtype=bool)
    for k, mesh in enumerate(meshes):
        sel = np.flatnonzero(which == k)
        if sel.size == 0:
            continue
        px = gx.ravel()[None, :] - pos[sel, :1]
        py = gy.ravel()[None, :] - pos[sel, 1:]
        bottom = _trimesh_ray_bottom_batch(mesh, rot[sel], px, py)
        lowest = np.einsum("vk,pk->pv", np.asarray(mesh.vertices), rot[sel, 2, :]).min(axis=1)
        pen = np.maximum(indent[sel, None] + lowest[:, None] - bottom, 0.0).reshape(
            sel.size, *gx.shape
        )
        u = displacement_from_penetration(pen, pitch_mm=sensor.array.pitch_mm, skin=sensor.skin)
        frames[sel] = sensor.contact_from_displacement(u)
    return frames


def baseline_frames(
    sensor: Sensor,
    meshes: list[Any],
    which: np.ndarray,
    rot: np.ndarray,
    pos: np.ndarray,
    indent: np.ndarray,
) -> np.ndarray:
    """Per-frame ray casting on the tessellated bodies, then the same skin and threshold."""
    margin = coupling_margin_taxels(sensor.skin, sensor.array.pitch_mm)
    xs, ys = sample_offsets_mm(sensor.array, margin=margin, oversample=1)
    gx, gy = np.meshgrid(xs, ys)
    frames = np.empty((rot.shape[0], *sensor.array.shape), dtype=bool)
    for i in range(rot.shape[0]):
        mesh = meshes[which[i]]
        px, py = gx.ravel() - pos[i, 0], gy.ravel() - pos[i, 1]
        if HAVE_RTREE:
            bottom = _trimesh_ray_bottom(mesh, rot[i], px, py)
        else:
            bottom = _vertical_ray_bottom(np.asarray(mesh.triangles) @ rot[i].T, px, py)
        lowest = (np.asarray(mesh.vertices) @ rot[i][2]).min()
        pen = np.maximum(indent[i] + lowest - bottom, 0.0).reshape(1, *gx.shape)
        u = displacement_from_penetration(pen, pitch_mm=sensor.array.pitch_mm, skin=sensor.skin)
        frames[i] = sensor.contact_from_displacement(u)[0]
    return frames


def batched_frames(
    sensor: Sensor,
    solids: list[Any],
    which: np.ndarray,
    rot: np.ndarray,
    pos: np.ndarray,
    indent: np.ndarray,
    *,
    noise: bool,
    seed: int,
) -> np.ndarray:
    """Contact frames through the batched simulator, one call per solid present."""
    frames = np.empty((rot.shape[0], *sensor.array.shape), dtype=bool)
    for k, solid in enumerate(solids):
        sel = np.flatnonzero(which == k)
        if sel.size == 0:
            continue
        u = displacement_from_solid(
            sensor, solid, rot[sel], pos[sel], indent_mm=indent[sel], add_noise=noise, rng=seed
        )
        frames[sel] = sensor.contact_from_displacement(u)
    return frames


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and print a table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--poses", type=int, default=10_000, help="poses per solid (batched)")
    parser.add_argument("--repeat", type=int, default=3, help="timing repeats (best is kept)")
    parser.add_argument(
        "--baseline-frames", type=int, default=50, help="frames for the per-frame baselines"
    )
    parser.add_argument("--seed", type=int, default=0)
    add_record_option(parser)
    args = parser.parse_args(argv)
    sensor = BONNEVILLE_16X16
    rng = np.random.default_rng(args.seed)
    solids = [make_solid(name) for name in SOLID_NAMES]
    meshes = [s.to_trimesh() for s in solids]
    margin = coupling_margin_taxels(sensor.skin, sensor.array.pitch_mm)
    xs, ys = sample_offsets_mm(sensor.array, margin=margin, oversample=1)
    n, nb = args.poses, min(args.baseline_frames, args.poses)
    print(
        f"{n} poses per case, best of {args.repeat}; sample grid {ys.size} x {xs.size}; "
        f"baseline on {nb} frames, rays by "
        + ("trimesh (rtree)" if HAVE_RTREE else "per-frame numpy barycentric test (no rtree)")
    )
    header = (
        f"{'solid':<15}{'batched':>11}{'+noise':>11}{'geometry':>11}{'ray':>9}{'rays':>10}"
        f"{'per-call':>10}{'batched/ray':>13}{'batched/rays':>13}{'batched/call':>14}{'agree':>9}"
    )
    print(header)
    print("-" * len(header))
    cases = [(name, np.full(n, k)) for k, name in enumerate(SOLID_NAMES)]
    cases.append(("mix", rng.integers(0, len(solids), size=n)))
    rows: dict[str, dict[str, float]] = {}
    for name, which in cases:
        rot, pos, indent = random_poses(rng, n)

        def run(
            noise: bool,
            which: np.ndarray = which,
            rot: np.ndarray = rot,
            pos: np.ndarray = pos,
            indent: np.ndarray = indent,
        ) -> np.ndarray:
            return batched_frames(
                sensor, solids, which, rot, pos, indent, noise=noise, seed=args.seed
            )

        fps = n / best_time(lambda: run(False), args.repeat)
        fps_noise = n / best_time(lambda: run(True), args.repeat)

        def geometry(
            which: np.ndarray = which, rot: np.ndarray = rot, pos: np.ndarray = pos
        ) -> None:
            for k, solid in enumerate(solids):
                sel = np.flatnonzero(which == k)
                for a in range(0, sel.size, 2048):
                    s = sel[a : a + 2048]
                    xg = (xs[None, :] - pos[s, :1]).astype(np.float32)
                    yg = (ys[None, :] - pos[s, 1:]).astype(np.float32)
                    solid.bottom_mm(rot[s], xg, yg)

        fps_geo = n / best_time(geometry, args.repeat)
        sub = slice(0, nb)
        t0 = time.process_time()
        base = baseline_frames(sensor, meshes, which[sub], rot[sub], pos[sub], indent[sub])
        fps_ray = nb / (time.process_time() - t0)
        fps_rays = float("nan")
        if HAVE_RTREE:
            t0 = time.process_time()
            rays = batched_ray_frames(sensor, meshes, which[sub], rot[sub], pos[sub], indent[sub])
            fps_rays = nb / (time.process_time() - t0)
            assert np.mean(rays == base) > 0.999  # the same rays, batched

        def per_call(
            which: np.ndarray = which,
            rot: np.ndarray = rot,
            pos: np.ndarray = pos,
            indent: np.ndarray = indent,
        ) -> None:
            for i in range(nb):
                u = displacement_from_solid(
                    sensor,
                    solids[which[i]],
                    rot[i],
                    pos[i],
                    indent_mm=indent[i],
                    add_noise=False,
                )
                sensor.contact_from_displacement(u)

        fps_call = nb / best_time(per_call, 1)
        ours = run(False)[sub]
        agree = float(np.mean(ours == base))
        rows[name] = {
            "batched": fps,
            "noise": fps_noise,
            "geometry": fps_geo,
            "ray": fps_ray,
            "rays": fps_rays,
            "per_call": fps_call,
            "agree": agree,
        }
        print(
            f"{name:<15}{fps:>11,.0f}{fps_noise:>11,.0f}{fps_geo:>11,.0f}{fps_ray:>9,.0f}"
            f"{fps_rays:>10,.0f}{fps_call:>10,.0f}{fps / fps_ray:>13,.0f}"
            f"{fps / fps_rays:>13,.0f}{fps / fps_call:>14,.0f}{100 * agree:>8.2f}%"
        )
    print(
        "frames/s on one core (CPU time); 'agree' = taxels with equal contact in the ray-cast "
        "baseline and the batched path (no noise)"
    )
    # The point/edge dimple of the skin (sensors/skin.py) is extra physics; show its cost.
    from dataclasses import replace

    plain = replace(sensor, skin=replace(sensor.skin, point_dimple=False))
    rot, pos, indent = random_poses(rng, n)
    which = rng.integers(0, len(solids), size=n)

    def run_plain() -> None:
        batched_frames(plain, solids, which, rot, pos, indent, noise=False, seed=args.seed)

    fps_plain = n / best_time(run_plain, args.repeat)
    print(f"mix without the point/edge dimple: {fps_plain:,.0f} frames/s")
    gen = np.random.default_rng(args.seed)
    shape = (n, *sensor.array.shape)
    t_normal = best_time(lambda: gen.standard_normal(shape, dtype=np.float32), args.repeat)
    normal_us = 1e6 * t_normal / n
    print(f"NumPy's normal generator alone: {normal_us:.2f} us per 16 x 16 frame (float32)")
    if args.record:
        record_row(rows, fps_plain, normal_us, args.poses)
    return 0


def record_row(
    rows: dict[str, dict[str, float]], fps_plain: float, normal_us: float, poses: int
) -> None:
    """Write the README row from the figures of this run."""
    mix = rows["mix"]
    per_solid = [v["batched"] for k, v in rows.items() if k != "mix"]
    base = (
        "trimesh ray casting (rtree) with all rays of all poses in one call"
        if HAVE_RTREE
        else "per-frame NumPy ray casting (rtree missing: trimesh's batched rays not timed)"
    )
    ratio_rays = mix["batched"] / (mix["rays"] if HAVE_RTREE else mix["ray"])
    record(
        __file__,
        figure="16 x 16 solid frames, batched, CPU time: "
        f"{mix['batched']:,.0f}/s (mix, noise-free; {mix['noise']:,.0f}/s with noise, NumPy's "
        f"normal generator alone {normal_us:.1f} us a frame; "
        f"{min(per_solid):,.0f}-{max(per_solid):,.0f}/s per solid)",
        ratio=f"{ratio_rays:,.0f}x {base}; {mix['batched'] / mix['per_call']:,.0f}x per-frame "
        "calls",
        measured={
            "poses_per_case": poses,
            "rtree": HAVE_RTREE,
            "frames_s": rows,
            "mix_without_dimple_frames_s": fps_plain,
            "normal_generator_us_per_frame": normal_us,
        },
    )


if __name__ == "__main__":
    raise SystemExit(main())
