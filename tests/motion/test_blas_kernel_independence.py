"""Simulated frames and physics rollouts do not depend on the CPU's BLAS kernels.

OpenBLAS picks its kernels by CPU (with fused multiply-adds or without), and
another kernel rounds a matrix product differently in the last place. Forcing
an old kernel with ``OPENBLAS_CORETYPE=Prescott`` stands in for another
machine. Before the products on these paths were summed in a fixed order
(:mod:`taxelkit._fixed_order`), a point on a body's boundary fell on either
side of it (240 frames/s kinematic rolls differed in their frames), every
MuJoCo scene's rollout drifted (the hand reads the body's state each step) and
the rolls of learnt meshes (each small turn built on the last) drifted too.
Where NumPy's BLAS is not OpenBLAS the override does nothing and the tests
hold trivially.
"""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys

import numpy as np
import pytest

from taxelkit import _fixed_order as fo

_KINEMATIC = """
import hashlib, numpy as np
from taxelkit.motion.engines import scenarios_from_engine
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
h = hashlib.sha256()
for i, name in enumerate(("sphere", "cylinder", "cone", "truncated-cone", "cube", "tetrahedron")):
    for rate in (20.0, 240.0):
        g = np.random.default_rng(i)
        sc = scenarios_from_engine("kinematic", name, rates_hz=(rate,), rng=g)[0]
        h.update(np.ascontiguousarray(sc.rotations))
        h.update(np.ascontiguousarray(frames_from_scenario(BONNEVILLE_16X16, sc, rng=i).frames))
print(h.hexdigest())
"""

_MUJOCO = """
import hashlib, numpy as np
from taxelkit.motion.engines.mujoco_scenes import mujoco_scene
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
h = hashlib.sha256()
for name in ("cone", "cube"):
    sc = mujoco_scene(name, rng=0).scenario
    h.update(np.ascontiguousarray(sc.rotations))
    h.update(np.ascontiguousarray(sc.positions_mm))
    h.update(np.ascontiguousarray(frames_from_scenario(BONNEVILLE_16X16, sc, rng=0).frames))
print(h.hexdigest())
"""

_MESH = """
import hashlib, numpy as np
from taxelkit.experiments.new_objects import _mesh
from taxelkit.motion.mesh_scenarios import make_mesh_scenario
h = hashlib.sha256()
for name in ("square-pyramid", "ellipsoid", "capsule"):
    solid, feats = _mesh(name)
    for seed in range(2):
        sc = make_mesh_scenario(solid, feats, name=name, rng=np.random.default_rng(seed))
        h.update(np.ascontiguousarray(sc.rotations))
        h.update(np.ascontiguousarray(sc.centroids_mm))
print(h.hexdigest())
"""


def _digest(script: str, **env: str) -> str:
    out = subprocess.run(
        [sys.executable, "-c", script],
        capture_output=True,
        text=True,
        env={**os.environ, "OPENBLAS_NUM_THREADS": "1", **env},
        check=True,
    )
    return out.stdout.strip()


def test_kinematic_frames_do_not_depend_on_the_blas_kernel() -> None:
    # 240 frames/s rolls differed in their frames before the skin's basis product
    # was summed in a fixed order
    assert _digest(_KINEMATIC) == _digest(_KINEMATIC, OPENBLAS_CORETYPE="Prescott")


@pytest.mark.skipif(
    importlib.util.find_spec("mujoco") is None,
    reason='the MuJoCo engine is an optional extra: pip install "taxelkit[mujoco]"',
)
def test_mujoco_rollouts_do_not_depend_on_the_blas_kernel() -> None:
    # both scenes' rotations differed before the hand's products were summed in a
    # fixed order; the cone's frames too
    assert _digest(_MUJOCO) == _digest(_MUJOCO, OPENBLAS_CORETYPE="Prescott")


def _python_sum(a: np.ndarray, b: np.ndarray) -> float:
    total = 0.0
    for x, y in zip(a.tolist(), b.tolist(), strict=True):
        total = total + x * y
    return total


