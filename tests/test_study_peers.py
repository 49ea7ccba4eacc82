"""`blurlab study --peers eevee` as docs/study.md gives it: the peers scored with the study's
default metrics, and a scene Blender cannot reproduce says why in its own section of the
report."""

from __future__ import annotations

import html
import re
import shlex
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from method_picks import pick

import blurlab as bl
from blurlab.studies.peers import EEVEE_ROWS
from blurlab.studies.study import run_study

ROOT = Path(__file__).resolve().parents[1]
needs_bpy = pytest.mark.skipif(
    not bl.blender.available(), reason="bpy is not installed (pip install 'blurlab[blender]')"
)


def documented_peers_command() -> str:
    """The one `blurlab study --peers` line of docs/study.md."""
    lines = [
        line.strip()
        for line in (ROOT / "docs" / "study.md").read_text().splitlines()
        if line.startswith("blurlab study --peers")
    ]
    assert len(lines) == 1, lines
    return lines[0]


def scene_sections(report: str) -> dict[str, str]:
    """Each scene's part of report.html, by the scene's name (the <h2> that opens it)."""
    parts = re.split(r"<h2>", report)[1:]
    return {part.split("<", 1)[0].split(" ", 1)[0]: part for part in parts}


def test_peers_run_with_the_default_metrics_and_a_scene_blender_cannot_render_says_why(
    ctx, tmp_path, monkeypatch
):
    # fan has Blinn-Phong specular, which Blender cannot render: its peer rows carry a note
    # and no numbers, so this runs without bpy. metrics=None is the CLI's default.
    monkeypatch.setattr(bl.blender, "available", lambda: True)
    report = run_study(
        ctx,
        ["fan"],
        (48, 32),
        tmp_path,
        reference_samples=8,
        grids={pick(params=("taps",)): {"taps": [4]}},
        progress=False,
        peer_names=("eevee",),
        chart_processes=0,
    )
    peers = pd.read_csv(tmp_path / "peers.csv")
    assert list(peers["method"]) == [label for label, *_ in EEVEE_ROWS]
    assert peers["note"].str.contains("Blinn-Phong").all()
    fan = scene_sections(report.read_text())["fan"]
    assert "Peers not scored on this scene" in fan and "Blinn-Phong specular" in fan


@needs_bpy
def test_the_documented_peers_command_runs(tmp_path):
    command = documented_peers_command()
    scenes = re.search(r"--scenes ((?:\w+ ?)+)", command).group(1).split()
    out = tmp_path / re.search(r"--out (\S+)", command).group(1)
    result = subprocess.run(
        [sys.executable, "-m", "blurlab", *shlex.split(command)[1:]],
        cwd=tmp_path,
        capture_output=True,
        text=True,
    )
    assert result.returncode == 0, result.stderr[-2000:]
    peers = pd.read_csv(out / "peers.csv")
    sections = scene_sections((out / "report.html").read_text())
    for scene in scenes:
        rows = peers[peers["scene"] == scene]
        assert list(rows["method"]) == [label for label, *_ in EEVEE_ROWS]
        if rows["note"].notna().any():  # cannot be rendered: says why, here and in the report
            assert rows["psnr"].isna().all()
            for note in rows["note"]:
                assert note.split(";")[0] in html.unescape(sections[scene])
        else:  # scored with every default metric of the study, as its methods are
            for metric in bl.metrics.default_names(bl.scenes.get(scene).hdr):
                assert np.isfinite(rows[metric]).all(), metric
            assert "Peers not scored" not in sections[scene]
    assert any(peers["note"].isna()) and any(peers["note"].notna())
