"""The study's transparency scenes and its translucency section (docs/transparency.md)."""

import pandas as pd

import blurlab as bl
from blurlab.methods.layers import TRANSLUCENCY
from blurlab.studies.study import run_study


def test_the_study_adds_the_transparency_scenes_and_their_section(ctx, tmp_path):
    grids = {"gather_box": {}, "gather_coverage": {}, "accumulation": {"samples": [4]}}
    report = run_study(
        ctx,
        ["moving_glass"],
        size=(160, 90),
        out=tmp_path,
        reference_samples=16,
        grids=grids,
        progress=False,
        chart_processes=0,
    ).read_text()
    table = pd.read_csv(tmp_path / "transparency.csv")
    # Every one-frame method of the grids under every approach; accumulation renders its own.
    assert sorted(table["method"].unique()) == ["gather_box", "gather_coverage"]
    assert sorted(table["translucency"].unique()) == sorted(TRANSLUCENCY.kind)
    assert len(table) == 2 * len(TRANSLUCENCY.kind)
    assert (tmp_path / "moving_glass_translucency.png").is_file()
    assert "Transparency: four ways to blur" in report
    # The pane moves over a still wall: only the layered blur gives it its own motion.
    layered = table[table["translucency"] == "layered"].set_index("method")["psnr"]
    composite = table[table["translucency"] == "composite"].set_index("method")["psnr"]
    assert (layered > composite + 1).all()
    assert layered["gather_coverage"] > composite["gather_coverage"] + 3


def test_an_opaque_study_has_no_transparency_section_unless_asked(ctx, tmp_path):
    report = run_study(
        ctx,
        ["fan"],
        size=(32, 18),
        out=tmp_path,
        grids={"gather_box": {}},
        progress=False,
        chart_processes=0,
    ).read_text()
    assert "Transparency: four ways" not in report
    assert not (tmp_path / "transparency.csv").exists()
    asked = run_study(
        ctx,
        ["fan"],
        size=(32, 18),
        out=tmp_path / "asked",
        reference_samples=8,
        grids={"gather_box": {}},
        progress=False,
        chart_processes=0,
        transparency_scenes=True,
    ).read_text()
    table = pd.read_csv(tmp_path / "asked" / "transparency.csv")
    assert sorted(table["scene"].unique()) == sorted(bl.scenes.names("transparency"))
    assert "Transparency: four ways" in asked
