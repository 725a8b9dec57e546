"""Tests of taxelkit.io.recordings: round trips, defaults, and every kind of bad file."""

from __future__ import annotations

import csv
import os
import sys
import tempfile
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from taxelkit.errors import (
    CorruptRecordingError,
    EmptyRecordingError,
    InputError,
    OutputExistsError,
    OutputWriteError,
    RecordingError,
    TaxelkitError,
    UnsupportedFormatError,
)
from taxelkit.frames import DEFAULT_FRAME_INTERVAL_S, DEFAULT_PITCH_MM, TactileFrames
from taxelkit.io.csv_format import _format_cells, _parse_cells
from taxelkit.io.recordings import (
    RECORDING_SUFFIXES,
    InvalidRecordingError,
    RecordingAccessError,
    RecordingNotFoundError,
    read_recording,
    recording_format,
    write_recording,
)

SUFFIXES = [".npz", ".h5", ".csv"]
BINARY_SUFFIXES = [".npz", ".h5"]
DTYPES = [np.bool_, np.float32, np.float64]


# ----------------------------------------------------------------------------- helpers
def _sample(dtype: Any = np.float64, shape: tuple[int, int, int] = (4, 3, 5)) -> TactileFrames:
    rng = np.random.default_rng(7)
    if dtype is np.bool_:
        frames: np.ndarray[Any, Any] = rng.random(shape) > 0.5
    else:
        frames = (rng.random(shape) * 0.4 - 0.05).astype(dtype)
    return TactileFrames(
        frames,
        t_s=0.125 + np.arange(shape[0]) * 0.01,
        pitch_mm=1.7625,
        units=None,
        sensor="bonneville-16x16",
    )


def _assert_names_file(err: BaseException, path: Path) -> None:
    message = str(err)
    assert path.name in message, message
    assert "\n" not in message, message


def _read_or_error(path: Path) -> TactileFrames | RecordingError:
    """Read a possibly damaged file: a recording or a RecordingError, nothing else."""
    try:
        return read_recording(path)
    except RecordingError as err:
        _assert_names_file(err, path)
        return err


def _write_csv_text(path: Path, text: str) -> Path:
    path.write_text(text, encoding="utf-8", newline="")
    return path


def _valid_file(folder: Path, suffix: str) -> Path:
    return write_recording(_sample(np.float32, (6, 4, 4)), folder / f"valid{suffix}")


# ----------------------------------------------------------------------------- round trips
_TEXT = st.text(
    alphabet=st.characters(codec="utf-8", exclude_categories=("Cc", "Cs", "Zl", "Zp")),
    max_size=12,
).map(str.strip)


@st.composite
def _recordings(draw: st.DrawFn, dtype: Any) -> TactileFrames:
    shape = (draw(st.integers(1, 4)), draw(st.integers(1, 4)), draw(st.integers(1, 4)))
    if dtype is np.bool_:
        frames = draw(arrays(np.bool_, shape))
    else:
        width = 32 if dtype is np.float32 else 64
        finite = st.floats(allow_nan=False, allow_infinity=False, width=width)
        frames = draw(arrays(dtype, shape, elements=finite))
    t_s = draw(
        st.none()
        | st.lists(
            st.floats(-1e9, 1e9, allow_nan=False),
            min_size=shape[0],
            max_size=shape[0],
            unique=True,
        ).map(sorted)
    )
    pitch = draw(st.none() | st.floats(1e-6, 1e6))
    units = None if dtype is np.bool_ else draw(st.none() | _TEXT.filter(lambda u: u != "contact"))
    sensor = draw(st.none() | _TEXT)
    kwargs: dict[str, Any] = {}
    if pitch is not None:
        kwargs["pitch_mm"] = pitch
    if sensor is not None:
        kwargs["sensor"] = sensor
    return TactileFrames(frames, t_s, units=units, **kwargs)


@pytest.mark.parametrize("suffix", SUFFIXES)
@pytest.mark.parametrize("dtype", DTYPES, ids=lambda d: np.dtype(d).name)
@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_round_trip_is_identical(suffix: str, dtype: Any, data: st.DataObject) -> None:
    rec = data.draw(_recordings(dtype))
    with tempfile.TemporaryDirectory() as folder:
        path = write_recording(rec, Path(folder) / f"rec{suffix}")
        back = read_recording(path)
    assert back.equals(rec), (rec, back)
    assert back.frames.dtype == rec.frames.dtype


