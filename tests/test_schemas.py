"""Every file format and every ``--json`` output validates against its schema in docs/schemas/.

Binary files are described by a *manifest* (docs/schemas.md): the arrays of an
``.npz`` with their dtype, shape and (0-d) value; the datasets and attributes
of an ``.h5``; the comment lines, header and line lengths of a ``.csv``; the
fields of a live packet read with :mod:`struct` from the documented layout.
The manifests are built here from files written by taxelkit's own writers,
independently of its readers.
"""

from __future__ import annotations

import io
import json
import re
import struct
import zipfile
import zlib
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from click.testing import CliRunner

from taxelkit.cli import cli

jsonschema = pytest.importorskip("jsonschema", reason="the schema tests need the test extra")

ROOT = Path(__file__).resolve().parents[1]
SCHEMAS = ROOT / "docs" / "schemas"
RESULTS = ROOT / "docs" / "results"


def schema(name: str) -> dict[str, Any]:
    doc: dict[str, Any] = json.loads((SCHEMAS / f"{name}.schema.json").read_text("utf-8"))
    return doc


def errors(name: str, doc: Any) -> list[str]:
    """Validation errors of ``doc`` against schema ``name`` (empty: valid)."""
    v = jsonschema.Draft202012Validator(schema(name))
    return [f"{'/'.join(map(str, e.absolute_path))}: {e.message}" for e in v.iter_errors(doc)]


def assert_valid(name: str, doc: Any) -> None:
    found = errors(name, doc)
    assert not found, "\n".join(found[:10])


# ------------------------------------------------------------------ manifests of binary files


def npz_manifest(path: Path) -> dict[str, Any]:
    """``{member: {dtype, shape[, value]}}`` of an ``.npz``, read member by member."""
    out: dict[str, Any] = {}
    with zipfile.ZipFile(path) as z:
        for name in z.namelist():
            arr = np.lib.format.read_array(io.BytesIO(z.read(name)), allow_pickle=False)
            entry: dict[str, Any] = {"dtype": arr.dtype.str, "shape": list(arr.shape)}
            if arr.ndim == 0:
                entry["value"] = arr.item()
            out[name.removesuffix(".npy")] = entry
    return out


def _attrs(obj: Any) -> dict[str, Any]:
    return {k: (v.item() if isinstance(v, np.generic) else v) for k, v in obj.attrs.items()}


def h5_manifest(path: Path) -> dict[str, Any]:
    """``{datasets: {name: {dtype, shape, attrs}}, attrs: {...}}`` of an HDF5 file's root."""
    import h5py

    with h5py.File(path, "r") as f:
        datasets = {
            name: {"dtype": obj.dtype.str, "shape": list(obj.shape), "attrs": _attrs(obj)}
            for name, obj in f.items()
            if isinstance(obj, h5py.Dataset)
        }
        return {"datasets": datasets, "attrs": _attrs(f)}


def csv_manifest(path: Path) -> dict[str, Any]:
    """Comment lines, header, data lines and their cell counts of a ``.csv``."""
    lines = path.read_text(encoding="utf-8").splitlines()
    meta = [ln for ln in lines if ln.startswith("#")]
    body = [ln for ln in lines if ln and not ln.startswith("#")]
    pairs = [re.match(r"#\s*([^:]+):\s*(.*)$", ln) for ln in meta]
    return {
        "metadata": {m.group(1).strip(): m.group(2).strip() for m in pairs if m},
        "header": body[0].split(","),
        "rows": len(body) - 1,
        "cells_per_line": sorted({len(ln.split(",")) for ln in body[1:]}),
    }


def packet_fields(packet: bytes) -> dict[str, Any]:
    """The fields of one live packet, read as docs/live-protocol.md lays them out."""
    magic = packet[:4].decode("ascii")
    if magic == "TXK2":
        index, t_s, array_id, rows, cols, ptype = struct.unpack_from("<IdHHHB", packet, 4)
        head = 23
    else:
        index, t_s, rows, cols, ptype = struct.unpack_from("<IdHHB", packet, 4)
        head, array_id = 21, None
    (crc,) = struct.unpack_from("<I", packet, len(packet) - 4)
    out = {
        "magic": magic,
        "index": index,
        "t_s": t_s,
        "rows": rows,
        "cols": cols,
        "payload_type": ptype,
        "payload_bytes": len(packet) - head - 4,
        "crc": crc,
        "crc_ok": crc == zlib.crc32(packet[4:-4]),
    }
    if array_id is not None:
        out["array_id"] = array_id
    return out


# ------------------------------------------------------------------ real outputs


