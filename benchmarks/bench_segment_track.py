"""Segmentation and tracking throughput on 16 x 16 frames with three objects, batch and streaming.

Frames: three-object scenes of :mod:`taxelkit.motion.multi_scenes` (cube,
cone, cylinder and the rest, kinematic scripts, 20 frames/s, noise on), whose
three 16 x 16 tiles are moved apart along the diagonal by 5 taxels and laid
over one another onto one 16 x 16 array (the largest deflection wins), so
that every frame is 16 x 16 and holds up to three contacts that now and then
touch (merges and splits) or leave the array. Objects of 10-20 mm on a
28 mm array overlap often, so these frames hold fewer than three regions
most of the time (the script prints how many); the same scenes on their
16 x 48 array (three tiles side by side, about three regions a frame) are
timed as well. Thresholded and
cleaned once; the timings below start from the cleaned images. Prints, in the
same run:

* batch: :func:`taxelkit.smart.regions.segment_frames` on the whole stack,
  then :func:`taxelkit.smart.tracks_batch.track_chunk` (the tracker's step on
  the frames where something may happen only), and, beside it, the step on
  every frame (what the batch path did before);
* streaming: segmentation and the step, one frame per call;
* the baseline: scikit-image's ``label`` (8-connectivity) plus
  ``regionprops`` (area and centroid of every region) on each frame, with no
  tracking at all; and the ratios;
* the whole per-track recogniser
  (:func:`taxelkit.smart.objects.recognise_objects`) against the
  single-object :func:`taxelkit.smart.recogniser.recognise` on the same frames.

Times are CPU seconds of this process (``time.process_time``, best of
``--repeat``), so that other work on a shared machine does not count.
scikit-image is in the ``test`` extra; it is imported here only.

Usage: ``python benchmarks/bench_segment_track.py [--scenes N] [--repeat N] [--record]``
(``--record`` writes the README row, ``docs/results/bench/bench_segment_track.json``).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402

import numpy as np  # noqa: E402
from skimage.measure import label, regionprops  # noqa: E402

from _record import add_record_option, record  # noqa: E402
from taxelkit.frames import TactileFrames  # noqa: E402
from taxelkit.motion.multi_scenes import frames_from_multi_scene, multi_scene  # noqa: E402
from taxelkit.smart.cleaning import clean_images  # noqa: E402
from taxelkit.smart.objects import recognise_objects  # noqa: E402
from taxelkit.smart.recogniser import recognise  # noqa: E402
from taxelkit.smart.regions import segment_frames  # noqa: E402
from taxelkit.smart.tacteme_table import OBJECTS  # noqa: E402
from taxelkit.smart.tactemes import TactemeConfig, debounce_counts  # noqa: E402
from taxelkit.smart.tracks import AREA_WEIGHT, RegionTracker  # noqa: E402
from taxelkit.smart.tracks_batch import continuing_frames, track_chunk  # noqa: E402

THRESHOLD_MM = 0.03
PITCH_MM = 28.2 / 16
#: (rows, columns) each tile of a three-object scene is moved by before the overlay.
TILE_SHIFTS = ((-5, -5), (0, 0), (5, 5))


def best_of(repeat: int, fn: Callable[[], object]) -> float:
    """Fastest of ``repeat`` timed calls, CPU seconds of this process."""
    times = []
    for _ in range(repeat):
        t0 = time.process_time()
        fn()
        times.append(time.process_time() - t0)
    return min(times)


def shifted(f: np.ndarray, dr: int, dc: int) -> np.ndarray:
    """Frames moved by ``dr`` rows and ``dc`` columns, zeros shifted in."""
    out = np.zeros_like(f)
    rows, cols = f.shape[1:]
    out[:, max(dr, 0) : rows + min(dr, 0), max(dc, 0) : cols + min(dc, 0)] = f[
        :, max(-dr, 0) : rows + min(-dr, 0), max(-dc, 0) : cols + min(-dc, 0)
    ]
    return out


def overlaid(scenes: int) -> TactileFrames:
    """Three-object scenes folded onto one 16 x 16 array, one scene after the other.

    Tile ``k`` is moved by :data:`TILE_SHIFTS` before the overlay, so that the
    three contacts sit apart (and sometimes touch, or leave the array).
    """
    parts, t0 = [], 0.0
    for k in range(scenes):
        rng = np.random.default_rng(k)
        names = [str(x) for x in rng.choice(OBJECTS, size=3, replace=False)]
        scene = multi_scene(names, rng=rng, max_delay_s=0.0)  # all three down together
        rec = frames_from_multi_scene(scene, rng=rng).recording
        tiles = rec.frames.reshape(rec.n_frames, 16, 3, 16)
        f = np.max(
            [shifted(tiles[:, :, j], dr, dc) for j, (dr, dc) in enumerate(TILE_SHIFTS)], axis=0
        )
        parts.append((f, rec.t_s + t0))
        t0 += float(rec.t_s[-1]) + 0.05
    frames = np.concatenate([p[0] for p in parts])
    t_s = np.concatenate([p[1] for p in parts])
    return TactileFrames(frames, t_s=t_s, pitch_mm=PITCH_MM, units="mm")


def track_batch(images: np.ndarray, t_s: np.ndarray, lost: int) -> int:
    reg = segment_frames(images, pitch_mm=PITCH_MM)
    tracker = RegionTracker(pitch_mm=PITCH_MM, lost_frames=lost)
    track_chunk(tracker, reg, t_s, first_frame=0)
    return tracker.next_id


def track_every_frame(images: np.ndarray, t_s: np.ndarray, lost: int) -> int:
    reg = segment_frames(images, pitch_mm=PITCH_MM)
    tracker = RegionTracker(pitch_mm=PITCH_MM, lost_frames=lost)
    for t in range(images.shape[0]):
        i = reg.in_frame(t)
        tracker.push(
            t,
            float(t_s[t]),
            reg.labels[t],
            i + 1,
            reg.centre_mm[i],
            reg.area_mm2[i],
            reg.taxels_of(i),
        )
    return tracker.next_id


def track_stream(images: np.ndarray, t_s: np.ndarray, lost: int) -> int:
    tracker = RegionTracker(pitch_mm=PITCH_MM, lost_frames=lost)
    for t in range(images.shape[0]):
        reg = segment_frames(images[t : t + 1], pitch_mm=PITCH_MM)
        i = np.arange(reg.n_regions)
        tracker.push(
            t, float(t_s[t]), reg.labels[0], i + 1, reg.centre_mm, reg.area_mm2, reg.taxels_of(i)
        )
    return tracker.next_id


def skimage_per_frame(images: np.ndarray) -> int:
    n = 0
    for frame in images:
        labelled = label(frame, connectivity=2)  # type: ignore[no-untyped-call]
        for r in regionprops(labelled):  # type: ignore[no-untyped-call]
            _ = (r.area, r.centroid)
            n += 1
    return n


def tiled(scenes: int) -> TactileFrames:
    """The same three-object scenes on their 16 x 48 array (three tiles side by side)."""
    parts, t0 = [], 0.0
    for k in range(scenes):
        rng = np.random.default_rng(k)
        names = [str(x) for x in rng.choice(OBJECTS, size=3, replace=False)]
        scene = multi_scene(names, rng=rng, max_delay_s=0.0)
        rec = frames_from_multi_scene(scene, rng=rng).recording
        parts.append((rec.frames, rec.t_s + t0))
        t0 += float(rec.t_s[-1]) + 0.05
    frames = np.concatenate([p[0] for p in parts])
    t_s = np.concatenate([p[1] for p in parts])
    return TactileFrames(frames, t_s=t_s, pitch_mm=PITCH_MM, units="mm")


def measure(title: str, rec: TactileFrames, repeat: int) -> dict[str, float]:
    """Print and return the timings of one set of frames (frames/s)."""
    images = clean_images(rec.frames > THRESHOLD_MM, rec.t_s)
    t_s = np.asarray(rec.t_s)
    n = images.shape[0]
    _, lost = debounce_counts(TactemeConfig(), float(t_s[1] - t_s[0]))
    reg = segment_frames(images, pitch_mm=PITCH_MM)
    per_frame = np.bincount(reg.frame, minlength=n)
    share = [round(float(np.mean(per_frame == k)), 2) for k in range(4)]
    print(
        f"{title}: {n} frames of {images.shape[1]} x {images.shape[2]}; regions per frame: "
        f"mean {per_frame.mean():.2f}, share with 0, 1, 2, 3: {share}"
    )
    cont = continuing_frames(reg, area_weight=AREA_WEIGHT)[0]
    batch = best_of(repeat, lambda: track_batch(images, t_s, lost))
    every = best_of(repeat, lambda: track_every_frame(images, t_s, lost))
    stream = best_of(repeat, lambda: track_stream(images, t_s, lost))
    seg_only = best_of(repeat, lambda: segment_frames(images, pitch_mm=PITCH_MM))
    base = best_of(repeat, lambda: skimage_per_frame(images))
    print(f"  segmentation only, batch:         {n / seg_only:12,.0f} frames/s")
    print(
        f"  segmentation + tracking, batch:   {n / batch:12,.0f} frames/s "
        f"({100 * cont.mean():.0f} % of the frames continuing; the step on every frame: "
        f"{n / every:,.0f} frames/s, {every / batch:.1f}x the time)"
    )
    print(f"  segmentation + tracking, stream:  {n / stream:12,.0f} frames/s")
    print(f"  skimage label + regionprops:      {n / base:12,.0f} frames/s (no tracking)")
    print(
        f"  ratio to skimage: segmentation {base / seg_only:.2f}x, segmentation + tracking "
        f"batch {base / batch:.2f}x, stream {base / stream:.2f}x (>1: faster)"
    )
    one = best_of(repeat, lambda: recognise(rec))
    many = best_of(repeat, lambda: recognise_objects(rec))
    print(
        f"  whole recogniser, Levels 1-4 per track: {n / many:,.0f} frames/s; single-object "
        f"recognise: {n / one:,.0f} frames/s ({many / one:.1f}x the time)"
    )
    return {
        "frames": float(n),
        "regions_per_frame": float(per_frame.mean()),
        "segmentation": n / seg_only,
        "tracking_batch": n / batch,
        "tracking_every_frame": n / every,
        "continuing_share": float(cont.mean()),
        "tracking_stream": n / stream,
        "skimage": n / base,
        "recognise_objects": n / many,
        "recognise": n / one,
    }


def record_row(small: dict[str, float], wide: dict[str, float]) -> None:
    """Write the README row from the figures of this run (16 x 16, then 16 x 48)."""

    def pair(key: str, fmt: str = ",.0f") -> str:
        return f"{small[key]:{fmt}} / {wide[key]:{fmt}}"

    def times(v: float) -> str:
        return f"{v:.0f}x" if v >= 10.0 else f"{v:.1f}x" if v >= 1.0 else f"{v:.2f}x"

    def ratio(key: str) -> str:
        return f"{times(small[key] / small['skimage'])} / {times(wide[key] / wide['skimage'])}"

    cost = ""
    if small["tracking_batch"] < small["skimage"] < small["segmentation"]:
        cost = ": the tracker's per-frame Python step is the cost"
    steps = f"{small['tracking_every_frame']:,.0f} / {wide['tracking_every_frame']:,.0f}"
    shares = f"{100 * small['continuing_share']:.0f} / {100 * wide['continuing_share']:.0f} %"
    slower = f"{small['recognise'] / small['recognise_objects']:.0f}x / "
    slower += f"{wide['recognise'] / wide['recognise_objects']:.0f}x"
    record(
        __file__,
        figure="3 objects (kinematic scenes) on 16 x 16 (tiles overlaid: "
        f"{small['regions_per_frame']:.1f} regions a frame; they touch) and on 16 x 48 (side "
        f"by side: {wide['regions_per_frame']:.1f} a frame), CPU time: segmentation alone "
        f"{pair('segmentation')} frames/s batch; segmentation + tracking "
        f"{pair('tracking_batch')} frames/s batch ({shares} of the frames continuing, "
        f"the tracker's step skipped; {steps} with the step on every frame), "
        f"{pair('tracking_stream')} streaming; the "
        f"whole per-track recogniser {pair('recognise_objects')} frames/s ({slower} the time "
        "of the single-object `recognise`)",
        ratio=f"{ratio('segmentation')} (segmentation), {ratio('tracking_batch')} "
        f"(segmentation + tracking, batch), {ratio('tracking_stream')} (streaming) "
        f"scikit-image `label` + `regionprops` per frame, which does no tracking{cost}",
        measured={"16x16_overlaid": small, "16x48_side_by_side": wide},
    )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", type=int, default=20)
    ap.add_argument("--repeat", type=int, default=3)
    add_record_option(ap)
    args = ap.parse_args()
    small = measure("16 x 16, three objects overlaid", overlaid(args.scenes), args.repeat)
    wide = measure("16 x 48, three objects side by side", tiled(args.scenes), args.repeat)
    if args.record:
        record_row(small, wide)


if __name__ == "__main__":
    main()
