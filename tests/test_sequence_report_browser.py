"""`blurlab study --sequence`'s report in headless Chromium, as tests/test_report_browser.py
drives the study's: a chart per scene with its points, every animation of worst frames
loaded and looping, no console error, nothing asked of the network."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from PIL import Image
from test_report_browser import CHROMIUM, opened

from blurlab import cli

pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="Chromium is not installed")


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("sequence")
    cli.main(
        ["study", "--sequence", "--scenes", "fan", "--size", "32x18", "--out", str(out)]
        + ["--reference-samples", "4"]
    )
    return out / "sequence.html"


def test_the_sequence_report_works_in_a_browser(report, tmp_path):
    with opened(report, tmp_path / "profile", ("file:",)) as browser:
        points = browser.chart_points()
        assert len(points) == 1 and points[0] > 0, points
        images = browser.evaluate(
            "[...document.querySelectorAll('.gallery img')]"
            ".map(i => [i.getAttribute('src'), i.complete && i.naturalWidth])"
        )
        assert images and all(width == 64 for _, width in images), images  # output + reference
    for src, _ in images:
        with Image.open(report.parent / src) as animation:
            assert animation.n_frames > 1 and animation.info.get("loop") == 0


def test_the_sequence_study_writes_its_phases(report):
    """phases.json: each phase the sequence study times, every one of them taken, and the
    evaluations written (the report fixture ran the command)."""
    timing = json.loads((report.parent / "phases.json").read_text())
    assert list(timing["phases_s"]) == ["sequences", "runs", "animations", "html"]
    assert all(seconds > 0 for seconds in timing["phases_s"].values())
    assert timing["size"] == [32, 18] and timing["evaluations"] > 0
    assert set(timing["phases"]) == set(timing["phases_s"])
