"""Real content in: the Khronos sample models in ../shared/assets/gltf (skipped where that folder
is absent) load, render and go through the study; scene files go wherever scene names go."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from gltf_writer import moving_box
from method_picks import EXAMPLE, pick

import blurlab as bl

ASSETS = Path(__file__).resolve().parents[2] / "shared" / "assets" / "gltf"
MODELS = sorted(ASSETS.glob("*/*.gltf")) + sorted(ASSETS.glob("*/*.glb")) if ASSETS.is_dir() else []
SIZE = (160, 90)
needs_assets = pytest.mark.skipif(not MODELS, reason=f"no sample models in {ASSETS}")


@needs_assets
@pytest.mark.parametrize("path", MODELS, ids=lambda p: p.stem)
def test_sample_model_loads_and_renders(ctx, path):
    scene = bl.scenes.gltf(path, size_hint=SIZE)
    frame = ctx.render(scene, SIZE)
    drawn = frame.object_id >= 0
    assert drawn.mean() > 0.005, "the framing camera should show the model"
    assert np.isfinite(frame.motion).all() and np.isfinite(frame.color).all()
    assert np.isfinite(frame.depth[drawn]).all()
    # Over a longer shutter the animation moves pixels (every sample model is animated).
    t0 = scene.shutter[0]
    moving = ctx.render(scene, SIZE, shutter=(t0, t0 + 0.25))
    assert np.abs(moving.motion).max() > 1.0


@needs_assets
def test_sample_models_go_through_a_sweep(ctx):
    table = bl.sweep(
        ctx,
        [str(p) for p in MODELS] + ["teapot_pass"],
        {EXAMPLE: {"k": [4]}, pick(params=("taps",)): {"taps": [8]}},
        size=(96, 54),
        metrics=("psnr",),
        progress=False,
    )
    assert set(table["scene"]) == {p.name for p in MODELS} | {"teapot_pass"}
    assert np.isfinite(table["psnr"]).all()


def test_study_cli_takes_a_file_beside_a_built_in_name(tmp_path):
    scene = moving_box(tmp_path / "moving box.glb")
    out = tmp_path / "study"
    command = [sys.executable, "-m", "blurlab", "study", "--scenes", str(scene), "fan"]
    command += ["--size", "64x36", "--metrics", "psnr", "--out", str(out)]
    result = subprocess.run(command, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr[-2000:]
    report = (out / "report.html").read_text()
    assert "moving box.glb (from " in report  # the report names the file
    assert (out / "moving_box.glb_pareto.png").is_file()
    import pandas as pd

    assert set(pd.read_csv(out / "results.csv")["scene"]) == {"moving box.glb", "fan"}


def test_recommend_cli_takes_a_file_and_refuses_a_missing_one(tmp_path):
    scene = moving_box(tmp_path / "box.gltf")
    command = [sys.executable, "-m", "blurlab", "recommend", str(scene), "--size", "64x36"]
    result = subprocess.run(
        command + ["--budget-ms", "1000"], capture_output=True, text=True, timeout=600
    )
    assert result.returncode == 0, result.stderr[-2000:]
    assert "recommend:" in result.stdout and "box.gltf 64x36" in result.stdout
    missing = subprocess.run(
        [
            sys.executable,
            "-m",
            "blurlab",
            "recommend",
            str(tmp_path / "nope.glb"),
            "--budget-ms",
            "1",
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert missing.returncode == 2
    assert missing.stderr.startswith("blurlab: error:") and "nope.glb" in missing.stderr
    assert "Traceback" not in missing.stderr
