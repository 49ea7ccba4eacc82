"""`blurlab study --sequence`'s report in headless Chromium, as tests/test_report_browser.py
drives the study's: a chart per scene with its points, every animation of worst frames
loaded and looping, no console error, nothing asked of the network."""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from PIL import Image
from test_report_browser import CHROMIUM, Browser

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
    browser = Browser(tmp_path / "profile")
    try:
        for domain in ("Page.enable", "Runtime.enable", "Log.enable", "Network.enable"):
            browser.call(domain)
        browser.call("Page.navigate", url=report.as_uri())
        browser.wait_for("Page.loadEventFired")
        points = browser.evaluate(
            "[...document.querySelectorAll('.js-plotly-plot')]"
            ".map(c => c.querySelectorAll('.scatterlayer .point').length)"
        )
        assert len(points) == 1 and points[0] > 0, points
        images = browser.evaluate(
            "[...document.querySelectorAll('.gallery img')]"
            ".map(i => [i.getAttribute('src'), i.complete && i.naturalWidth])"
        )
        assert images and all(width == 64 for _, width in images), images  # output + reference
        time.sleep(0.5)
        browser.call("Runtime.evaluate", expression="1")  # collect the events sent meanwhile
    finally:
        browser.close()
    errors = [
        e
        for e in browser.events
        if e.get("method") == "Runtime.exceptionThrown"
        or (e.get("method") == "Runtime.consoleAPICalled" and e["params"]["type"] == "error")
        or (e.get("method") == "Log.entryAdded" and e["params"]["entry"]["level"] == "error")
    ]
    assert not errors, errors[:3]
    requests = [
        e["params"]["request"]["url"]
        for e in browser.events
        if e.get("method") == "Network.requestWillBeSent"
    ]
    assert requests and all(url.startswith("file:") for url in requests), requests
    for src, _ in images:
        with Image.open(report.parent / src) as animation:
            assert animation.n_frames > 1 and animation.info.get("loop") == 0
