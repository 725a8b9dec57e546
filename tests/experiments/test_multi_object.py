"""The multi-object experiment: scoring from ground truth, Dask equals the pool, CLI output."""

from __future__ import annotations

import json
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pytest

from taxelkit.cli import run
from taxelkit.errors import InputError
from taxelkit.experiments.multi_object import run_multi_object, score_scene
from taxelkit.experiments.report import render_block
from taxelkit.plotting.experiments import plot_experiment
from taxelkit.smart.elimination import explain
from taxelkit.smart.objects import ObjectRecognition, ObjectVerdict


def verdict(track: int, identified: str | None) -> ObjectVerdict:
    return ObjectVerdict(track, 0, 1, 0.0, 0.05, identified, (), explain([]), (), True)


def test_scoring_names_wrong_and_mixed_up_tracks() -> None:
    owner = np.full((4, 2, 4), -1, np.int8)
    owner[:, :, :2] = 0
    owner[:, :, 2:] = 1
    tmap = np.full((4, 2, 4), -1, np.int16)
    tmap[:, :, :2] = 0  # track 0: object 0 throughout
    tmap[:2, :, 2:] = 1  # track 1: object 1 for two frames...
    tmap[2:, :, :1] = 1  # ...then part of object 0's taxels (object 0 keeps the other column)
    tmap[2:, :, 1:2] = 0
    res = ObjectRecognition((verdict(0, "cube"), verdict(1, "cube")), (), 4, tmap)
    outcomes, purities, mixed = score_scene(res, owner, ("cube", "cone"))
    assert purities == (1.0, 0.5)
    # track 1's true object is a tie broken to the first: object 0, named right
    assert outcomes == ("identified", "missed") and mixed == 0
    res = ObjectRecognition((verdict(0, "cube"), verdict(1, "sphere")), (), 4, tmap)
    outcomes, _, mixed = score_scene(res, owner, ("cube", "cone"))
    assert outcomes == ("wrong", "missed") and mixed == 1
    with pytest.raises(InputError, match="track map"):
        score_scene(ObjectRecognition((), (), 4), owner, ("cube", "cone"))


def test_a_tiny_run_is_reproducible_and_the_same_on_dask() -> None:
    rates = (20.0, 100.0)
    here = run_multi_object(seed=1, n_trials=2, engines=["kinematic"], rates_hz=rates, workers=1)
    again = run_multi_object(seed=1, n_trials=2, engines=["kinematic"], rates_hz=rates, workers=2)
    assert here.scenes == again.scenes
    # each scene at each rate, as the sensor gives it, then through every imperfection at once
    assert [(s.n_objects, s.trial, s.rate_hz, s.imperfection) for s in here.scenes] == [
        (n, t, r, f) for n in (2, 3) for t in (0, 1) for r in rates for f in ("none", "all")
    ]
    by_rate = [[s.names for s in here.scenes if s.rate_hz == r] for r in rates]
    assert by_rate[0] == by_rate[1]  # the same objects at every rate
    doc = here.to_json()
    assert doc["summaries"][0]["objects"] == 4 and doc["summaries"][1]["objects"] == 6
    assert "| kinematic | 20 | none |" in render_block("multi-object", {"multi-object": doc})
    # the figure: per engine and count, the outcome shares stack to the whole
    fig = plot_experiment("multi-object", here)
    left = fig.axes[0]
    n_bars = len(doc["summaries"])
    heights = np.array([bar.get_height() for bar in left.patches]).reshape(-1, n_bars)
    assert heights.sum(axis=0) == pytest.approx(np.ones(n_bars))
    ident = [s["identified"] / s["objects"] for s in doc["summaries"]]
    assert list(heights[0]) == pytest.approx(ident)
    plt.close(fig)
    distributed = pytest.importorskip("distributed", reason="needs the dask extra")
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None
    ) as cluster:
        there = run_multi_object(
            seed=1,
            n_trials=2,
            engines=["kinematic"],
            rates_hz=rates,
            scheduler=cluster.scheduler_address,
        )
    assert there.scenes == here.scenes