def test_products_are_summed_from_the_first_index() -> None:
    rng = np.random.default_rng(3)
    m = rng.normal(size=(5, 4, 3))
    v = rng.normal(size=(5, 3))
    b = rng.normal(size=(5, 3, 2))
    mv = fo.matvec(m, v)
    mm = fo.matmul(m, b)
    for p in range(5):
        for i in range(4):
            assert mv[p, i] == _python_sum(m[p, i], v[p])  # bit for bit
            for j in range(2):
                assert mm[p, i, j] == _python_sum(m[p, i], b[p, :, j])
        # one small matrix takes the Python-float path: the same bits as the batch
        np.testing.assert_array_equal(fo.matvec(m[p], v[p]), mv[p])
        np.testing.assert_array_equal(fo.matmul(m[p], b[p]), mm[p])
        assert fo.dot(v[p], v[p]) == _python_sum(v[p], v[p])
        assert fo.scalar_norm(v[p]) == np.sqrt(_python_sum(v[p], v[p]))
    xy = rng.normal(size=(5, 2))  # a small matrix with two columns: the general small path
    turn = rng.normal(size=(2, 2))
    small = fo.matmul(xy, turn)
    for i in range(5):
        for j in range(2):
            assert small[i, j] == _python_sum(xy[i], turn[:, j])
    np.testing.assert_allclose(mv, np.einsum("pij,pj->pi", m, v), rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(mm, m @ b, rtol=1e-13, atol=1e-14)


def test_shapes_broadcast_like_numpy() -> None:
    rng = np.random.default_rng(4)
    r = rng.normal(size=(3, 3))
    pts = rng.normal(size=(7, 3))
    rots = rng.normal(size=(6, 3, 3))
    np.testing.assert_allclose(fo.rotate_points(pts, r), pts @ r.T, rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(fo.matvec(r, pts), pts @ r.T, rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(fo.matmul(r, rots), r @ rots, rtol=1e-13, atol=1e-14)
    np.testing.assert_allclose(fo.norm(pts), np.linalg.norm(pts, axis=1), rtol=1e-14)
    assert fo.matmul(np.ones((2, 3)), np.ones((3, 4))).shape == (2, 4)
    assert fo.dot(np.ones(3), np.ones(3)).shape == ()
    # empty batches keep their shapes on both paths
    assert fo.matmul(np.ones((0, 3)), np.ones((3, 4))).shape == (0, 4)
    assert fo.matmul(np.ones((0, 3)), np.ones((3, 8))).shape == (0, 8)
    assert fo.matvec(np.ones((0, 3)), np.ones(3)).shape == (0,)


def test_learnt_mesh_rolls_do_not_depend_on_the_blas_kernel() -> None:
    # the ellipsoid's and the capsule's rolls (each step built on the last) and a
    # square pyramid's tips differed in their poses before their products were
    # summed in a fixed order
    assert _digest(_MESH) == _digest(_MESH, OPENBLAS_CORETYPE="Prescott")


#: The motion drawn for a MuJoCo truncated cone of the robustness experiment
#: (seed 0, trial 15), seen at 20 frames/s alone: its script took another path
#: where NumPy's AVX-512 ``arctan2`` rounded one angle differently.
_MUJOCO_ANGLES = """
import hashlib, numpy as np
from taxelkit.experiments.robustness import _units
from taxelkit.motion.engines import scenarios_from_engine
from taxelkit.motion.rolling import frames_from_scenario
from taxelkit.sensors.presets import BONNEVILLE_16X16
unit = [u for u in _units(["mujoco"], (20.0,), 16, 0)
        if u.truth == "truncated-cone" and u.trial == 15 and u.array is None][0]
motion, noise, _ = np.random.SeedSequence([unit.entropy, unit.trial]).spawn(3)
rng = np.random.default_rng(motion)
sc = scenarios_from_engine("mujoco", unit.truth, rates_hz=(20.0,), rng=rng)[0]
h = hashlib.sha256()
h.update(np.ascontiguousarray(sc.rotations))
h.update(np.ascontiguousarray(frames_from_scenario(BONNEVILLE_16X16, sc, rng=0).frames))
print(h.hexdigest())
"""


def _avx512_loops() -> str:
    """The AVX-512 targets NumPy dispatches to here, as ``NPY_DISABLE_CPU_FEATURES`` takes them."""
    from numpy._core._multiarray_umath import __cpu_features__ as features

    return " ".join(f for f in ("X86_V4", "AVX512_ICL", "AVX512_SPR") if features.get(f))


def test_simulated_motion_does_not_depend_on_numpy_simd_loops() -> None:
    # NumPy's AVX-512 arctan2 differs from the C library's in the last bit; the
    # scripts' and the rollouts' sampling angles now come from the C library
    off = _avx512_loops()
    if not off:
        pytest.skip("NumPy dispatches no AVX-512 loops on this CPU: nothing to switch off")
    assert _digest(_KINEMATIC) == _digest(_KINEMATIC, NPY_DISABLE_CPU_FEATURES=off)
    if importlib.util.find_spec("mujoco") is not None:
        assert _digest(_MUJOCO_ANGLES) == _digest(_MUJOCO_ANGLES, NPY_DISABLE_CPU_FEATURES=off)


def test_fixed_order_angles_are_the_c_librarys() -> None:
    import math

    rng = np.random.default_rng(5)
    y, x = rng.normal(size=(4, 3)), rng.normal(size=3)
    got = fo.arctan2(y, x)
    assert got.shape == (4, 3) and got.dtype == np.float64
    for i in range(4):
        for j in range(3):
            assert got[i, j] == math.atan2(y[i, j], x[j])  # bit for bit
    c = np.clip(rng.normal(size=5), -1.0, 1.0)
    assert fo.arccos(c).tolist() == [math.acos(v) for v in c.tolist()]
    assert fo.arctan2(np.zeros(0), np.zeros(0)).shape == (0,)