_EXTREMES = {
    np.float16: [0.0, -0.0, 0.1, 1 / 3, 6e-8, 65504.0, -65504.0, 6.1e-5],
    np.float32: [0.0, -0.0, 0.1, 1 / 3, 1e-45, 1.17e-38, 3.4028235e38, -2.5e-7],
    np.float64: [0.0, -0.0, 0.1, 1 / 3, 5e-324, 2.2250738585072014e-308, 1.7976931348623157e308],
}


@pytest.mark.parametrize("suffix", SUFFIXES)
@pytest.mark.parametrize("dtype", list(_EXTREMES), ids=lambda d: np.dtype(d).name)
def test_extreme_values_round_trip_bit_exactly(tmp_path: Path, suffix: str, dtype: Any) -> None:
    values = np.array(_EXTREMES[dtype], dtype=dtype)
    frames = np.stack([values, values[::-1]])[:, None, :]
    t_s = np.array([5e-324, 0.30000000000000004])
    rec = TactileFrames(frames, t_s, pitch_mm=0.1 + 0.2, units="um", sensor="x: y, z #1")
    back = read_recording(write_recording(rec, tmp_path / f"extreme{suffix}"))
    assert back.equals(rec)
    assert np.array_equal(back.frames.view(np.uint8), rec.frames.view(np.uint8))


@pytest.mark.parametrize("suffix", SUFFIXES)
@pytest.mark.parametrize("dtype", DTYPES, ids=lambda d: np.dtype(d).name)
def test_round_trip_with_all_defaults(tmp_path: Path, suffix: str, dtype: Any) -> None:
    rec = TactileFrames(_sample(dtype).frames)
    back = read_recording(write_recording(rec, tmp_path / f"plain{suffix}"))
    assert back.equals(rec)


@pytest.mark.parametrize("name", ["a.NPZ", "b.H5", "c.HDF5", "d.Csv", "e.hdf5"])
def test_suffix_is_case_insensitive(tmp_path: Path, name: str) -> None:
    rec = _sample(np.float32)
    assert read_recording(write_recording(rec, tmp_path / name)).equals(rec)


def test_recording_format_and_suffixes() -> None:
    assert RECORDING_SUFFIXES == (".npz", ".h5", ".hdf5", ".csv")
    assert [recording_format(f"x{s}") for s in RECORDING_SUFFIXES] == [
        "npz",
        "hdf5",
        "hdf5",
        "csv",
    ]
    assert recording_format(Path("dir.csv") / "run.H5") == "hdf5"


# ----------------------------------------------------------------------------- layouts
def test_npz_layout(tmp_path: Path) -> None:
    path = write_recording(_sample(np.float32), tmp_path / "r.npz")
    with np.load(path, allow_pickle=False) as z:
        assert sorted(z.files) == ["frames", "pitch_mm", "sensor", "t_s", "units"]
        assert z["frames"].dtype == np.float32 and z["frames"].shape == (4, 3, 5)
        assert z["t_s"].dtype == np.float64
        assert z["pitch_mm"].shape == () and float(z["pitch_mm"]) == 1.7625
        assert z["units"].dtype.kind == "U" and str(z["units"]) == "mm"
        assert str(z["sensor"]) == "bonneville-16x16"


def test_h5_layout(tmp_path: Path) -> None:
    path = write_recording(_sample(np.bool_), tmp_path / "r.h5")
    with h5py.File(path, "r") as f:
        assert sorted(f.keys()) == ["frames", "t_s"]
        assert f["frames"].compression == "gzip"
        assert f["frames"].dtype == np.bool_
        assert dict(f.attrs) == {
            "pitch_mm": 1.7625,
            "units": "contact",
            "sensor": "bonneville-16x16",
        }


def test_csv_layout_is_exactly_as_documented(tmp_path: Path) -> None:
    rec = TactileFrames(
        np.array([[[0.1, 0.2, 0.3], [0.4, 0.5, -0.0]]], dtype=np.float32),
        t_s=[0.5],
        pitch_mm=1.7625,
        sensor="bonneville-16x16",
    )
    path = write_recording(rec, tmp_path / "r.csv")
    assert path.read_text(encoding="utf-8") == (
        "# pitch_mm: 1.7625\n"
        "# units: mm\n"
        "# sensor: bonneville-16x16\n"
        "# dtype: float32\n"
        "t_s,r0c0,r0c1,r0c2,r1c0,r1c1,r1c2\n"
        "0.5,0.1,0.2,0.3,0.4,0.5,-0.0\n"
    )


