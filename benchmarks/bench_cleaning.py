"""Cost of the image cleaning against Levels 1-4 of the smart sensor, batch, 240 frames/s.

Frames come from randomised rolls of all six objects at the Bonneville
array's maximum rate (240 frames/s), seen through every sensor imperfection
at once (``fault_model("all")``: threshold spread, drift, crosstalk, flicker,
dead and stuck taxels). Prints, in the same run:

* cleaning: :func:`taxelkit.smart.cleaning.clean_images` on the whole stream;
* Levels 1-4: :func:`taxelkit.smart.recogniser.recognise` with cleaning off
  (``cleaning=None``) on the same images: the baseline;
* the ratio cleaning / Levels 1-4 (the target: below 2);
* streaming: :class:`taxelkit.smart.cleaning.ImageCleaner`, one frame per call.

Usage: ``python benchmarks/bench_cleaning.py [--scenarios N] [--repeat N]``.
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from _record import add_record_option, record  # noqa: E402
from _rolls import roll_images  # noqa: E402
from taxelkit.frames import TactileFrames  # noqa: E402
from taxelkit.sensors import BONNEVILLE_16X16  # noqa: E402
from taxelkit.smart.cleaning import clean_images  # noqa: E402
from taxelkit.smart.cleaning_stream import ImageCleaner  # noqa: E402
from taxelkit.smart.recogniser import recognise  # noqa: E402


def best_of(repeat: int, fn: object) -> float:
    """Fastest of ``repeat`` timed calls, s."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()  # type: ignore[operator]
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenarios", type=int, default=36)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--stream-frames", type=int, default=20_000)
    add_record_option(ap)
    args = ap.parse_args()
    sensor = BONNEVILLE_16X16
    images = np.concatenate(roll_images(args.scenarios, faults=True))
    t_s = np.arange(images.shape[0]) / sensor.max_rate_hz
    n = images.shape[0]
    cleaned = clean_images(images, t_s)
    rec = TactileFrames(cleaned, t_s, pitch_mm=sensor.array.pitch_mm)
    t_clean = best_of(args.repeat, lambda: clean_images(images, t_s))
    t_levels = best_of(args.repeat, lambda: recognise(rec, cleaning=None))
    print(f"frames: {n:,} of {images.shape[1]} x {images.shape[2]} at 240 frames/s, faults 'all'")
    print(f"cleaning (batch):   {n / t_clean:12,.0f} frames/s  ({1e3 * t_clean:.1f} ms)")
    print(f"Levels 1-4 (batch): {n / t_levels:12,.0f} frames/s  ({1e3 * t_levels:.1f} ms)")
    print(f"ratio cleaning / Levels 1-4: {t_clean / t_levels:.2f} (target < 2)")
    m = min(args.stream_frames, n)
    cleaner = ImageCleaner(images.shape[1:])
    t0 = time.perf_counter()
    for img, t in zip(images[:m], t_s[:m], strict=True):
        cleaner.push(img, float(t))
    t_stream = time.perf_counter() - t0
    print(f"cleaning (streaming, one frame a call): {m / t_stream:,.0f} frames/s")
    if args.record:
        record(
            __file__,
            figure="image cleaning, 240 Hz rolls through every imperfection: batch "
            f"{n / t_clean:,.0f} frames/s, streaming {m / t_stream:,.0f} frames/s",
            ratio=f"{t_clean / t_levels:.2f}x the Levels 1-4 batch time of the same run "
            "(target < 2x)",
            measured={"frames": n, "clean_s": t_clean, "levels_s": t_levels, "stream_s": t_stream},
        )


if __name__ == "__main__":
    main()