def test_the_imperfect_views_leave_the_clean_scenes_as_they_were() -> None:
    kw = {"seed": 2, "n_trials": 3, "engines": ["kinematic"], "counts": [2], "workers": 1}
    both = run_multi_object(**kw, rates_hz=[20.0])
    clean = run_multi_object(**kw, rates_hz=[20.0], imperfections=["none"])
    assert clean.imperfections == ("none",)
    assert [s for s in both.scenes if s.imperfection == "none"] == list(clean.scenes)
    imperfect = [s for s in both.scenes if s.imperfection == "all"]
    assert [s.names for s in imperfect] == [s.names for s in clean.scenes]  # the same motion
    doc = both.to_json()
    assert [(s["imperfection"], s["n_objects"]) for s in doc["summaries"]] == [
        ("none", 2),
        ("all", 2),
    ]
    assert set(doc["acceptance_imperfect"]) == {"all"}
    text = render_block("multi-object", {"multi-object": doc})
    assert "| kinematic | 20 | all |" in text and "imperfection all" in text


def test_bad_settings_are_refused() -> None:
    with pytest.raises(InputError, match="n_trials"):
        run_multi_object(n_trials=0)
    with pytest.raises(InputError, match="unknown engine"):
        run_multi_object(engines=["bullet"], n_trials=1)
    with pytest.raises(InputError, match="counts"):
        run_multi_object(counts=[7], n_trials=1)
    with pytest.raises(InputError, match="unknown imperfection"):
        run_multi_object(imperfections=["rust"], n_trials=1)
    with pytest.raises(InputError, match="rates_hz"):
        run_multi_object(rates_hz=[0.0], n_trials=1)


@pytest.mark.slow
def test_reproduce_writes_json_and_png(tmp_path: Path) -> None:
    args = ["reproduce", "multi-object", "--out", str(tmp_path), "--trials", "1"]
    assert run([*args, "--workers", "1"]) == 0
    doc = json.loads((tmp_path / "multi-object.json").read_text())
    assert doc["experiment"] == "multi-object" and doc["scenes"]
    assert (tmp_path / "multi-object.png").stat().st_size > 10_000


def test_recognize_reports_one_verdict_per_object(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    from taxelkit.io.recordings import write_recording
    from taxelkit.motion.multi_scenes import frames_from_multi_scene, multi_scene

    scene = multi_scene(["cube", "cone"], rng=4)
    write_recording(frames_from_multi_scene(scene, rng=4).recording, tmp_path / "two.h5")
    capsys.readouterr()
    assert run(["recognize", str(tmp_path / "two.h5"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert sorted(o["identified"] for o in out["objects"] if o["accepted"]) == ["cone", "cube"]
    assert {e["kind"] for e in out["track_events"]} >= {"birth", "death", "identified"}
    assert run(["recognize", str(tmp_path / "two.h5")]) == 0
    text = capsys.readouterr().out
    assert "identified: cone (object 0); cube (object 1)" in text
    assert "object 1: frames" in text and "identified cube" in text


@pytest.mark.parametrize("per_frame", [False, True])
def test_recognize_json_streams_the_document_json_dumps_would_print(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    per_frame: bool,
) -> None:
    """The long lists are written a few items at a time; the text is that of the whole document."""
    import taxelkit.cli.recognize_output as output

    monkeypatch.setattr(output, "_ITEMS_A_WRITE", 3)
    from taxelkit.io.recordings import read_recording, write_recording
    from taxelkit.motion.multi_scenes import frames_from_multi_scene, multi_scene
    from taxelkit.smart.objects import recognise_objects
    from taxelkit.smart.recognise_chunks import ChunkRecogniser

    scene = multi_scene(["cylinder", "tetrahedron"], rng=7)
    path = tmp_path / "two.npz"
    write_recording(frames_from_multi_scene(scene, rng=7).recording, path)
    rec = read_recording(path)
    whole = ChunkRecogniser(rec.frames.shape[1:], pitch_mm=rec.pitch_mm, per_frame=per_frame)
    whole.push(rec.frames, rec.t_s)
    doc = whole.result().to_json(per_frame=per_frame)
    doc.update(recognise_objects(rec).to_json())
    capsys.readouterr()
    assert run(["recognize", str(path), "--json", *(["--per-frame"] if per_frame else [])]) == 0
    assert capsys.readouterr().out == json.dumps(doc) + "\n"
    assert len(doc["class_segments"]) > 5 and len(doc["track_events"]) > 5
