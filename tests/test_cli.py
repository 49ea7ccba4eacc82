"""The command line: `blurlab info` and the demo that the README's main command runs."""

from __future__ import annotations

import json

import numpy as np
import pytest

import blurlab as bl
from blurlab import cli


def test_info_prints_json(capsys):
    assert cli.main(["info"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["context"]["device"] in ("gpu", "software")
    assert report["devices"] == bl.Context.devices()


def test_demo_renders_blurs_and_writes(tmp_path, capsys):
    assert cli.main(["demo", "--size", "160x90", "--out", str(tmp_path)]) == 0
    assert bl.io.read(tmp_path / "test_pattern.png").shape == (90, 160, 3)
    for name in bl.scenes.names():
        sharp = bl.io.read(tmp_path / f"{name}_sharp.png")
        blurred = bl.io.read(tmp_path / f"{name}_blurred.png")
        assert sharp.shape == blurred.shape == (90, 160, 4)
        gbuffer = bl.io.read(tmp_path / f"{name}_gbuffer.exr")
        assert gbuffer.shape == (90, 160, 7) and gbuffer.dtype == np.float32
    printed = capsys.readouterr().out
    assert "largest difference from NumPy" in printed and "teapot_pass" in printed


def test_bad_size_is_rejected():
    with pytest.raises(SystemExit):
        cli.main(["demo", "--size", "160by90"])
