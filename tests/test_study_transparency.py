"""The study's report on transparency scenes (docs/study.md, docs/transparency.md)."""

import pandas as pd
from method_picks import pick

import blurlab as bl
from blurlab import cli
from blurlab.methods.layers import TRANSLUCENCY
from blurlab.studies import study
from blurlab.studies.study import run_study

LAYER = pick(role="translucent_layer")  # what blurs the translucent layer
GATHER = pick(kind="gather", params=("taps",))  # a gather with taps, beside it
RENDERS = pick(kind="render", params=("samples",))  # a method that renders its own sub-frames


def test_a_transparency_scene_gets_the_four_ways_to_blur_it(ctx, tmp_path):
    grids = {GATHER: {}, LAYER: {}, RENDERS: {"samples": [4]}}
    report = run_study(
        ctx,
        ["moving_glass", "fan"],
        size=(160, 90),
        out=tmp_path,
        reference_samples=16,
        grids=grids,
        progress=False,
        chart_processes=0,
    ).read_text()
    table = pd.read_csv(tmp_path / "moving_glass_transparency.csv")
    # Every one-frame method of the grids under every approach; the render method renders its own.
    assert sorted(table["method"].unique()) == sorted([GATHER, LAYER])
    assert sorted(table["translucency"].unique()) == sorted(TRANSLUCENCY.kind)
    assert len(table) == 2 * len(TRANSLUCENCY.kind)
    assert (tmp_path / "moving_glass_translucency.png").is_file()
    assert report.count("Four ways to blur its translucent surfaces") == 1  # not for fan
    assert not (tmp_path / "fan_transparency.csv").exists()
    # The pane moves over a still wall: only the layered blur gives it its own motion.
    layered = table[table["translucency"] == "layered"].set_index("method")["psnr"]
    composite = table[table["translucency"] == "composite"].set_index("method")["psnr"]
    assert (layered > composite + 1).all()
    assert layered[LAYER] > composite[LAYER] + 3


def test_the_study_command_adds_the_transparency_scenes(tmp_path, monkeypatch):
    monkeypatch.setattr(study, "default_grids", lambda: {LAYER: {}})
    out = tmp_path / "study"
    argv = ["study", "--scenes", "fan", "--transparency", "--size", "48x27"]
    assert cli.main([*argv, "--reference-samples", "8", "--out", str(out)]) == 0
    names = bl.scenes.names("transparency")
    table = pd.read_csv(out / "results.csv")
    assert sorted(table["scene"].unique()) == sorted(["fan", *names])
    for name in names:
        assert (out / f"{name}_transparency.csv").is_file()
    assert not (out / "fan_transparency.csv").exists()
