"""blurlab.studies.comparator without a browser: what it writes, how HDR images travel (16-bit
log2 codes that decode to within 0.07 %), and the errors bad input gets.
tests/test_comparator_browser.py drives the page itself."""

from __future__ import annotations

import base64
import concurrent.futures
import io
import json
import re

import numpy as np
import pytest
from PIL import Image

from blurlab.studies import comparator


def images(width=16, height=9, peak=1.0):
    rng = np.random.default_rng(1)
    reference = rng.random((height, width, 3), dtype=np.float32) * peak
    return reference, {"a<b>": reference * 0.5, "c": reference[::-1].copy()}


def test_sdr_files_and_fragment(tmp_path):
    reference, methods = images()
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        fragment, pending = comparator.write_comparator(
            "scene", reference, methods, tmp_path, pool=pool
        )
        assert len(pending) == 5  # the reference, two images, two error maps
        for future in pending:
            future.result()
    written = sorted(p.name for p in (tmp_path / comparator.FOLDER).iterdir())
    assert written == [
        "scene_0.png",
        "scene_0_error.png",
        "scene_1.png",
        "scene_1_error.png",
        "scene_reference.png",
    ]
    for src in re.findall(r"src='([^']+)'", fragment):
        assert (tmp_path / src).is_file(), src
    assert "a&lt;b&gt;" in fragment and "a<b>" not in fragment  # names are escaped
    assert fragment.count("class='bl-look-panel'") == 2
    assert "<canvas" not in fragment and "exposure" not in fragment  # HDR only


def decoded(script: str, key: str, width: int, height: int) -> np.ndarray:
    """What comparator.js decodes from the HDR script's picture `key`."""
    data = json.loads(script[script.index("] = ") + 4 : script.rindex(";")])
    png = Image.open(io.BytesIO(base64.b64decode(data["images"][key])))
    assert png.mode == "RGB" and png.size == (2 * width, height)
    pixels = np.asarray(png).astype(np.int64)
    code = 256 * pixels[:, :width] + pixels[:, width:]
    return np.where(code > 0, 2.0 ** (code / data["steps"] - data["offset"]), 0.0)


def test_hdr_images_travel_as_floats(tmp_path):
    reference, methods = images(peak=500.0)
    reference[0, 0] = [0.0, 1e-3, 2e4]  # black, dim and bright channels in one pixel
    fragment, pending = comparator.write_comparator("hdr", reference, methods, tmp_path, hdr=True)
    assert pending == []
    script = (tmp_path / comparator.FOLDER / "hdr.js").read_text()
    back = decoded(script, "reference", 16, 9)
    assert back[0, 0, 0] == 0.0
    np.testing.assert_allclose(back, reference, rtol=2 ** (0.5 / comparator.LOG_STEPS) - 1)
    assert fragment.count("<canvas") == 4 and "bl-look-exposure" in fragment
    assert "hdr.js" in fragment
    # The page itself carries no picture: every one is a file in look/.
    assert len(fragment) < 4000


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (dict(name="../x"), "name"),
        (dict(name=""), "name"),
        (dict(images={}), "non-empty"),
        (dict(images={"a": np.zeros((9, 16, 3), np.uint8)}), "float array"),
        (dict(images={"a": np.zeros((8, 16, 3), np.float32)}), "16x8, the reference 16x9"),
        (dict(images={"a": np.full((9, 16, 3), np.nan, np.float32)}), "NaN"),
        (dict(reference=np.zeros((9, 16), np.float32)), "reference must be"),
        (dict(exposure=2.0), "exposure is for HDR"),
        (dict(hdr=True, exposure=-1.0), "exposure must be finite and > 0"),
    ],
)
def test_bad_input_is_refused(tmp_path, change, message):
    reference, methods = images()
    arguments = dict(name="scene", reference=reference, images=methods, out=tmp_path) | change
    with pytest.raises((ValueError, TypeError), match=re.escape(message)):
        comparator.write_comparator(**arguments)


def test_an_image_too_large_to_show_is_refused(tmp_path, monkeypatch):
    monkeypatch.setattr(comparator, "MAX_PIXELS", 100)
    reference, methods = images()
    with pytest.raises(ValueError, match="at most 100"):
        comparator.write_comparator("scene", reference, methods, tmp_path)
