"""Heightmap specimens: grid convention, bilinear interpolation, .npz round trip, bad files."""

from __future__ import annotations

import pickle
import zipfile
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from taxelkit.errors import (
    CorruptRecordingError,
    InputError,
    RecordingAccessError,
    RecordingNotFoundError,
)
from taxelkit.world.base import Relief
from taxelkit.world.heightmap import (
    HeightmapRelief,
    heightmap_from_relief,
    load_heightmap,
    relief_from_heightmap,
)
from taxelkit.world.relief import relief_shape

#: A 2 x 3 map whose values name their position: 10 * row + column.
TINY = np.array([[0.0, 1.0, 2.0], [10.0, 11.0, 12.0]])


def _save(path: Path, **arrays: Any) -> Path:
    np.savez(path, **arrays)
    return path


def test_centred_default_convention_on_an_asymmetric_map() -> None:
    hm = relief_from_heightmap(TINY, pixel_mm=0.5)
    # W = 3 columns along x, H = 2 rows along y: x0 = -(3-1)/2*0.5, y0 = -(2-1)/2*0.5.
    assert (hm.x0_mm, hm.y0_mm) == (-0.5, -0.25)
    assert hm.extent_mm == (-0.5, 0.5, -0.25, 0.25)
    np.testing.assert_array_equal(hm.x_mm, [-0.5, 0.0, 0.5])
    np.testing.assert_array_equal(hm.y_mm, [-0.25, 0.25])
    x = np.array([-0.5, 0.5, -0.5, 0.0])
    y = np.array([-0.25, -0.25, 0.25, 0.25])
    np.testing.assert_array_equal(hm.height_mm(x, y), [0.0, 2.0, 10.0, 11.0])


def test_explicit_origin_convention() -> None:
    hm = relief_from_heightmap(TINY, pixel_mm=2.0, x0_mm=10.0, y0_mm=-3.0)
    # heights_mm[i, j] sits at x = 10 + 2 j, y = -3 + 2 i.
    for i in range(2):
        for j in range(3):
            assert float(hm.height_mm(10.0 + 2.0 * j, -3.0 + 2.0 * i)) == TINY[i, j]
    assert float(hm.height_mm(0.0, 0.0)) == 0.0  # the centre is outside this map


def test_bilinear_between_samples_and_zero_outside() -> None:
    hm = relief_from_heightmap(TINY, pixel_mm=1.0, x0_mm=0.0, y0_mm=0.0)
    assert float(hm.height_mm(0.5, 0.0)) == pytest.approx(0.5)
    assert float(hm.height_mm(0.0, 0.5)) == pytest.approx(5.0)
    assert float(hm.height_mm(1.5, 0.5)) == pytest.approx(6.5)  # mean of 1, 2, 11, 12
    assert float(hm.height_mm(2.0, 1.0)) == 12.0  # the last sample is inside (closed)
    outside = hm.height_mm(
        [-1e-9, 2.0 + 1e-9, 1.0, 1.0, np.nan], [0.5, 0.5, -1e-9, 1.0 + 1e-9, 0.5]
    )
    np.testing.assert_array_equal(outside, 0.0)