def test_csv_bool_frames_are_zero_one_with_contact_units(tmp_path: Path) -> None:
    rec = TactileFrames(np.array([[[True, False]], [[False, True]]]))
    path = write_recording(rec, tmp_path / "c.csv")
    text = path.read_text(encoding="utf-8")
    assert "# units: contact\n" in text and "# dtype" not in text
    assert text.endswith("t_s,r0c0,r0c1\n0.0,1,0\n1.0,0,1\n")


# ----------------------------------------------------------------------------- defaults
@pytest.mark.parametrize("dtype", [np.float32, np.bool_], ids=["float32", "bool"])
def test_npz_with_frames_only_gets_defaults(tmp_path: Path, dtype: Any) -> None:
    frames = _sample(dtype).frames
    path = tmp_path / "bare.npz"
    np.savez(path, frames=frames)
    rec = read_recording(path)
    assert rec.frames.dtype == dtype
    assert np.array_equal(rec.frames, frames)
    assert np.array_equal(rec.t_s, np.arange(4) * DEFAULT_FRAME_INTERVAL_S)
    assert rec.pitch_mm == DEFAULT_PITCH_MM
    assert rec.units == ("contact" if dtype is np.bool_ else "mm")
    assert rec.sensor == "unknown"


def test_h5_with_frames_only_gets_defaults(tmp_path: Path) -> None:
    frames = _sample(np.float64).frames
    path = tmp_path / "bare.h5"
    with h5py.File(path, "w") as f:
        f.create_dataset("frames", data=frames)
    rec = read_recording(path)
    assert rec.equals(TactileFrames(frames))


def test_csv_from_another_program_reads(tmp_path: Path) -> None:
    path = tmp_path / "other.csv"
    with path.open("w", newline="") as fh:  # csv's default line ends are \r\n
        out = csv.writer(fh)
        out.writerow(["t_s", "r0c0", "r0c1", "r1c0", "r1c1"])
        out.writerow([0.0, 0.25, 0, 1e-3, 2])
        out.writerow([0.02, 0.5, 0, 0, 1])
    rec = read_recording(path)
    assert rec.shape == (2, 2, 2)
    assert rec.frames.dtype == np.float64
    assert np.array_equal(rec.frames[0], [[0.25, 0.0], [1e-3, 2.0]])
    assert np.array_equal(rec.t_s, [0.0, 0.02])
    assert (rec.pitch_mm, rec.units, rec.sensor) == (DEFAULT_PITCH_MM, "mm", "unknown")


def test_csv_lenient_details(tmp_path: Path) -> None:
    text = (
        "\ufeff# written by hand\r\n"
        "#pitch_mm:2.5\r\n"
        "#  sensor :  my sensor: v2  \r\n"
        "# colour: blue\r\n"
        "\r\n"
        '"t_s", "r0c0","r0c1"\r\n'
        " 0 , 1.5 ,2\r\n"
        "# a comment between frames\r\n"
        "\r\n"
        "1,3,4\r\n"
    )
    rec = read_recording(_write_csv_text(tmp_path / "lenient.csv", text))
    assert rec.shape == (2, 1, 2)
    assert np.array_equal(rec.frames[:, 0, :], [[1.5, 2], [3, 4]])
    assert (rec.pitch_mm, rec.units, rec.sensor) == (2.5, "mm", "my sensor: v2")


def test_csv_dtype_comment_selects_dtype(tmp_path: Path) -> None:
    text = "# dtype: float32\nt_s,r0c0\n0,0.1\n"
    rec = read_recording(_write_csv_text(tmp_path / "f32.csv", text))
    assert rec.frames.dtype == np.float32 and rec.frames[0, 0, 0] == np.float32(0.1)


@pytest.mark.parametrize("comments", ["# units: contact\n", "# dtype: bool\n"])
def test_csv_contact_is_read_as_bool(tmp_path: Path, comments: str) -> None:
    text = comments + "t_s,r0c0,r0c1\n0,1,0\n1,0.0,1.0\n"
    rec = read_recording(_write_csv_text(tmp_path / "contact.csv", text))
    assert rec.is_contact and rec.units == "contact"
    assert np.array_equal(rec.frames[:, 0, :], [[True, False], [False, True]])


def test_csv_shape_is_recovered_from_header(tmp_path: Path) -> None:
    rec = TactileFrames(np.arange(2 * 3 * 2, dtype=float).reshape(2, 3, 2))
    back = read_recording(write_recording(rec, tmp_path / "shape.csv"))
    assert back.shape == (2, 3, 2) and back.equals(rec)


