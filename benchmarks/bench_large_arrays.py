"""Cost per taxel of Levels 1-2 (and of the image cleaning) from 16 x 16 to 128 x 128 arrays.

For each array size, seeded elliptical contact blobs (scaled with the array,
drifting slowly from frame to frame, some frames empty) are processed in
batch, about the same number of taxels for every size, on one core:

* Levels 1-2: :func:`taxelkit.smart.image_stats` then
  :func:`taxelkit.smart.classify_contacts`;
* cleaning: :func:`taxelkit.smart.cleaning.clean_images` (packed rows up to
  64 columns, bool arrays beyond);
* baseline: the same Level 1 moments as a NumPy user would write them
  (``einsum`` over the whole batch, float64; ``benchmarks/_baselines.py``),
  and scikit-image's ``regionprops_table`` over the stacked batch (on a subset).

Prints nanoseconds per taxel, the ratio to 16 x 16 (target: Levels 1-2 within
2x up to 128 x 128) and the ratio to the baselines.

Usage: ``python benchmarks/bench_large_arrays.py [--taxels 50000000] [--repeat 3]``.
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

from _baselines import numpy_moments, skimage_moments  # noqa: E402
from _record import add_record_option, record  # noqa: E402
from taxelkit.smart import classify_contacts, image_stats  # noqa: E402
from taxelkit.smart.cleaning import clean_images  # noqa: E402

SIZES = (16, 32, 64, 128)
HAVE_SKIMAGE = importlib.util.find_spec("skimage") is not None


def drifting_blobs(rng: np.random.Generator, n_frames: int, size: int) -> np.ndarray:
    """Elliptical contacts whose centre, axes and angle drift; 10 % of frames empty."""
    i, j = np.mgrid[0:size, 0:size]
    scale = size / 16.0
    steps = rng.normal(0.0, 0.05, size=(n_frames, 5)).cumsum(axis=0)
    c = size / 2 + scale * 3.0 * np.sin(steps[:, :2])
    a = scale * (3.5 + 2.5 * np.sin(steps[:, 2]))
    b = scale * (1.5 + 1.0 * np.sin(steps[:, 3]))
    ang = steps[:, 4]
    cos, sin = np.cos(ang)[:, None, None], np.sin(ang)[:, None, None]
    du, dv = j - c[:, 1, None, None], i - c[:, 0, None, None]
    u, v = du * cos + dv * sin, -du * sin + dv * cos
    img = (u / a[:, None, None]) ** 2 + (v / b[:, None, None]) ** 2 <= 1.0
    img[: n_frames // 20] = False  # the stream starts out of contact
    img[rng.random(n_frames) < 0.1] = False
    return img


def best_of(fn: Callable[[], Any], repeat: int) -> float:
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return float(best)


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--taxels", type=int, default=50_000_000, help="taxels per size")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--skimage-frames", type=int, default=2_000)
    add_record_option(ap)
    args = ap.parse_args()
    rows = []
    for size in SIZES:
        n_frames = max(100, args.taxels // (size * size))
        images = drifting_blobs(np.random.default_rng(size), n_frames, size)
        t_s = np.arange(n_frames) / 240.0
        taxels = images.size

        def levels12(images: np.ndarray = images) -> None:
            classify_contacts(image_stats(images, pitch_mm=1.0))

        t12 = best_of(levels12, args.repeat)
        t_clean = best_of(lambda images=images, t_s=t_s: clean_images(images, t_s), args.repeat)
        t_np = best_of(lambda images=images: numpy_moments(images), args.repeat)
        t_sk = float("nan")
        if HAVE_SKIMAGE:
            pick = np.linspace(0, n_frames - 1, min(n_frames, args.skimage_frames)).astype(int)
            sub = images[pick]  # spread over the stream: its first frames are empty
            t_sk = best_of(lambda sub=sub: skimage_moments(sub), 1) * n_frames / sub.shape[0]
        rows.append((size, n_frames, *(1e9 * t / taxels for t in (t12, t_clean, t_np, t_sk))))
    print(f"Levels 1-2 and cleaning in batch, ~{args.taxels:,} taxels per size, one core")
    print(
        f"{'array':>9} {'frames':>9} {'L1-2 ns/taxel':>14} {'vs 16x16':>9} "
        f"{'clean ns/taxel':>15} {'vs 16x16':>9} {'NumPy einsum':>13} {'skimage':>9} "
        f"{'L1-2 vs NumPy':>14} {'vs skimage':>11}"
    )
    base12, base_clean = rows[0][2], rows[0][3]
    for size, n_frames, c12, c_clean, c_np, c_sk in rows:
        print(
            f"{size:>4} x {size:<3} {n_frames:>9,} {c12:>14.2f} {c12 / base12:>8.2f}x "
            f"{c_clean:>15.2f} {c_clean / base_clean:>8.2f}x {c_np:>13.2f} {c_sk:>9.1f} "
            f"{c_np / c12:>13.1f}x {c_sk / c12:>10.1f}x"
        )
    worst = max(r[2] for r in rows) / base12
    print(f"Levels 1-2 worst cost per taxel / 16 x 16: {worst:.2f}x (target <= 2x)")
    if args.record:
        sizes = ", ".join(f"{r[2]:.2f}{' ns' if k == 0 else ''} ({r[0]} x {r[0]})"
                          for k, r in enumerate(rows))  # fmt: skip
        cleaning = ", ".join(f"{r[3]:.1f}" for r in rows)
        vs_np = [r[4] / r[2] for r in rows]
        last = rows[-1]
        record(
            __file__,
            figure=f"Levels 1-2 per taxel: {sizes}; cleaning {cleaning} ns",
            ratio=f"{min(vs_np):.1f}x-{max(vs_np):.1f}x batched NumPy moments; "
            f"{last[0]} x {last[0]} costs {last[2] / base12:.2f}x (cleaning "
            f"{last[3] / base_clean:.2f}x) of 16 x 16 per taxel (target <= 2x)",
            measured={
                f"{r[0]}x{r[0]}": {
                    "frames": r[1],
                    "levels12_ns": r[2],
                    "cleaning_ns": r[3],
                    "numpy_ns": r[4],
                    "skimage_ns": r[5],
                }
                for r in rows
            },
        )


if __name__ == "__main__":
    main()