@settings(max_examples=40, deadline=None)
@given(
    a=st.floats(-1.0, 1.0),
    b=st.floats(-1.0, 1.0),
    c=st.floats(-1.0, 1.0),
    d=st.floats(-0.1, 0.1),
    seed=st.integers(0, 2**31),
)
def test_bilinear_reproduces_bilinear_surfaces_exactly(
    a: float, b: float, c: float, d: float, seed: int
) -> None:
    hm0 = relief_from_heightmap(np.zeros((7, 9)), pixel_mm=0.7, x0_mm=1.0, y0_mm=-2.0)
    xs, ys = hm0.x_mm, hm0.y_mm

    def surface(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return np.asarray(a * x + b * y + c + d * x * y)

    hm = relief_from_heightmap(
        surface(xs[None, :], ys[:, None]), pixel_mm=0.7, x0_mm=1.0, y0_mm=-2.0
    )
    rng = np.random.default_rng(seed)
    x = rng.uniform(xs[0], xs[-1], (5, 40))
    y = rng.uniform(ys[0], ys[-1], (5, 40))
    np.testing.assert_allclose(hm.height_mm(x, y), surface(x, y), atol=1e-12)


def test_single_row_and_column_maps() -> None:
    row = relief_from_heightmap([[0.0, 1.0, 3.0]], pixel_mm=1.0)
    assert float(row.height_mm(0.5, 0.0)) == 2.0
    assert float(row.height_mm(0.5, 0.1)) == 0.0
    dot = relief_from_heightmap([[4.0]], pixel_mm=1.0)
    np.testing.assert_array_equal(dot.height_mm([0.0, 0.1], [0.0, 0.0]), [4.0, 0.0])


def test_rasterise_save_load_round_trip(tmp_path: Path) -> None:
    star = relief_shape("star", diameter_mm=40.0, step_height_um=150.0, rotation_deg=10.0)
    hm = heightmap_from_relief(star, pixel_mm=0.25, extent_mm=(-22.0, 22.0, -21.0, 23.0))
    assert hm.shape == (177, 177)
    assert hm.extent_mm == pytest.approx((-22.0, 22.0, -21.0, 23.0))
    path = _save(tmp_path / "star.npz", **hm.to_arrays())
    loaded = load_heightmap(path)
    np.testing.assert_array_equal(loaded.heights_mm, hm.heights_mm)
    assert (loaded.pixel_mm, loaded.x0_mm, loaded.y0_mm) == (hm.pixel_mm, hm.x0_mm, hm.y0_mm)
    gx, gy = loaded.x_mm[None, :], loaded.y_mm[:, None]
    np.testing.assert_allclose(loaded.height_mm(gx, gy), hm.heights_mm, atol=1e-15)
    np.testing.assert_array_equal(hm.heights_mm, star.height_mm(gx, gy))
    # Away from the contour (more than a pixel diagonal) the raster equals the shape.
    pts = np.random.default_rng(3).uniform(-21.0, 21.0, (4000, 2))
    pts = pts[star.distance_to_edge_mm(pts) > 0.25 * np.sqrt(2.0)]
    np.testing.assert_array_equal(loaded.height_mm(*pts.T), star.height_mm(*pts.T))
    assert isinstance(loaded, Relief)


def test_loading_without_origin_centres_the_map(tmp_path: Path) -> None:
    path = _save(tmp_path / "tiny.npz", height_mm=TINY, pixel_mm=0.5)
    hm = load_heightmap(path)
    assert (hm.x0_mm, hm.y0_mm) == (-0.5, -0.25)
    assert float(hm.height_mm(0.5, 0.25)) == 12.0
    path = _save(tmp_path / "shifted.npz", height_mm=TINY, pixel_mm=0.5, x0_mm=1.0, y0_mm=2.0)
    hm = load_heightmap(path)
    assert float(hm.height_mm(1.0, 2.0)) == 0.0
    assert float(hm.height_mm(2.0, 2.5)) == 12.0


def test_heightmap_from_relief_includes_whole_pixel_ends_and_validates() -> None:
    edge_hm = heightmap_from_relief(relief_shape("square"), pixel_mm=0.1, extent_mm=(0, 1, 0, 0.3))
    assert edge_hm.shape == (4, 11)
    with pytest.raises(InputError, match="extent_mm"):
        heightmap_from_relief(relief_shape("square"), pixel_mm=0.1, extent_mm=(1, 0, 0, 1))
    with pytest.raises(InputError, match="extent_mm"):
        heightmap_from_relief(relief_shape("square"), pixel_mm=0.1, extent_mm=(0, 1, 0))  # type: ignore[arg-type]
    with pytest.raises(InputError, match="pixel_mm"):
        heightmap_from_relief(relief_shape("square"), pixel_mm=0.0, extent_mm=(0, 1, 0, 1))


def test_heightmap_is_frozen_and_read_only() -> None:
    source = TINY.copy()
    hm = relief_from_heightmap(source, pixel_mm=1.0)
    source[0, 0] = 99.0  # the relief keeps its own copy
    assert hm.heights_mm[0, 0] == 0.0
    with pytest.raises(ValueError, match="read-only"):
        hm.heights_mm[0, 0] = 1.0
    assert set(hm.to_arrays()) == {"height_mm", "pixel_mm", "x0_mm", "y0_mm"}
    copy = pickle.loads(pickle.dumps(hm))
    np.testing.assert_array_equal(copy.heights_mm, hm.heights_mm)
    assert (copy.pixel_mm, copy.x0_mm, copy.y0_mm) == (hm.pixel_mm, hm.x0_mm, hm.y0_mm)
    assert not copy.heights_mm.flags.writeable


@pytest.mark.parametrize(
    ("heights", "pixel", "match"),
    [
        (np.zeros(4), 1.0, r"shape \(H, W\)"),
        (np.zeros((2, 2, 2)), 1.0, r"shape \(H, W\)"),
        (np.zeros((0, 3)), 1.0, "empty"),
        (np.array([[0.0, np.nan]]), 1.0, "finite"),
        (np.array([[0.0, np.inf]]), 1.0, "finite"),
        (np.zeros((2, 2), dtype=bool), 1.0, "real numbers"),
        (np.zeros((2, 2)), 0.0, "pixel_mm"),
        (np.zeros((2, 2)), -1.0, "pixel_mm"),
    ],
)
def test_bad_arrays_raise_input_error(heights: np.ndarray, pixel: float, match: str) -> None:
    with pytest.raises(InputError, match=match):
        relief_from_heightmap(heights, pixel_mm=pixel)


def _truncated(path: Path) -> None:
    _save(path, height_mm=np.zeros((50, 50)), pixel_mm=1.0)
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])


