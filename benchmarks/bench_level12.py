"""Throughput of the smart sensor's Level 1 statistics and Level 2 classes (paper 001).

Seeded random 16 x 16 contact images (blobs of 0-60 taxels, some empty) are
processed by

* ``batched``: :func:`taxelkit.smart.image_stats` on all frames at once (matrix
  products against coordinate vectors), then
  :func:`taxelkit.smart.classify_contacts`;
* ``per-frame``: :func:`taxelkit.smart.frame_stats` called once per frame,
  the streaming path (a batch of one through the same kernel);
* ``skimage per frame``: ``skimage.measure.regionprops`` once per frame (area,
  centroid, orientation, inertia eigenvalues), when scikit-image is installed
  (measured on a subset and extrapolated);
* ``skimage batch``: ``regionprops_table`` once for a batch of frames stacked
  into one label image (one label per frame): the best scikit-image allows;
* ``NumPy einsum batch``: the same moments as a NumPy user would write them
  for the whole batch (``benchmarks/_baselines.py``).

The per-frame results are checked to be identical to the batched ones.

Usage: ``python benchmarks/bench_level12.py [--frames 100000] [--repeat 3]``.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"  # one core, so the ratios compare algorithms, not threads

import argparse  # noqa: E402
import importlib.util  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

from _baselines import numpy_moments, skimage_moments  # noqa: E402
from _record import add_record_option, record  # noqa: E402
from taxelkit.sensors.presets import BONNEVILLE_16X16  # noqa: E402
from taxelkit.smart import classify_contacts, frame_stats, image_stats  # noqa: E402

PITCH_MM = BONNEVILLE_16X16.array.pitch_mm
HAVE_SKIMAGE = importlib.util.find_spec("skimage") is not None


def random_contacts(rng: np.random.Generator, n: int) -> np.ndarray:
    """Thresholded smooth random fields: compact and elongated blobs, ~5 % empty."""
    rows, cols = BONNEVILLE_16X16.array.shape
    i, j = np.mgrid[0:rows, 0:cols]
    c = rng.uniform(4, 11, size=(n, 2, 1, 1))
    ang = rng.uniform(0, np.pi, size=(n, 1, 1))
    a = rng.uniform(0.5, 6.0, size=(n, 1, 1))
    b = rng.uniform(0.5, 2.5, size=(n, 1, 1))
    u = (j - c[:, 1]) * np.cos(ang) + (i - c[:, 0]) * np.sin(ang)
    v = -(j - c[:, 1]) * np.sin(ang) + (i - c[:, 0]) * np.cos(ang)
    img = (u / a) ** 2 + (v / b) ** 2 <= 1.0
    img[rng.random(n) < 0.05] = False
    return img


def best_of(fn: Callable[[], Any], repeat: int) -> float:
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return float(best)


def per_frame(images: np.ndarray) -> list[Any]:
    return [frame_stats(f, pitch_mm=PITCH_MM) for f in images]


def skimage_per_frame(images: np.ndarray) -> list[Any]:
    from skimage.measure import regionprops

    out: list[Any] = []
    for f in images:
        props = regionprops(f.astype(np.uint8))
        if props:
            p = props[0]
            out.append((p.area, p.centroid, p.orientation, p.inertia_tensor_eigvals))
        else:
            out.append(None)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    ap.add_argument("--frames", type=int, default=100_000)
    ap.add_argument("--loop-frames", type=int, default=5_000, help="subset for the loops")
    ap.add_argument("--repeat", type=int, default=3)
    add_record_option(ap)
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    images = random_contacts(rng, args.frames)
    subset = images[: args.loop_frames]

    stats = image_stats(images, pitch_mm=PITCH_MM)
    loop = per_frame(subset)
    for t, s in enumerate(loop):
        ref = stats.frame(t)
        a = [s.area_mm2, *s.centre_mm, s.orientation_deg, s.elongation]
        b = [ref.area_mm2, *ref.centre_mm, ref.orientation_deg, ref.elongation]
        np.testing.assert_array_equal(a, b)

    t_stats = best_of(lambda: image_stats(images, pitch_mm=PITCH_MM), args.repeat)
    t_class = best_of(lambda: classify_contacts(stats), args.repeat)
    t_loop = best_of(lambda: per_frame(subset), 1) * args.frames / len(subset)
    rows: list[tuple[str, float]] = [
        ("batched stats", t_stats),
        ("batched classes", t_class),
        ("batched both", t_stats + t_class),
        ("per-frame stats", t_loop),
    ]
    t_numpy = best_of(lambda: numpy_moments(images), args.repeat)
    rows.append(("NumPy einsum batch", t_numpy))
    if HAVE_SKIMAGE:
        t_sk = best_of(lambda: skimage_per_frame(subset), 1) * args.frames / len(subset)
        rows.append(("skimage per frame", t_sk))
        t_skb = best_of(lambda: skimage_moments(images[: 4 * len(subset)]), 1)
        rows.append(("skimage batch", t_skb * args.frames / min(args.frames, 4 * len(subset))))

    print(f"{args.frames} random 16 x 16 contact images, 1 thread (loops timed on {len(subset)})")
    header = (
        f"{'path':<20} {'time s':>9} {'frames/s':>12} {'vs per-frame':>13} "
        f"{'batched both vs it':>19}"
    )
    print(header)
    print("-" * len(header))
    both = t_stats + t_class
    for name, t in rows:
        print(
            f"{name:<20} {t:>9.3f} {args.frames / t:>12.0f} {t_loop / t:>12.1f}x {t / both:>18.1f}x"
        )
    counts = np.bincount(classify_contacts(stats), minlength=5)
    print("classes (none, indeterminate, point, line, area):", counts.tolist())
    if args.record:
        times = dict(rows)
        rate = args.frames / both
        ratio = f"{t_numpy / both:.1f}x batched NumPy `einsum` moments"
        if "skimage batch" in times:
            sk = times["skimage batch"] / both
            ratio += f", {sk:.0f}x scikit-image `regionprops_table` over the batch"
        record(
            __file__,
            figure=f"Levels 1-2 on random 16 x 16 images: {rate / 1e6:.1f} M frames/s",
            ratio=ratio,
            measured={"frames": args.frames, **{k: round(v, 6) for k, v in times.items()}},
        )


if __name__ == "__main__":
    main()