def test_h5_scalars_as_datasets_or_byte_attributes(tmp_path: Path) -> None:
    frames = _sample(np.float32).frames
    path = tmp_path / "lenient.h5"
    with h5py.File(path, "w") as f:
        f.create_dataset("frames", data=frames)
        f.attrs["t_s"] = np.arange(4) * 0.5
        f.create_dataset("pitch_mm", data=np.array([2.0]))
        f.create_dataset("units", data="um")
        f.attrs["sensor"] = np.bytes_(b"fixed-length")
    rec = read_recording(path)
    assert rec.equals(
        TactileFrames(frames, np.arange(4) * 0.5, pitch_mm=2.0, units="um", sensor="fixed-length")
    )


def test_integer_and_big_endian_frames(tmp_path: Path) -> None:
    ints = np.arange(8, dtype=np.uint16).reshape(2, 2, 2)
    np.savez(tmp_path / "ints.npz", frames=ints)
    rec = read_recording(tmp_path / "ints.npz")
    assert rec.frames.dtype == np.float64 and np.array_equal(rec.frames, ints)

    big = np.arange(8, dtype=">f4").reshape(2, 2, 2)
    np.savez(tmp_path / "big.npz", frames=big)
    rec = read_recording(tmp_path / "big.npz")
    assert rec.frames.dtype == np.dtype(np.float32) and np.array_equal(rec.frames, big)


@pytest.mark.parametrize("dtype", [np.uint8, np.float64])
def test_npz_contact_units_turn_zero_one_frames_into_bool(tmp_path: Path, dtype: Any) -> None:
    frames = np.array([[[0, 1], [1, 0]]], dtype=dtype)
    np.savez(tmp_path / "c.npz", frames=frames, units="contact")
    rec = read_recording(tmp_path / "c.npz")
    assert rec.is_contact and np.array_equal(rec.frames, frames.astype(bool))


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_pitch_override(tmp_path: Path, suffix: str) -> None:
    path = write_recording(_sample(), tmp_path / f"p{suffix}")
    assert read_recording(path).pitch_mm == 1.7625
    assert read_recording(path, pitch_mm=0.5).pitch_mm == 0.5


def test_pitch_override_replaces_an_invalid_stored_pitch(tmp_path: Path) -> None:
    np.savez(tmp_path / "p.npz", frames=np.zeros((1, 2, 2)), pitch_mm=-1.0)
    with pytest.raises(InvalidRecordingError, match="pitch_mm"):
        read_recording(tmp_path / "p.npz")
    assert read_recording(tmp_path / "p.npz", pitch_mm=3.0).pitch_mm == 3.0


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan"), float("inf")])
def test_invalid_pitch_override_is_an_input_error(tmp_path: Path, bad: float) -> None:
    path = write_recording(_sample(), tmp_path / "p.npz")
    with pytest.raises(InputError, match="pitch_mm") as info:
        read_recording(path, pitch_mm=bad)
    assert not isinstance(info.value, RecordingError)


