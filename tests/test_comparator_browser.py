"""The "look closer" comparator (blurlab.studies.comparator) in headless Chromium, driven over the
DevTools protocol as tests/test_report_browser.py drives the report: a mouse drag on the split
line moves the split in every panel, the wheel zooms every panel alike down to single pixels
drawn as squares, a drag pans them together, the error toggle swaps the method's picture for
its error map, and the exposure control redraws an HDR panel. Every assertion reads the page's
state (Runtime.evaluate) after real input events. 160x90 images; skips without Chromium."""

from __future__ import annotations

import base64
import io
import time
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from test_report_browser import CHROMIUM, opened

from blurlab import metrics
from blurlab.studies import comparator

pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="Chromium is not installed")

WIDTH, HEIGHT = 160, 90
SDR = "#look-sdr"
HDR = "#look-hdr"


def pictures(peak: float) -> tuple[np.ndarray, dict]:
    """A reference with one-pixel detail (a checkerboard under a gradient) and two 'methods'."""
    y, x = np.mgrid[0:HEIGHT, 0:WIDTH]
    checker = ((x + y) % 2).astype(np.float32)
    reference = np.stack([x / WIDTH, y / HEIGHT, 0.25 + 0.5 * checker], -1).astype(np.float32)
    reference *= peak
    shifted = np.roll(reference, 3, axis=1)
    dimmed = reference * np.float32(0.8)
    return reference, {"shifted": shifted, "dimmed": dimmed}


