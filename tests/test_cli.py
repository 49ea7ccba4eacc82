"""The command line: `blurlab info` and the demo that the README's main command runs."""

from __future__ import annotations

import json

import numpy as np
import pytest

import blurlab as bl
from blurlab import cli


def test_info_prints_json(capsys):
    assert cli.main(["--device", "software", "info"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["context"]["device"] == "software"


def test_demo_writes_pattern_files(tmp_path, capsys):
    assert cli.main(["demo", "--size", "160x90", "--out", str(tmp_path)]) == 0
    exr = bl.io.read(tmp_path / "test_pattern.exr")
    png = bl.io.read(tmp_path / "test_pattern.png")
    assert exr.shape == (90, 160, 4) and png.shape == (90, 160, 3)
    np.testing.assert_allclose(exr[..., :3], bl.reference.test_pattern(160, 90)[..., :3], atol=1e-7)
    assert "ms (" in capsys.readouterr().out


def test_bad_size_is_rejected():
    with pytest.raises(SystemExit):
        cli.main(["demo", "--size", "160by90"])