# ----------------------------------------------------------------------------- bad paths
@pytest.mark.parametrize("suffix", RECORDING_SUFFIXES)
def test_missing_file(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"missing{suffix}"
    with pytest.raises(RecordingNotFoundError) as info:
        read_recording(path)
    assert isinstance(info.value, FileNotFoundError)
    assert isinstance(info.value, RecordingError)
    _assert_names_file(info.value, path)


@pytest.mark.parametrize("suffix", [*SUFFIXES, ""])
def test_folder_instead_of_file(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"folder{suffix}"
    path.mkdir()
    with pytest.raises(RecordingAccessError, match="folder") as info:
        read_recording(path)
    _assert_names_file(info.value, path)


@pytest.mark.skipif(
    sys.platform == "win32" or os.geteuid() == 0, reason="needs POSIX permissions, not root"
)
def test_unreadable_file(tmp_path: Path) -> None:
    path = _valid_file(tmp_path, ".npz")
    path.chmod(0)
    with pytest.raises(RecordingAccessError) as info:
        read_recording(path)
    _assert_names_file(info.value, path)


@pytest.mark.parametrize("name", ["rec.txt", "rec.npy", "rec", "rec.csv.gz"])
def test_unsupported_extension(tmp_path: Path, name: str) -> None:
    path = tmp_path / name
    path.write_bytes(b"whatever")
    with pytest.raises(UnsupportedFormatError) as info:
        read_recording(path)
    _assert_names_file(info.value, path)
    assert all(s in str(info.value) for s in RECORDING_SUFFIXES)
    with pytest.raises(UnsupportedFormatError):
        write_recording(_sample(), tmp_path / f"out-{name}")
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]


@pytest.mark.parametrize("suffix", RECORDING_SUFFIXES)
def test_zero_byte_file_is_empty(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"empty{suffix}"
    path.touch()
    with pytest.raises(EmptyRecordingError, match="empty") as info:
        read_recording(path)
    _assert_names_file(info.value, path)


def _zero_frames(path: Path) -> None:
    frames = np.zeros((0, 3, 3))
    if path.suffix == ".npz":
        np.savez(path, frames=frames, t_s=np.zeros(0))
    elif path.suffix == ".h5":
        with h5py.File(path, "w") as f:
            f.create_dataset("frames", data=frames)
    else:
        _write_csv_text(path, "# units: mm\nt_s,r0c0,r0c1\n\n")


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_zero_frames_is_empty(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"zero{suffix}"
    _zero_frames(path)
    with pytest.raises(EmptyRecordingError, match="zero frames") as info:
        read_recording(path)
    _assert_names_file(info.value, path)


@pytest.mark.parametrize("suffix", BINARY_SUFFIXES)
def test_missing_frames_array(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"noframes{suffix}"
    if suffix == ".npz":
        np.savez(path, t_s=np.arange(3.0), data=np.zeros((3, 2, 2)))
    else:
        with h5py.File(path, "w") as f:
            f.create_dataset("t_s", data=np.arange(3.0))
            f.create_dataset("data", data=np.zeros((3, 2, 2)))
    with pytest.raises(CorruptRecordingError, match=r"no 'frames' array.*data") as info:
        read_recording(path)
    _assert_names_file(info.value, path)


# ----------------------------------------------------------------------------- invalid fields
_GOOD = np.zeros((3, 2, 2))
_NAN = _GOOD.copy()
_NAN[1, 0, 1] = np.nan
_INF = _GOOD.copy()
_INF[2, 1, 1] = -np.inf

_INVALID_FIELDS: dict[str, tuple[dict[str, Any], str]] = {
    "frames-2d": ({"frames": np.zeros((3, 4))}, "frames"),
    "frames-4d": ({"frames": np.zeros((1, 2, 2, 2))}, "frames"),
    "frames-scalar": ({"frames": np.float64(1.0)}, "frames"),
    "frames-text": ({"frames": np.array([[["a"]]])}, "frames"),
    "frames-no-columns": ({"frames": np.zeros((2, 3, 0))}, "frames"),
    "frames-nan": ({"frames": _NAN}, "frames"),
    "frames-inf": ({"frames": _INF}, "frames"),
    "t_s-decreasing": ({"frames": _GOOD, "t_s": [0.0, 2.0, 1.0]}, "t_s"),
    "t_s-repeated": ({"frames": _GOOD, "t_s": [0.0, 1.0, 1.0]}, "t_s"),
    "t_s-length": ({"frames": _GOOD, "t_s": [0.0, 1.0]}, "t_s"),
    "t_s-nan": ({"frames": _GOOD, "t_s": [0.0, np.nan, 2.0]}, "t_s"),
    "t_s-2d": ({"frames": _GOOD, "t_s": np.zeros((3, 1))}, "t_s"),
    "t_s-text": ({"frames": _GOOD, "t_s": np.array(["0", "1", "2"])}, "t_s"),
    "pitch-zero": ({"frames": _GOOD, "pitch_mm": 0.0}, "pitch_mm"),
    "pitch-negative": ({"frames": _GOOD, "pitch_mm": -2.0}, "pitch_mm"),
    "pitch-nan": ({"frames": _GOOD, "pitch_mm": np.nan}, "pitch_mm"),
    "pitch-vector": ({"frames": _GOOD, "pitch_mm": [1.0, 2.0]}, "pitch_mm"),
    "pitch-text": ({"frames": _GOOD, "pitch_mm": "wide"}, "pitch_mm"),
    "units-number": ({"frames": _GOOD, "units": 3.0}, "units"),
    "sensor-vector": ({"frames": _GOOD, "sensor": np.array(["a", "b"])}, "sensor"),
    "contact-not-0-1": ({"frames": _GOOD + 2, "units": "contact"}, "frames"),
}


def _check_invalid(path: Path, field: str) -> None:
    with pytest.raises(InvalidRecordingError) as info:
        read_recording(path)
    err = info.value
    assert isinstance(err, RecordingError) and isinstance(err, InputError)
    assert isinstance(err, TaxelkitError) and isinstance(err, ValueError)
    _assert_names_file(err, path)
    assert field in str(err), str(err)


@pytest.mark.parametrize("case", list(_INVALID_FIELDS))
def test_invalid_npz_fields(tmp_path: Path, case: str) -> None:
    fields, field = _INVALID_FIELDS[case]
    path = tmp_path / f"{case}.npz"
    np.savez(path, **fields)
    _check_invalid(path, field)


@pytest.mark.parametrize(
    "case", ["frames-2d", "frames-nan", "t_s-decreasing", "pitch-zero", "units-number"]
)
def test_invalid_h5_fields(tmp_path: Path, case: str) -> None:
    fields, field = _INVALID_FIELDS[case]
    path = tmp_path / f"{case}.h5"
    with h5py.File(path, "w") as f:
        for name, value in fields.items():
            if name in ("frames", "t_s"):
                f.create_dataset(name, data=value)
            else:
                f.attrs[name] = value
    _check_invalid(path, field)


_INVALID_CSV: dict[str, tuple[str, str]] = {
    "nan-cell": ("t_s,r0c0\n0,1\n1,nan\n", "frames"),
    "inf-cell": ("t_s,r0c0\n0,inf\n", "frames"),
    "t_s-decreasing": ("t_s,r0c0\n1,0\n0,0\n", "t_s"),
    "t_s-nan": ("t_s,r0c0\nnan,0\n", "t_s"),
    "pitch-text": ("# pitch_mm: wide\nt_s,r0c0\n0,0\n", "pitch_mm"),
    "pitch-negative": ("# pitch_mm: -1\nt_s,r0c0\n0,0\n", "pitch_mm"),
    "contact-not-0-1": ("# units: contact\nt_s,r0c0\n0,0.5\n", "frames"),
    "float16-overflow": ("# dtype: float16\nt_s,r0c0\n0,1e6\n", "frames"),
}


@pytest.mark.parametrize("case", list(_INVALID_CSV))
def test_invalid_csv_fields(tmp_path: Path, case: str) -> None:
    text, field = _INVALID_CSV[case]
    _check_invalid(_write_csv_text(tmp_path / f"{case}.csv", text), field)


# ----------------------------------------------------------------------------- corrupt files
_CORRUPT_CSV: dict[str, tuple[str, str]] = {
    "short-row": ("t_s,r0c0,r0c1\n0,1,2\n1,3\n", "line 3 has 2 cells, expected 3"),
    "long-row": ("# units: mm\nt_s,r0c0\n0,1,2\n", "line 3 has 3 cells, expected 2"),
    "word-cell": ("t_s,r0c0,r0c1\n0,1,2\n1,3,high\n", "line 3, column r0c1: not a number"),
    "blank-cell": ("t_s,r0c0,r0c1\n0,,2\n", "line 2, column r0c0: not a number"),
    "word-time": ("t_s,r0c0\nnoon,1\n", "line 2, column t_s: not a number"),
    "no-header": ("# pitch_mm: 1\n# units: mm\n\n", "no CSV header"),
    "missing-column": ("t_s,r0c0,r1c0,r1c1\n0,1,2,3\n", "mismatched CSV columns"),
    "swapped-columns": ("t_s,r0c1,r0c0\n0,1,2\n", "mismatched CSV columns"),
    "column-major": ("t_s,r0c0,r1c0,r0c1,r1c1\n0,1,2,3,4\n", "mismatched CSV columns"),
    "duplicate-column": ("t_s,r0c0,r0c0\n0,1,2\n", "mismatched CSV columns"),
    "huge-index": ("t_s,r0c0,r99999999c99999999\n0,1,2\n", "mismatched CSV columns"),
    "bad-name": ("t_s,r0c0,x\n0,1,2\n", "mismatched CSV columns"),
    "leading-zero": ("t_s,r00c0\n0,1\n", "mismatched CSV columns"),
    "time-not-first": ("r0c0,t_s\n1,0\n", "mismatched CSV columns"),
    "time-only": ("t_s\n0\n1\n", "mismatched CSV columns"),
    "unknown-dtype": ("# dtype: int8\nt_s,r0c0\n0,1\n", "dtype"),
}


@pytest.mark.parametrize("case", list(_CORRUPT_CSV))
def test_corrupt_csv(tmp_path: Path, case: str) -> None:
    text, expected = _CORRUPT_CSV[case]
    path = _write_csv_text(tmp_path / f"{case}.csv", text)
    with pytest.raises(CorruptRecordingError) as info:
        read_recording(path)
    assert expected in str(info.value), str(info.value)
    _assert_names_file(info.value, path)


def test_csv_that_is_not_utf8(tmp_path: Path) -> None:
    path = tmp_path / "latin1.csv"
    path.write_bytes("# sensor: capteur à bord\nt_s,r0c0\n0,1\n".encode("latin-1"))
    with pytest.raises(CorruptRecordingError, match="UTF-8") as info:
        read_recording(path)
    _assert_names_file(info.value, path)


def _npy_bytes(folder: Path) -> bytes:
    np.save(folder / "single.npy", np.zeros((2, 2, 2)))
    return (folder / "single.npy").read_bytes()


@pytest.mark.parametrize("suffix", [*RECORDING_SUFFIXES])
@pytest.mark.parametrize("content", ["random", "text", "npy", "other-format"])
def test_wrong_content_for_extension(tmp_path: Path, suffix: str, content: str) -> None:
    if content == "random":
        data = np.random.default_rng(3).bytes(2000)
    elif content == "text":
        data = b"this is not a recording\n" * 10
    elif content == "npy":
        data = _npy_bytes(tmp_path)
    else:
        other = ".h5" if suffix in (".npz", ".csv") else ".npz"
        data = _valid_file(tmp_path, other).read_bytes()
    path = tmp_path / f"wrong{suffix}"
    path.write_bytes(data)
    with pytest.raises(CorruptRecordingError) as info:
        read_recording(path)
    _assert_names_file(info.value, path)


def test_npz_with_object_array_is_corrupt(tmp_path: Path) -> None:
    path = tmp_path / "pickled.npz"
    np.savez(path, frames=np.array([[[None]]], dtype=object))
    with pytest.raises(CorruptRecordingError) as info:
        read_recording(path)
    _assert_names_file(info.value, path)


def test_h5_frames_group_is_corrupt(tmp_path: Path) -> None:
    path = tmp_path / "group.h5"
    with h5py.File(path, "w") as f:
        f.create_group("frames")
    with pytest.raises(CorruptRecordingError, match="group") as info:
        read_recording(path)
    _assert_names_file(info.value, path)


@pytest.mark.parametrize("suffix", BINARY_SUFFIXES)
@pytest.mark.parametrize("fraction", [0.001, 0.01, 0.1, 0.25, 0.5, 0.75, 0.9, 0.99, 0.999])
def test_truncated_binary_file_is_corrupt(tmp_path: Path, suffix: str, fraction: float) -> None:
    path = _valid_file(tmp_path, suffix)
    data = path.read_bytes()
    path.write_bytes(data[: max(1, int(len(data) * fraction))])
    with pytest.raises(CorruptRecordingError) as info:
        read_recording(path)
    _assert_names_file(info.value, path)


@pytest.mark.parametrize("suffix", BINARY_SUFFIXES)
def test_truncated_by_one_byte_is_corrupt(tmp_path: Path, suffix: str) -> None:
    path = _valid_file(tmp_path, suffix)
    path.write_bytes(path.read_bytes()[:-1])
    with pytest.raises(CorruptRecordingError):
        read_recording(path)


def test_truncated_csv_never_escapes(tmp_path: Path) -> None:
    source = _valid_file(tmp_path, ".csv").read_bytes()
    path = tmp_path / "cut.csv"
    outcomes = set()
    for length in range(1, len(source), max(1, len(source) // 150)):
        path.write_bytes(source[:length])
        outcome = _read_or_error(path)
        outcomes.add(type(outcome).__name__)
    assert outcomes <= {"TactileFrames", "CorruptRecordingError", "EmptyRecordingError"}
    assert {"TactileFrames", "CorruptRecordingError"} <= outcomes


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_flipped_bytes_never_escape(tmp_path: Path, suffix: str) -> None:
    source = bytearray(_valid_file(tmp_path, suffix).read_bytes())
    path = tmp_path / f"flipped{suffix}"
    rng = np.random.default_rng(11)
    for position in rng.integers(0, len(source), size=40):
        damaged = bytearray(source)
        damaged[position] ^= 0xFF
        path.write_bytes(bytes(damaged))
        _read_or_error(path)


# ----------------------------------------------------------------------------- writing
@pytest.mark.parametrize("suffix", SUFFIXES)
def test_write_refuses_to_overwrite_without_force(tmp_path: Path, suffix: str) -> None:
    path = tmp_path / f"out{suffix}"
    path.write_text("old")
    with pytest.raises(OutputExistsError, match="--force") as info:
        write_recording(_sample(), path)
    _assert_names_file(info.value, path)
    assert path.read_text() == "old"
    assert write_recording(_sample(), path, force=True) == path
    assert read_recording(path).equals(_sample())
    assert sorted(p.name for p in tmp_path.iterdir()) == [path.name]


def test_write_accepts_str_and_returns_path(tmp_path: Path) -> None:
    out = write_recording(_sample(), str(tmp_path / "s.npz"))
    assert out == tmp_path / "s.npz"


def test_write_zero_frames_is_refused(tmp_path: Path) -> None:
    rec = TactileFrames(np.zeros((0, 2, 2)))
    with pytest.raises(EmptyRecordingError):
        write_recording(rec, tmp_path / "zero.npz")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    "sensor", ["two\nlines", "carriage\rreturn", " padded", "nul\x00char", "sep\u2028line"]
)
def test_write_refuses_text_that_cannot_round_trip(tmp_path: Path, sensor: str) -> None:
    rec = TactileFrames(np.zeros((1, 1, 1)), sensor=sensor)
    with pytest.raises(InputError, match="sensor"):
        write_recording(rec, tmp_path / "x.csv")
    assert list(tmp_path.iterdir()) == []


def test_write_refuses_unsupported_dtypes(tmp_path: Path) -> None:
    swapped = np.dtype(np.float32).newbyteorder("S")
    big_endian = TactileFrames(np.zeros((1, 2, 2), dtype=swapped))
    with pytest.raises(InputError, match="dtype"):
        write_recording(big_endian, tmp_path / "x.h5")
    if np.dtype(np.longdouble) != np.dtype(np.float64):
        with pytest.raises(InputError, match="dtype"):
            write_recording(TactileFrames(np.zeros((1, 2, 2), np.longdouble)), tmp_path / "x.npz")
    assert list(tmp_path.iterdir()) == []


def test_write_into_missing_folder(tmp_path: Path) -> None:
    with pytest.raises(OutputWriteError, match="does not exist"):
        write_recording(_sample(), tmp_path / "nope" / "x.npz")


def test_failed_write_keeps_existing_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = write_recording(_sample(np.bool_), tmp_path / "keep.h5")
    before = path.read_bytes()

    def broken(*args: Any, **kwargs: Any) -> None:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(h5py.Group, "create_dataset", broken)
    with pytest.raises(OutputWriteError, match="No space left"):
        write_recording(_sample(), path, force=True)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.h5"]


# ----------------------------------------------------------------------------- CSV encoding
def test_csv_encoding_of_every_float16_is_exact() -> None:
    every = np.arange(2**16, dtype=np.uint16).view(np.float16)
    every = every[np.isfinite(every)]
    back = _parse_cells(_format_cells(every)).astype(np.float16)
    assert np.array_equal(back.view(np.uint16), every.view(np.uint16))


def test_csv_encoding_of_random_float32_bit_patterns_is_exact_and_short() -> None:
    bits = np.random.default_rng(5).integers(0, 2**32, size=50_000, dtype=np.uint64)
    values = bits.astype(np.uint32).view(np.float32)
    values = values[np.isfinite(values)]
    cells = _format_cells(values)
    back = _parse_cells(cells).astype(np.float32)
    assert np.array_equal(back.view(np.uint32), values.view(np.uint32))
    # float32's own shortest form (at most 9 significant digits), not float64's.
    assert max(len(c) for c in cells) <= len("-1.23456789e-38")


@pytest.mark.parametrize(
    "stored", [2.5, np.float32(2.5), np.uint8(2) + 0.5, "2.5", np.array([2.5]), np.array(["2.5"])]
)
def test_npz_pitch_may_be_any_single_number_or_numeric_text(tmp_path: Path, stored: Any) -> None:
    np.savez(tmp_path / "p.npz", frames=np.zeros((1, 1, 1)), pitch_mm=stored)
    assert read_recording(tmp_path / "p.npz").pitch_mm == 2.5


@pytest.mark.parametrize("stored", [True, np.array([1.0, 2.0]), 1j, "2.5 mm"])
def test_npz_pitch_that_is_not_a_number(tmp_path: Path, stored: Any) -> None:
    np.savez(tmp_path / "p.npz", frames=np.zeros((1, 1, 1)), pitch_mm=stored)
    _check_invalid(tmp_path / "p.npz", "pitch_mm")
