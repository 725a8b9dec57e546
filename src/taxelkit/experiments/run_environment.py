"""What an experiment ran on: versions, CPU and BLAS, recorded beside its timing.

The same seed gives byte-identical JSON on the same machine and libraries,
and the simulation no longer depends on the CPU's BLAS kernels: the small
products of the skin, the motion scripts, the mesh roller and MuJoCo's
scripted hand are summed in a fixed order (``taxelkit._fixed_order``; a lying body's contact
line also used to hang on a rounding error, see
:func:`~taxelkit.world.solids_revolution.revolution_lowest_segment_mm`).
What could still move a figure at the margin elsewhere is what was not tried:
NumPy's AVX-512 loops, another MuJoCo build, other library versions.
:func:`run_environment` records what such a comparison needs to know.
"""

from __future__ import annotations

import ctypes
import glob
import importlib.metadata
import os
import platform
from typing import Any

__all__ = ["run_environment"]

#: Libraries whose versions are recorded when installed.
LIBRARIES = ("numpy", "scipy", "mujoco", "shapely", "trimesh")


def _version(name: str) -> str | None:
    try:
        return importlib.metadata.version(name)
    except importlib.metadata.PackageNotFoundError:
        return None


def _cpu_model() -> str:
    """The CPU's model name (Linux ``/proc/cpuinfo``), else what :mod:`platform` says."""
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            for line in fh:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown"


def _numpy_simd() -> list[str]:
    """The SIMD extensions NumPy found and dispatches to (empty if it does not say)."""
    import importlib

    try:  # NumPy's own record (private, so looked up rather than imported by name)
        features = importlib.import_module("numpy._core._multiarray_umath").__cpu_features__
    except (ImportError, AttributeError):
        return []
    return sorted(str(k) for k, on in features.items() if on)


def _blas() -> str:
    """NumPy's BLAS, its version and, for a bundled OpenBLAS, the kernels it chose here."""
    import numpy as np

    try:
        info = np.show_config(mode="dicts")["Build Dependencies"]["blas"]
        name = f"{info.get('name', 'unknown')} {info.get('version', '')}".strip()
    except (KeyError, TypeError, ValueError):
        return "unknown"
    libs = os.path.join(os.path.dirname(np.__file__), os.pardir, "numpy.libs")
    for path in glob.glob(os.path.join(libs, "*openblas*")):
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for symbol in ("scipy_openblas_get_corename64_", "scipy_openblas_get_corename"):
            fn = getattr(lib, symbol, None)
            if fn is not None:
                fn.restype = ctypes.c_char_p
                core = fn()
                return f"{name} ({core.decode()} kernels)" if core else name
    return name


def run_environment() -> dict[str, Any]:
    """The machine and libraries an experiment runs on.

    Returns
    -------
    dict
        ``python``, ``platform``, ``cpu`` (model name), ``numpy_simd`` (the
        extensions NumPy dispatches to), ``blas`` (name, version and, where
        it says, the CPU kernels it picked), ``libraries`` (version of each
        of :data:`LIBRARIES`, None if not installed) and
        ``openblas_coretype`` (the ``OPENBLAS_CORETYPE`` override, None if
        unset) and ``numpy_disabled_features`` (NumPy's
        ``NPY_DISABLE_CPU_FEATURES``: the SIMD targets switched off, for
        example ``X86_V4`` on an AVX-512 CPU to compare with AVX2 runs; None
        if unset). Every value is JSON-serialisable.

    Examples
    --------
    >>> env = run_environment()
    >>> sorted(env)[:4]
    ['blas', 'cpu', 'libraries', 'numpy_disabled_features']
    >>> sorted(env)[4:]
    ['numpy_simd', 'openblas_coretype', 'platform', 'python']
    """
    return {
        "python": platform.python_version(),
        "platform": f"{platform.system()} {platform.machine()}",
        "cpu": _cpu_model(),
        "numpy_simd": _numpy_simd(),
        "blas": _blas(),
        "libraries": {name: _version(name) for name in LIBRARIES},
        "openblas_coretype": os.environ.get("OPENBLAS_CORETYPE"),
        "numpy_disabled_features": os.environ.get("NPY_DISABLE_CPU_FEATURES"),
    }