def _damaged(path: Path) -> None:
    _save(path, height_mm=np.zeros((50, 50)), pixel_mm=1.0)
    data = bytearray(path.read_bytes())
    data[200] ^= 0xFF  # inside the stored height_mm member: CRC mismatch
    path.write_bytes(bytes(data))


def _pickled(path: Path) -> None:
    with zipfile.ZipFile(path, "w") as zf, zf.open("height_mm.npy", "w") as member:
        np.save(member, np.array([{"a": 1}], dtype=object), allow_pickle=True)
    with zipfile.ZipFile(path, "a") as zf, zf.open("pixel_mm.npy", "w") as member:
        np.save(member, np.array(1.0))


@pytest.mark.parametrize(
    ("write", "error", "match"),
    [
        (lambda p: p.write_text("not a zip archive\n"), CorruptRecordingError, "not an .npz"),
        (lambda p: p.write_bytes(b""), CorruptRecordingError, "is empty"),
        (_truncated, CorruptRecordingError, "unreadable .npz heightmap"),
        (_damaged, CorruptRecordingError, "unreadable .npz heightmap"),
        (_pickled, CorruptRecordingError, "never loads"),
        (lambda p: np.save(p.with_suffix(".npy"), np.zeros((2, 2))), CorruptRecordingError, ".npy"),
        (lambda p: _save(p, pixel_mm=1.0), CorruptRecordingError, "missing array.*height_mm"),
        (
            lambda p: _save(p, height_mm=np.zeros((2, 2))),
            CorruptRecordingError,
            "missing.*pixel_mm",
        ),
        (lambda p: _save(p, height_mm=np.zeros(5), pixel_mm=1.0), InputError, r"\(H, W\)"),
        (lambda p: _save(p, height_mm=np.zeros((2, 2, 2)), pixel_mm=1.0), InputError, r"\(H, W\)"),
        (lambda p: _save(p, height_mm=np.full((2, 2), np.nan), pixel_mm=1.0), InputError, "finite"),
        (lambda p: _save(p, height_mm=np.full((2, 2), np.inf), pixel_mm=1.0), InputError, "finite"),
        (lambda p: _save(p, height_mm=np.array([["a"]]), pixel_mm=1.0), InputError, "real"),
        (lambda p: _save(p, height_mm=np.zeros((2, 2)), pixel_mm=0.0), InputError, "pixel_mm"),
        (lambda p: _save(p, height_mm=np.zeros((2, 2)), pixel_mm=-0.5), InputError, "pixel_mm"),
        (lambda p: _save(p, height_mm=np.zeros((2, 2)), pixel_mm=np.nan), InputError, "pixel_mm"),
        (lambda p: _save(p, height_mm=np.zeros((2, 2)), pixel_mm=[1.0, 2.0]), InputError, "scalar"),
        (
            lambda p: _save(p, height_mm=np.zeros((2, 2)), pixel_mm=1.0, x0_mm=np.inf),
            InputError,
            "x0_mm",
        ),
    ],
)
def test_bad_files_raise_typed_errors_naming_the_file(
    tmp_path: Path, write: Any, error: type[Exception], match: str
) -> None:
    path = tmp_path / "specimen.npz"
    write(path)
    if not path.exists():  # np.save wrote the .npy beside it
        path.with_suffix(".npy").rename(path)
    with pytest.raises(error, match=match) as info:
        load_heightmap(path)
    message = str(info.value)
    assert str(path) in message
    assert "\n" not in message
    if error is InputError:
        assert not isinstance(info.value, CorruptRecordingError)


def test_missing_file_is_an_access_error_naming_the_path(tmp_path: Path) -> None:
    path = tmp_path / "nowhere.npz"
    with pytest.raises(RecordingNotFoundError, match="no such heightmap file") as info:
        load_heightmap(path)
    assert str(path) in str(info.value)
    with pytest.raises(RecordingAccessError, match="not a regular file"):
        load_heightmap(tmp_path)


def test_dataclass_accepts_explicit_origin_only() -> None:
    hm = HeightmapRelief(TINY, 1.0, 0.0, 0.0)
    assert hm.shape == (2, 3)
    with pytest.raises(InputError, match="x0_mm"):
        HeightmapRelief(TINY, 1.0, float("nan"), 0.0)
