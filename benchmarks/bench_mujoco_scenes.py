"""MuJoCo scenes: seconds per scene, intended contact sequences, and the smart sensor's verdicts.

For each scene name and ``--seeds`` seeds this simulates one MuJoCo scene at
``--rate-hz`` (:func:`taxelkit.motion.engines.mujoco_scenes.mujoco_scene`),
prints the wall time per scene, checks that the scene shows the contact
sequence it is meant to show (ground truth from the engine), renders its
frames with the skin model and runs the paper-001 recogniser
(:func:`taxelkit.smart.recogniser.recognise`) on them. The kinematic engine's
time per scene is printed beside it as the baseline of the same run.

Intended sequences (every scene also starts and ends lifted):

* sphere: a point contact rolling in two runs at 60-120 deg to each other;
* cylinder: a line contact rolling;
* cone, truncated-cone: a line contact rolling whose line sweeps >= 15 deg;
* cube, tetrahedron: face -> edge -> face at least twice, consecutive edge
  lines parallel or at 90 deg (cube), at 60 or 120 deg (tetrahedron), +- 15 deg;
* sliding: a face that slides or spins (>= 3 frames), never on an edge or a point.

"identified" counts correct names (for sliding: the verdict "unknown"),
"wrong" any other object name, "undecided" no verdict (or "unknown" for a
rolling object).

Usage: ``python benchmarks/bench_mujoco_scenes.py [--seeds 10] [--rate-hz 20]``.
"""

from __future__ import annotations

import argparse
import itertools
import math
import time
from collections import Counter

import numpy as np

from taxelkit.motion.engines.mujoco_scenes import MujocoScene, mujoco_scene
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.motion.scenarios import SCENARIO_NAMES, make_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
from taxelkit.smart.recogniser import recognise

_ANGLE_TOL_DEG = 15.0


def _edge(ms: MujocoScene, frame: int) -> tuple[float, np.ndarray]:
    """Direction (deg, mod 180) and midpoint (xy, body-centred) of a resting edge."""
    v = ms.scenario.solid.vertices_mm @ ms.scenario.rotations[frame].T  # type: ignore[union-attr]
    low = v[np.argsort(v[:, 2])[:2]]
    d = low[1] - low[0]
    mid = 0.5 * (low[0] + low[1])[:2] + ms.scenario.positions_mm[frame]
    return math.degrees(math.atan2(d[1], d[0])) % 180.0, mid


def _axis_deg(ms: MujocoScene, frame: int) -> float:
    """Heading (deg) of a round body's axis projected on the plate."""
    a = ms.scenario.rotations[frame][:, 2]
    return math.degrees(math.atan2(a[1], a[0]))


def _line_angles_deg(ms: MujocoScene, label: str) -> list[float]:
    """Direction (deg, mod 180) of each edge held in a ``label`` run, in order.

    One edge held over two runs (the label flickering) counts once.
    """
    out: list[tuple[float, np.ndarray]] = []
    for phase, a, b in ms.scenario.phase_runs():
        if phase == label and ms.contact[(a + b) // 2] == "line":
            angle, mid = _edge(ms, (a + b) // 2)
            if not out or np.linalg.norm(mid - out[-1][1]) > 1.0:
                out.append((angle, mid))
    return [angle for angle, _ in out]


def _near(angle: float, targets: tuple[float, ...]) -> bool:
    return any(abs((angle - t + 90.0) % 180.0 - 90.0) <= _ANGLE_TOL_DEG for t in targets)


def intended(name: str, ms: MujocoScene) -> bool:
    """True if the scene shows the contact sequence it is meant to show (module notes)."""
    sc = ms.scenario
    if sc.phase[0] != "lifted" or sc.phase[-1] != "lifted":
        return False
    touching = [c for c in ms.contact if c != "none"]
    rolling = [i for i, p in enumerate(sc.phase) if p == "rolling"]
    if name == "sphere":
        runs = [(a, b) for p, a, b in sc.phase_runs() if p == "rolling" and b - a >= 3]
        dirs = [sc.positions_mm[b - 1] - sc.positions_mm[a] for a, b in runs]
        turns = [
            math.degrees(math.acos(abs(u @ v) / (np.linalg.norm(u) * np.linalg.norm(v))))
            for u, v in itertools.pairwise(dirs)
        ]
        return any(t >= 60.0 for t in turns)
    if name in ("cylinder", "cone", "truncated-cone"):
        lines = [i for i in rolling if ms.contact[i] == "line"]
        if len(lines) < 5:
            return False
        if name == "cylinder":
            return True
        heading = np.unwrap(np.radians([_axis_deg(ms, i) for i in lines]))
        return bool(math.degrees(float(np.ptp(heading))) >= 15.0)
    if name in ("cube", "tetrahedron"):
        seq = [k for k, _ in _runs(touching)]
        if sum(1 for k in seq if k == "line") < 2:
            return False
        angles = _line_angles_deg(ms, "edge")
        rel = [(b - a) % 180.0 for a, b in itertools.pairwise(angles)]
        targets = (0.0, 90.0) if name == "cube" else (60.0, 120.0)
        return len(rel) >= 1 and all(_near(r, targets) for r in rel)
    slipping = sum(1 for p in sc.phase if p in ("sliding", "spinning"))
    return slipping >= 3 and set(touching) == {"area"}


def _runs(seq: list[str]) -> list[tuple[str, int]]:
    out: list[tuple[str, int]] = []
    for k in seq:
        if out and out[-1][0] == k:
            out[-1] = (k, out[-1][1] + 1)
        else:
            out.append((k, 1))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=10)
    parser.add_argument("--rate-hz", type=float, default=20.0)
    parser.add_argument("--lift-gap-s", type=float, default=0.0)
    args = parser.parse_args()
    print(f"MuJoCo scenes at {args.rate_hz:g} Hz, seeds 0-{args.seeds - 1}")
    header = "scene            s/scene  kin s  intended  identified  wrong  undecided  verdicts"
    print(header)
    for name in SCENARIO_NAMES:
        wall, kin, ok, right, wrong, undecided = [], [], 0, 0, 0, 0
        verdicts: Counter[str] = Counter()
        for seed in range(args.seeds):
            t0 = time.perf_counter()
            ms = mujoco_scene(name, rng=seed, rate_hz=args.rate_hz, lift_gap_s=args.lift_gap_s)
            wall.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            make_scenario(name, rng=seed, rate_hz=args.rate_hz)
            kin.append(time.perf_counter() - t0)
            ok += intended(name, ms)
            frames = frames_from_scenario(BONNEVILLE_16X16, ms.scenario, rng=seed)
            got = recognise(frames).identified
            verdicts[str(got)] += 1
            if got is None or (got == "unknown" and not ms.scenario.slides):
                undecided += 1
            elif ms.scenario.slides:
                wrong += got != "unknown"  # a sliding body must not be named
                right += got == "unknown"
            elif got == ms.scenario.object_name:
                right += 1
            else:
                wrong += 1
        print(
            f"{name:15s} {np.mean(wall):7.2f} {np.mean(kin):6.3f} {ok:5d}/{args.seeds:<3d}"
            f" {right:7d}/{args.seeds:<3d} {wrong:5d} {undecided:9d}  {dict(verdicts)}"
        )


if __name__ == "__main__":
    main()