@pytest.fixture(scope="module")
def roll(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A simulated roll written in every plain format, float and contact, and packed."""
    from taxelkit.frames import TactileFrames
    from taxelkit.io.chunked_write import RecordingAppender
    from taxelkit.io.recordings import write_recording
    from taxelkit.motion.rolling import frames_from_scenario
    from taxelkit.motion.scenarios import make_scenario
    from taxelkit.sensors.presets import BONNEVILLE_16X16

    out = tmp_path_factory.mktemp("roll")
    rec = frames_from_scenario(BONNEVILLE_16X16, make_scenario("cylinder", rng=3), rng=3)
    contact = TactileFrames(
        BONNEVILLE_16X16.contact_from_displacement(rec.frames), rec.t_s, rec.pitch_mm,
        sensor=rec.sensor,
    )  # fmt: skip
    paths = {}
    for label, r in (("float", rec), ("contact", contact)):
        for ext in ("npz", "h5", "csv", "mcap"):
            paths[f"{label}.{ext}"] = out / f"{label}.{ext}"
            write_recording(r, paths[f"{label}.{ext}"])
    paths["packed.h5"] = out / "packed.h5"
    with RecordingAppender(
        paths["packed.h5"], shape=(16, 16), pitch_mm=rec.pitch_mm, dtype=bool
    ) as a:
        a.append(contact.frames, contact.t_s)
    return paths


@pytest.mark.parametrize("label", ["float", "contact"])
def test_recordings_match_their_schemas(roll: dict[str, Path], label: str) -> None:
    assert_valid("recording-npz", npz_manifest(roll[f"{label}.npz"]))
    assert_valid("recording-h5", h5_manifest(roll[f"{label}.h5"]))
    assert_valid("recording-csv", csv_manifest(roll[f"{label}.csv"]))


def test_packed_h5_recording_matches_its_schema(roll: dict[str, Path]) -> None:
    manifest = h5_manifest(roll["packed.h5"])
    assert "frames_packed" in manifest["datasets"] and "frames" not in manifest["datasets"]
    assert_valid("recording-h5", manifest)


@pytest.mark.parametrize("label", ["float", "contact"])
def test_bag_info_message_matches_its_schema(roll: dict[str, Path], label: str) -> None:
    pytest.importorskip("mcap", reason="MCAP needs the ros extra")
    from mcap.reader import make_reader
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    with roll[f"{label}.mcap"].open("rb") as f:
        infos = [
            store.deserialize_cdr(m.data, "std_msgs/msg/String").data
            for _, ch, m in make_reader(f).iter_messages()
            if ch.topic.endswith("/info")
        ]
    assert len(infos) == 1
    assert_valid("recording-bag-info", json.loads(infos[0]))


@pytest.mark.parametrize(("label", "ext"), [("float", "h5"), ("contact", "npz"), ("float", "csv")])
def test_info_json_matches_its_schema(roll: dict[str, Path], label: str, ext: str) -> None:
    res = CliRunner().invoke(cli, ["info", str(roll[f"{label}.{ext}"]), "--json"])
    assert res.exit_code == 0, res.output
    assert_valid("cli-info", json.loads(res.output))


@pytest.mark.parametrize("per_frame", [False, True])
def test_recognize_json_matches_its_schema(roll: dict[str, Path], per_frame: bool) -> None:
    argv = ["recognize", str(roll["float.h5"]), "--json", *(["--per-frame"] if per_frame else [])]
    res = CliRunner().invoke(cli, argv)
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    assert_valid("cli-recognize", doc)
    assert ("classes" in doc) is per_frame and doc["identified"] == "cylinder"


def test_live_packets_match_their_schema() -> None:
    from taxelkit.io.frame_packet import encode_frame

    frames = [
        np.eye(3, 4, dtype=bool),
        np.arange(12, dtype=np.uint16).reshape(3, 4),
        np.linspace(0.0, 0.3, 12, dtype=np.float32).reshape(3, 4),
    ]
    for ptype, values in enumerate(frames):
        for array_id in (None, 7):
            packet = encode_frame(values, index=2**32 - 1, t_s=0.25, array_id=array_id)
            fields = packet_fields(packet)
            assert_valid("live-packet", fields)
            assert fields["payload_type"] == ptype
            assert fields["payload_bytes"] == 12 * values.dtype.itemsize
            assert ("array_id" in fields) is (array_id is not None)


@pytest.fixture(scope="module")
def specimen(tmp_path_factory: pytest.TempPathFactory) -> Path:
    from taxelkit.world.heightmap import heightmap_from_relief
    from taxelkit.world.relief import relief_shape

    path = tmp_path_factory.mktemp("specimen") / "square.npz"
    hm = heightmap_from_relief(
        relief_shape("square", diameter_mm=60.0, step_height_um=200),
        pixel_mm=0.5,
        extent_mm=(-40, 40, -40, 40),
    )
    np.savez(path, **hm.to_arrays())
    return path


def test_heightmap_matches_its_schema(specimen: Path) -> None:
    assert_valid("heightmap-npz", npz_manifest(specimen))


def test_memory_and_trace_json_match_their_schemas(specimen: Path, tmp_path: Path) -> None:
    mem = tmp_path / "mem.npz"
    argv = ["memorise", "--specimen", str(specimen), "--name", "sq", "--out", str(mem)]
    res = CliRunner().invoke(cli, argv)
    assert res.exit_code == 0, res.output
    assert_valid("memory-npz", npz_manifest(mem))
    for extra in ([], ["--memory", str(mem)]):
        argv = ["trace", "--specimen", str(specimen), "--json", *extra]
        res = CliRunner().invoke(cli, argv)
        assert res.exit_code == 0, res.output
        assert_valid("cli-trace", json.loads(res.output))


def test_committed_results_and_timings_match_their_schemas() -> None:
    for path in sorted(RESULTS.glob("*.json")):
        doc = json.loads(path.read_text(encoding="utf-8"))
        if path.name.endswith(".timing.json"):
            assert_valid("experiment-timing", doc)
            assert doc["experiment"] == path.name.removesuffix(".timing.json")
        else:
            assert_valid("experiment-result", doc)
            assert doc["experiment"] == path.stem


def test_object_table_matches_its_schema(tmp_path: Path) -> None:
    from taxelkit.smart.object_table import ObjectRow, ObjectTable, dumps, read_object_table
    from taxelkit.smart.tacteme_table import Tacteme

    row = ObjectRow(
        "hex-prism",
        frozenset({Tacteme.LC, Tacteme.AC}),
        ((Tacteme.LC, "its edges"),),
        "hex_prism.stl",
        {"trials": 2},
    )
    path = tmp_path / "objects.json"
    path.write_text(dumps(ObjectTable((row,))), encoding="utf-8")
    doc = json.loads(path.read_text(encoding="utf-8"))
    assert_valid("object-table", doc)
    assert read_object_table(path).objects == ("hex-prism",)
    assert errors("object-table", {**doc, "version": 2})  # newer versions are refused
    bad = {**doc, "objects": [{**doc["objects"][0], "name": "cube"}]}
    assert errors("object-table", bad)  # one of the six


def test_benchmark_records_match_their_schema() -> None:
    records = sorted((RESULTS / "bench").glob("*.json"))
    assert records
    for path in records:
        doc = json.loads(path.read_text(encoding="utf-8"))
        assert_valid("bench-record", doc)
        assert doc["script"] == f"{path.stem}.py"


# ------------------------------------------------------------------ the schemas themselves

ALL = sorted(p.name.removesuffix(".schema.json") for p in SCHEMAS.glob("*.schema.json"))


@pytest.mark.parametrize("name", ALL)
def test_schema_is_valid_and_documented(name: str) -> None:
    jsonschema.Draft202012Validator.check_schema(schema(name))
    page = (ROOT / "docs" / "schemas.md").read_text(encoding="utf-8")
    assert f"schemas/{name}.schema.json" in page


@pytest.mark.parametrize("name", [n for n in ALL if schema(n).get("required")])
def test_schema_refuses_a_document_missing_a_required_field(name: str) -> None:
    doc = {k: None for k in schema(name)["required"]}
    for key in schema(name)["required"]:
        partial = {k: v for k, v in doc.items() if k != key}
        assert any(key in e for e in errors(name, partial)), key


def test_schemas_refuse_wrong_values() -> None:
    info = {"file": "a.h5", "sensor": "s", "frames": 2, "rows": 1, "cols": 1, "pitch_mm": 1.0,
            "units": "mm", "dtype": "float32", "duration_s": 1.0, "rate_hz": 1.0, "min": 0.0,
            "max": 1.0}  # fmt: skip
    assert not errors("cli-info", info)
    assert errors("cli-info", {**info, "pitch_mm": 0.0})
    assert errors("cli-info", {**info, "contact_fraction": 0.5})  # only for contact frames
    assert errors("cli-info", {**info, "dtype": "bool"})  # contact frames need contact_fraction
    fields = packet_fields(b"TXK1" + struct.pack("<IdHHB", 0, 0.0, 1, 1, 0) + b"\x01" + b"\0" * 4)
    assert errors("live-packet", fields)  # the CRC does not match
