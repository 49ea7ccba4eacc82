"""The study report in a real browser (Debian's headless Chromium, driven over the DevTools
protocol): no console error, every chart drawn with its points, a hover shows the parameters,
and the page asks the network for nothing. A screenshot lands in the test's folder.
Skips where Chromium is not installed (.ci/install-deps installs it for CI)."""

from __future__ import annotations

import base64
import json
import re
import shutil
import subprocess
import time
import urllib.request
from contextlib import contextmanager
from pathlib import Path

import pandas as pd
import pytest

from blurlab import cli

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
pytestmark = pytest.mark.skipif(CHROMIUM is None, reason="Chromium is not installed")


class Browser:
    """One headless Chromium and a DevTools connection to its page."""

    def __init__(self, profile: Path):
        import websocket  # websocket-client, in the test extra

        self.process = subprocess.Popen(
            [
                CHROMIUM,
                "--headless=new",
                "--no-sandbox",
                "--disable-gpu",
                "--no-first-run",
                "--remote-debugging-port=0",
                f"--user-data-dir={profile}",
                "--window-size=1280,1600",
                "about:blank",
            ],
            stderr=subprocess.PIPE,
            text=True,
        )
        port = self._port()
        pages = json.loads(
            urllib.request.urlopen(f"http://127.0.0.1:{port}/json", timeout=10).read()
        )
        url = next(p["webSocketDebuggerUrl"] for p in pages if p["type"] == "page")
        self.socket = websocket.create_connection(url, timeout=30, suppress_origin=True)
        self.next_id = 0
        self.events: list[dict] = []

    def _port(self) -> int:
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            line = self.process.stderr.readline()
            match = re.search(r"DevTools listening on ws://127\.0\.0\.1:(\d+)/", line)
            if match:
                return int(match.group(1))
        raise RuntimeError("Chromium did not open its DevTools port within 30 s")

    def call(self, method: str, **params) -> dict:
        self.next_id += 1
        self.socket.send(json.dumps({"id": self.next_id, "method": method, "params": params}))
        while True:
            message = json.loads(self.socket.recv())
            if message.get("id") == self.next_id:
                if "error" in message:
                    raise RuntimeError(f"{method}: {message['error']}")
                return message.get("result", {})
            self.events.append(message)

    def wait_for(self, event: str, seconds: float = 60) -> None:
        deadline = time.monotonic() + seconds
        while not any(e.get("method") == event for e in self.events):
            if time.monotonic() > deadline:
                raise TimeoutError(event)
            self.events.append(json.loads(self.socket.recv()))

    def evaluate(self, expression: str):
        """The expression's value (a promise's, once it settles)."""
        result = self.call(
            "Runtime.evaluate", expression=expression, returnByValue=True, awaitPromise=True
        )
        if "exceptionDetails" in result:
            raise RuntimeError(result["exceptionDetails"])
        return result["result"].get("value")

    def open(self, page: Path) -> None:
        """Loads `page` with the page, console, log and network events recorded."""
        for domain in ("Page.enable", "Runtime.enable", "Log.enable", "Network.enable"):
            self.call(domain)
        self.call("Page.navigate", url=page.as_uri())
        self.wait_for("Page.loadEventFired")

    def chart_points(self) -> list[int]:
        """How many points each Plotly chart of the page draws."""
        return self.evaluate(
            "[...document.querySelectorAll('.js-plotly-plot')]"
            ".map(c => c.querySelectorAll('.scatterlayer .point').length)"
        )

    def settle(self) -> None:
        """Waits half a second and collects the events the page sent meanwhile."""
        time.sleep(0.5)
        self.call("Runtime.evaluate", expression="1")

    def close(self) -> None:
        self.socket.close()
        self.process.kill()
        self.process.wait(timeout=10)


def page_errors(events: list[dict]) -> list[dict]:
    """The exceptions, console errors and log errors among a page's DevTools events."""
    return [
        e
        for e in events
        if e.get("method") == "Runtime.exceptionThrown"
        or (e.get("method") == "Runtime.consoleAPICalled" and e["params"]["type"] == "error")
        or (e.get("method") == "Log.entryAdded" and e["params"]["entry"]["level"] == "error")
    ]


def requested_urls(events: list[dict]) -> list[str]:
    """Every URL the page asked for."""
    return [
        e["params"]["request"]["url"]
        for e in events
        if e.get("method") == "Network.requestWillBeSent"
    ]


def assert_clean(events: list[dict], schemes: tuple[str, ...]) -> None:
    """No error on the page, and every request (there was one) for a URL of `schemes`."""
    errors = page_errors(events)
    assert not errors, errors[:3]
    requests = requested_urls(events)
    assert requests and all(url.startswith(schemes) for url in requests), requests


@contextmanager
def opened(page: Path, profile: Path, schemes: tuple[str, ...]):
    """A browser with `page` loaded. On leaving, the page must have logged no error and asked
    only for URLs of `schemes`."""
    browser = Browser(profile)
    try:
        browser.open(page)
        yield browser
        browser.settle()
    finally:
        browser.close()
    assert_clean(browser.events, schemes)


@pytest.fixture(scope="module")
def report(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("study")
    cli.main(["study", "--scenes", "fan", "--size", "64x36", "--out", str(out)])
    return out / "report.html"


def test_the_report_works_in_a_browser(report, tmp_path):
    with opened(report, tmp_path / "profile", ("file:", "data:")) as browser:
        points = browser.chart_points()
        assert points and all(n > 0 for n in points), points
        hover = browser.evaluate(
            "(() => { const c = document.querySelector('.js-plotly-plot');"
            " Plotly.Fx.hover(c, [{curveNumber: 0, pointNumber: 0}]);"
            " return c.querySelector('.hoverlayer').textContent; })()"
        )
        assert " ms" in hover and "PSNR" in hover, hover
        assert re.search(r"=|defaults", hover), hover  # the parameters
        # The scene's comparator (blurlab.studies.comparator): a panel per method, every
        # picture loaded at the study's size (tests/test_comparator_browser.py drives it).
        # The pictures load lazily, as they come near the screen; the error maps once shown.
        browser.evaluate("document.querySelector('.blurlab-look').scrollIntoView()")
        shown = "img:not(.bl-look-error)"
        panels = browser.evaluate(
            f"Promise.all([...document.querySelectorAll('.blurlab-look {shown}')]"
            ".map(i => i.decode())).then(() =>"
            " [...document.querySelectorAll('.blurlab-look .bl-look-panel')].map(p =>"
            f" [p.dataset.method, [...p.querySelectorAll('{shown}')].map(i => i.naturalWidth),"
            " p.querySelector('.bl-look-error').getAttribute('src')]))"
        )
        methods = set(pd.read_csv(report.parent / "results.csv")["method"])
        assert {method for method, _, _ in panels} == methods, panels
        assert all(widths == [64, 64] for _, widths, _ in panels), panels
        assert all((report.parent / error).is_file() for _, _, error in panels), panels
        shot = browser.call("Page.captureScreenshot", format="png", captureBeyondViewport=True)
        (tmp_path / "report.png").write_bytes(base64.b64decode(shot["data"]))