@pytest.fixture(scope="module")
def page(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("look")
    parts = ["<!doctype html><meta charset='utf-8'><title>look</title>", comparator.assets_html()]
    for name, peak, hdr in (("sdr", 1.0, False), ("hdr", 40.0, True)):
        reference, images = pictures(peak)
        fragment, pending = comparator.write_comparator(name, reference, images, out, hdr=hdr)
        assert pending == []  # no pool: written before it returned
        parts.append(fragment)
    path = out / "page.html"
    path.write_text("\n".join(parts))
    return path


@pytest.fixture(scope="module")
def browser(page, tmp_path_factory):
    with opened(page, tmp_path_factory.mktemp("profile"), ("file:",)) as browser:
        deadline = time.monotonic() + 30
        ready = "window.blurlabLooks.every(r => r.look.state().ready)"
        while not browser.evaluate(f"window.blurlabLooks.length == 2 && {ready}"):
            assert time.monotonic() < deadline, "the comparators did not get ready"
            time.sleep(0.1)
        yield browser


def state(browser, root: str) -> dict:
    return browser.evaluate(f"document.querySelector('{root}').look.state()")


def box(browser, selector: str) -> dict:
    """The element's box on the page (CSS px), scrolled into view."""
    return browser.evaluate(
        f"(() => {{ const e = document.querySelector('{selector}'); e.scrollIntoView();"
        " const b = e.getBoundingClientRect();"
        " return {x: b.left, y: b.top, width: b.width, height: b.height}; })()"
    )


def mouse(browser, kind: str, x: float, y: float, **extra) -> None:
    browser.call("Input.dispatchMouseEvent", type=kind, x=x, y=y, **extra)


def drag(browser, start: tuple[float, float], end: tuple[float, float], steps: int = 5) -> None:
    mouse(browser, "mousePressed", *start, button="left", buttons=1, clickCount=1)
    for i in range(1, steps + 1):
        f = i / steps
        point = (start[0] + f * (end[0] - start[0]), start[1] + f * (end[1] - start[1]))
        mouse(browser, "mouseMoved", *point, button="left", buttons=1)
    mouse(browser, "mouseReleased", *end, button="left", buttons=0, clickCount=1)
    settle(browser)


def settle(browser) -> None:
    """Two animation frames: Panzoom applies its transform in one."""
    browser.evaluate(
        "new Promise(r => requestAnimationFrame(() => requestAnimationFrame(() => r(1))))"
    )
    time.sleep(0.05)


def test_a_drag_on_the_split_line_moves_the_split_in_every_panel(browser):
    view = box(browser, f"{SDR} .bl-look-panel:nth-child(2) .bl-look-view")
    handle = box(browser, f"{SDR} .bl-look-panel:nth-child(2) .bl-look-handle")
    assert state(browser, SDR)["split"] == 0.5
    start = (handle["x"] + handle["width"] / 2, handle["y"] + handle["height"] / 2)
    end = (view["x"] + 0.8 * view["width"], start[1])
    drag(browser, start, end)
    split = state(browser, SDR)["split"]
    assert split == pytest.approx(0.8, abs=0.01)
    clips = browser.evaluate(
        f"[...document.querySelectorAll('{SDR} .bl-look-top')].map(t => t.style.clipPath)"
    )
    assert len(clips) == 2 and len(set(clips)) == 1 and "80" in clips[0], clips
    browser.evaluate(f"document.querySelector('{SDR}').look.setSplit(0.5)")


def test_the_wheel_zooms_every_panel_down_to_single_pixels(browser):
    view = box(browser, f"{SDR} .bl-look-panel:nth-child(2) .bl-look-view")
    before = state(browser, SDR)
    assert before["scale"] == 1 and before["pixel"] == pytest.approx(2.0)  # 160 px shown at 320
    centre = (view["x"] + 0.3 * view["width"], view["y"] + 0.4 * view["height"])
    for _ in range(20):  # each tick zooms by exp(0.2); the deepest zoom takes 14
        mouse(browser, "mouseWheel", *centre, deltaX=0, deltaY=-120)
    settle(browser)
    after = state(browser, SDR)
    assert after["pixel"] == pytest.approx(comparator.MAX_PIXEL_SIZE, rel=1e-6), after
    assert len(set(after["transforms"])) == 1 and "scale(16)" in after["transforms"][0]
    # The zoom kept the point under the wheel (in panel 2, though Panzoom measures panel 1)
    # where it was: its place on the unzoomed stage is where the wheel turned, to 0.1 px.
    for axis, size, shift in ((0, view["width"], after["x"]), (1, view["height"], after["y"])):
        under = centre[axis] - (view["x"], view["y"])[axis]
        unzoomed = (under - size / 2) / after["scale"] + size / 2 - shift
        assert unzoomed == pytest.approx(under, abs=0.1), (axis, after)
    rendering = browser.evaluate(
        f"[...document.querySelectorAll('{SDR} .bl-look-stage img')]"
        ".map(i => getComputedStyle(i).imageRendering)"
    )
    assert rendering and set(rendering) == {"pixelated"}, rendering
    # What the screen shows: the one-pixel checkerboard as squares of 32 screen pixels.
    scroll = browser.evaluate("[scrollX, scrollY]")  # a clip is in page coordinates
    clip = {"x": view["x"] + scroll[0], "y": view["y"] + scroll[1], "width": 128, "height": 128}
    shot = browser.call("Page.captureScreenshot", format="png", clip=clip | {"scale": 1})
    screen = np.asarray(Image.open(io.BytesIO(base64.b64decode(shot["data"]))).convert("RGB"))
    blue = screen[..., 2].astype(int)
    runs = np.flatnonzero(np.diff(blue[64]) != 0)  # where the row's colour changes
    gaps = np.diff(runs)
    assert len(runs) >= 2 and np.all(np.abs(gaps - 32) <= 1), runs


def test_a_drag_pans_every_panel_together(browser):
    view = box(browser, f"{SDR} .bl-look-panel:nth-child(1) .bl-look-view")
    before = state(browser, SDR)
    assert before["scale"] > 1  # zoomed by the test before
    start = (view["x"] + 0.2 * view["width"], view["y"] + 0.5 * view["height"])
    drag(browser, start, (start[0] + 40, start[1] + 20))
    after = state(browser, SDR)
    assert after["x"] != before["x"] and after["y"] != before["y"], (before, after)
    assert after["split"] == 0.5  # a drag off the line does not move it
    assert len(set(after["transforms"])) == 1
    browser.evaluate(f"document.querySelector('{SDR} .bl-look-fit').click()")
    settle(browser)
    assert state(browser, SDR)["scale"] == 1
    button = box(browser, f"{SDR} .bl-look-in")
    point = (button["x"] + button["width"] / 2, button["y"] + button["height"] / 2)
    mouse(browser, "mousePressed", *point, button="left", buttons=1, clickCount=1)
    mouse(browser, "mouseReleased", *point, button="left", buttons=0, clickCount=1)
    settle(browser)
    assert state(browser, SDR)["scale"] == pytest.approx(np.exp(0.6))  # Panzoom's step
    browser.evaluate(f"document.querySelector('{SDR} .bl-look-fit').click()")
    settle(browser)


@pytest.mark.parametrize("root", [SDR, HDR])
def test_the_error_toggle_shows_the_error_map(browser, root):
    # Each of the first panel's top pictures: its class and the width it is drawn at (0: not
    # drawn at all, as a hidden one or one caught inside another element).
    shown = (
        f"[...document.querySelectorAll('{root} .bl-look-panel:nth-child(1) .bl-look-top *')]"
        ".filter(e => e.matches('img, canvas'))"
        ".map(e => [e.className, e.getBoundingClientRect().width])"
    )
    assert browser.evaluate(shown) == [["bl-look-method", 320], ["bl-look-error", 0]]
    toggle = box(browser, f"{root} .bl-look-error-toggle")
    point = (toggle["x"] + toggle["width"] / 2, toggle["y"] + toggle["height"] / 2)
    mouse(browser, "mousePressed", *point, button="left", buttons=1, clickCount=1)
    mouse(browser, "mouseReleased", *point, button="left", buttons=0, clickCount=1)
    settle(browser)
    assert state(browser, root)["error"] is True
    assert browser.evaluate(shown) == [["bl-look-method", 0], ["bl-look-error", 320]]
    browser.evaluate(f"document.querySelector('{root}').look.setError(false)")


def hdr_pixel(browser, x: int, y: int) -> list[int]:
    """The HDR method panel's displayed sRGB pixel (x, y) of the image."""
    return browser.evaluate(
        f"[...document.querySelector('{HDR} canvas.bl-look-method').getContext('2d')"
        f".getImageData({x}, {y}, 1, 1).data].slice(0, 3)"
    )


def test_exposure_redraws_the_hdr_panels(browser):
    before = hdr_pixel(browser, 40, 20)
    assert 0 < max(before) < 255, before  # tone-mapped at the scene's exposure
    slider = box(browser, f"{HDR} .bl-look-exposure")
    # A click at the slider's right end: +8 stops.
    point = (slider["x"] + slider["width"] - 2, slider["y"] + slider["height"] / 2)
    mouse(browser, "mousePressed", *point, button="left", buttons=1, clickCount=1)
    mouse(browser, "mouseReleased", *point, button="left", buttons=0, clickCount=1)
    settle(browser)
    assert state(browser, HDR)["exposure"] == comparator.EXPOSURE_STOPS
    after = hdr_pixel(browser, 40, 20)
    assert all(a >= b for a, b in zip(after, before, strict=True)) and after != before
    reference = browser.evaluate(
        f"[...document.querySelector('{HDR} .bl-look-stage canvas').getContext('2d')"
        ".getImageData(40, 20, 1, 1).data].slice(0, 3)"
    )
    assert reference != before  # the reference panel was redrawn too, not only the method's


def test_the_hdr_panel_shows_what_the_study_shows(browser):
    """At 0 stops the page's tone mapping of its RGBE data is the study's (plots.tone_mapped)
    to within one 8-bit step (the 16-bit log codes are 0.07 % apart)."""
    browser.evaluate(f"document.querySelector('{HDR}').look.setExposure(0)")
    reference, images = pictures(40.0)
    exposure = metrics.exposure(reference)
    expected = np.round(metrics.tone_map(images["shifted"], exposure) * 255)
    shown = np.array(
        browser.evaluate(
            f"[...document.querySelector('{HDR} canvas.bl-look-method').getContext('2d')"
            f".getImageData(0, 0, {WIDTH}, {HEIGHT}).data]"
        )
    ).reshape(HEIGHT, WIDTH, 4)[..., :3]
    assert np.abs(shown - expected).max() <= 1
