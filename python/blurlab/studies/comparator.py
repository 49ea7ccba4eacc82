"""Look closer: each method beside the reference in panels that pan and zoom together, down to
single pixels drawn as squares, with a split slider, the error map on a toggle and, for HDR
images, an exposure control. The reports (the study's report.html) embed it.

A page puts `assets_html()` in once (the style, Panzoom and the comparator's script, inline: the
page works offline) and one `write_comparator` fragment per scene. The pictures are files in
`<out>/look/`, beside the page: PNGs for SDR images; for HDR images a script holding each image
as floats (log2 of each channel in 16 bits, 0.07 % apart), which the page tone-maps at the
exposure chosen (blurlab.metrics.tone_map, docs/spec.md §6.2).

Zoom and pan are Panzoom's (timmywil/panzoom 4.6.2, MIT; vendor/panzoom holds its release build
and licence). The split slider is written here: img-comparison-slider's built file could not be
obtained for bundling (see README.md, "What it is built on, and why")."""

from __future__ import annotations

import base64
import concurrent.futures
import functools
import html
import io as bytes_io
import json
import math
import re
from collections.abc import Mapping
from pathlib import Path

import numpy as np
from PIL import Image

from .. import metrics
from ..io import images as io
from . import plots

HERE = Path(__file__).parent
PANZOOM = HERE / "vendor" / "panzoom" / "panzoom.min.js"

FOLDER = "look"  # the pictures' folder, beside the page
MAX_PIXELS = 3840 * 2160  # per image: the page's pictures stay bounded
PANEL_WIDTH = (320, 480)  # a panel's width on screen, px: at least, at most
MAX_PIXEL_SIZE = 32  # the deepest zoom: one image pixel as this many screen px
EXPOSURE_STOPS = 8  # the exposure control's range: ± this many stops about the scene's

# A study's report holds hundreds of panels: each picture loads as it comes near the screen.
LAZY = "loading='lazy' decoding='async' alt=''"

_NAME = re.compile(r"[A-Za-z0-9_.-]{1,100}")


def assets_html() -> str:
    """The comparator's style and scripts (Panzoom's, then its own), inline: once per page,
    before or after the fragments."""
    style = (HERE / "comparator.css").read_text()
    scripts = PANZOOM.read_text() + "\n" + (HERE / "comparator.js").read_text()
    return f"<style>{style}</style>\n<script>{scripts}</script>"


def write_comparator(
    name: str,
    reference: np.ndarray,
    images: Mapping[str, np.ndarray],
    out,
    *,
    hdr: bool = False,
    exposure: float | None = None,
    pool: concurrent.futures.Executor | None = None,
) -> tuple[str, list]:
    """One comparator: each of `images` ({method name: (H, W, 3 or 4) linear float image}) beside
    `reference` (the same shape). Writes its pictures into `out`/look/ as `name`_*.png (and,
    with `hdr`, `name`.js) and returns (the HTML fragment, the futures of the writes left
    running on `pool`; [] without one, when everything is written before it returns).

    `name`: letters, digits, '_', '.', '-' (it names the files and the element's id). SDR
    images are shown clipped to [0, 1]; `hdr` ones tone-mapped at `exposure` (by default
    metrics.exposure(reference), as the study's pictures) times the page's 2^stops. The error
    maps are metrics.error_map of the pictures as shown at that exposure, coloured on one
    scale (plots.error_scale)."""
    _check_name(name)
    reference = _checked("reference", reference, None)
    if not isinstance(images, Mapping) or not images:
        raise ValueError("blurlab comparator: images must be a non-empty {method name: image}")
    images = {str(k): _checked(f"images[{k!r}]", v, reference.shape) for k, v in images.items()}
    if hdr:
        exposure = metrics.exposure(reference) if exposure is None else exposure
        if isinstance(exposure, bool) or not isinstance(exposure, (int, float)):
            raise TypeError(f"blurlab comparator: exposure must be a number, not {exposure!r}")
        if not (math.isfinite(exposure) and exposure > 0):
            raise ValueError(f"blurlab comparator: exposure must be finite and > 0, not {exposure}")
        shown = lambda image: plots.tone_mapped(image, exposure)  # noqa: E731
    elif exposure is not None:
        raise ValueError("blurlab comparator: exposure is for HDR images (hdr=True)")
    else:
        shown = lambda image: np.clip(image, 0.0, 1.0)  # noqa: E731
    folder = Path(out) / FOLDER
    folder.mkdir(parents=True, exist_ok=True)
    height, width = reference.shape[:2]
    element = f"look-{name}"
    shown_reference = shown(reference)
    errors = [metrics.error_map(shown_reference, shown(image)) for image in images.values()]
    vmax = plots.error_scale(errors)
    # The writes, each a call: coloured and encoded on `pool` where there is one.
    jobs = [
        functools.partial(_write_error_png, folder / f"{name}_{i}_error.png", error, vmax)
        for i, error in enumerate(errors)
    ]
    if hdr:
        jobs.append(
            functools.partial(_write_data, folder / f"{name}.js", element, reference, images)
        )
    else:
        pictures = {"reference": reference} | {str(i): v for i, v in enumerate(images.values())}
        jobs += [
            functools.partial(io.write, folder / f"{name}_{key}.png", picture, png_compression=1)
            for key, picture in pictures.items()
        ]
    if pool is None:
        for job in jobs:
            job()
        writes = []
    else:
        writes = [pool.submit(job) for job in jobs]
    sources = {
        key: f"{FOLDER}/{name}_{key}.png" for key in ["reference", *map(str, range(len(images)))]
    }
    sources |= {f"error:{i}": f"{FOLDER}/{name}_{i}_error.png" for i in range(len(images))}
    fragment = _fragment(name, element, list(images), width, height, hdr, exposure, vmax, sources)
    return fragment, writes


def comparator_of_files(
    name: str, size: tuple[int, int], reference: str, pictures: Mapping[str, tuple[str, str]], vmax
) -> str:
    """The comparator of SDR pictures already written beside the page (the study's gallery):
    `reference` and, per method, (its picture, its error map) as paths relative to the page,
    the error maps coloured on one scale up to `vmax`; `size` = (W, H). Nothing is written, so
    a report shows its pictures once, in the gallery and in the comparator."""
    _check_name(name)
    if not pictures:
        raise ValueError("blurlab comparator: pictures must be a non-empty {method: files}")
    sources = {"reference": reference}
    for i, (picture, error) in enumerate(pictures.values()):
        sources |= {str(i): picture, f"error:{i}": error}
    width, height = size
    return _fragment(
        name, f"look-{name}", list(pictures), width, height, False, None, vmax, sources
    )


def _write_error_png(path: Path, error: np.ndarray, vmax: float) -> Path:
    return io.write(path, plots.error_colours(error, vmax), png_compression=1)


def _write_data(path: Path, element: str, reference: np.ndarray, images: dict) -> Path:
    """The HDR comparator's script: each picture's linear colour (_log_png) for the page."""
    pictures = {"reference": _log_png(reference)}
    pictures.update({str(i): _log_png(image) for i, image in enumerate(images.values())})
    data = {"steps": LOG_STEPS, "offset": LOG_OFFSET, "images": pictures}
    return io.write_text(
        path,
        "window.blurlabLookData = window.blurlabLookData || {};\n"
        f"window.blurlabLookData[{json.dumps(element)}] = {json.dumps(data)};\n",
    )


def _check_name(name) -> None:
    """A comparator's name names its files and its element: refused unless plain."""
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise ValueError(
            f"blurlab comparator: name {name!r} must be 1 to 100 letters, digits, '_', '.', '-'"
        )


def _checked(what: str, image, shape) -> np.ndarray:
    """`image` as (H, W, 3) float32 linear colour; alpha dropped."""
    array = np.asarray(image)
    if array.dtype.kind != "f" or array.ndim != 3 or array.shape[2] not in (3, 4):
        raise ValueError(
            f"blurlab comparator: {what} must be an (H, W, 3 or 4) float array, not "
            f"{array.dtype} of shape {array.shape}"
        )
    if shape is not None and array.shape[:2] != shape[:2]:
        raise ValueError(
            f"blurlab comparator: {what} is {array.shape[1]}x{array.shape[0]}, the reference "
            f"{shape[1]}x{shape[0]}"
        )
    if array.shape[0] * array.shape[1] > MAX_PIXELS:
        raise ValueError(
            f"blurlab comparator: {what} has {array.shape[0] * array.shape[1]} pixels; at most "
            f"{MAX_PIXELS} are shown"
        )
    rgb = np.ascontiguousarray(array[..., :3], dtype=np.float32)
    if not np.isfinite(rgb).all():
        raise ValueError(f"blurlab comparator: {what} has NaN or infinite values")
    return rgb


# HDR pictures travel as log2 of each channel in 16 bits: 1/LOG_STEPS of a stop apart (0.07 %),
# from 2^-LOG_OFFSET up to 2^(65535 / LOG_STEPS - LOG_OFFSET); the code 0 is black.
LOG_STEPS = 1024
LOG_OFFSET = 32


def _log_png(image: np.ndarray) -> str:
    """Base64 PNG, (H, 2W) RGB 8 bits: each channel's 16-bit code round((log2(c) + LOG_OFFSET)
    · LOG_STEPS) (0 for black), its high bytes on the left, its low bytes on the right. An opaque
    RGB PNG reads back exactly in a canvas; the page decodes it to floats (comparator.js)."""
    rgb = np.maximum(image.astype(np.float64), 0.0)
    with np.errstate(divide="ignore"):
        code = np.round((np.log2(rgb) + LOG_OFFSET) * LOG_STEPS)
    code = np.where(rgb > 0, np.clip(code, 1, 65535), 0).astype(np.uint16)
    picture = np.concatenate([(code >> 8).astype(np.uint8), (code & 255).astype(np.uint8)], 1)
    buffer = bytes_io.BytesIO()
    Image.fromarray(picture, "RGB").save(buffer, format="PNG", compress_level=6)
    return base64.b64encode(buffer.getvalue()).decode("ascii")


def _fragment(name, element, methods, width, height, hdr, exposure, vmax, sources) -> str:
    e = html.escape
    # Small images at an integer enlargement, large ones shrunk to fit two panels a row.
    shown = min(PANEL_WIDTH[1], width * max(1, math.ceil(PANEL_WIDTH[0] / width)))
    shown_height = round(shown * height / width)
    size = f"width:{shown}px;height:{shown_height}px"

    def picture(key: str, css: str = "") -> str:
        if hdr and key != "error":
            return (
                f"<canvas class='{css}' data-image='{key}' width='{width}' height='{height}'>"
                "</canvas>"
            )
        return f"<img class='{css}' src='{e(sources[key])}' {LAZY}>"

    panels = []
    for i, method in enumerate(methods):
        error = f"<img class='bl-look-error' src='{e(sources[f'error:{i}'])}' {LAZY}>"
        panels.append(
            f"<figure class='bl-look-panel' data-method='{e(method)}'>"
            f"<div class='bl-look-view' style='{size}'>"
            f"<div class='bl-look-stage'>{picture('reference')}</div>"
            f"<div class='bl-look-top'><div class='bl-look-stage'>"
            f"{picture(str(i), 'bl-look-method')}{error}</div></div>"
            "<div class='bl-look-handle panzoom-exclude'></div></div>"
            f"<figcaption><span>reference</span><span>{e(method)}</span></figcaption></figure>"
        )
    exposure_control = ""
    if hdr:
        exposure_control = (
            f"<label>exposure <input type='range' class='bl-look-exposure' "
            f"min='-{EXPOSURE_STOPS}' max='{EXPOSURE_STOPS}' step='0.25' value='0'> "
            f"<span class='bl-look-stops'>+0 stops</span> about {exposure:.4g} (Reinhard)</label>"
        )
    data_script = f"<script src='{FOLDER}/{name}.js'></script>" if hdr else ""
    attributes = f"data-width='{width}' data-height='{height}' data-max-pixel='{MAX_PIXEL_SIZE}'"
    if hdr:
        attributes += f" data-exposure='{float(exposure)!r}'"
    return (
        f"{data_script}<div class='blurlab-look' id='{element}' {attributes}>"
        "<div class='bl-look-controls'><b>Look closer</b>"
        "<label>split <input type='range' class='bl-look-split' min='0' max='1' step='0.001' "
        "value='0.5'></label>"
        "<label><input type='checkbox' class='bl-look-error-toggle'> error map (|error|, 0 to "
        f"{vmax:.3g}, magma)</label>{exposure_control}"
        "<span><button type='button' class='bl-look-out' title='zoom out'>−</button>"
        "<button type='button' class='bl-look-in' title='zoom in'>+</button>"
        "<button type='button' class='bl-look-fit'>fit</button></span>"
        "<span class='bl-look-readout'></span></div>"
        "<div class='bl-look-panels'>" + "".join(panels) + "</div>"
        "<p style='font-size:11px'>Drag the white line to move the split; drag elsewhere to "
        "pan; the wheel (or + and −) zooms, down to single pixels drawn as squares. Every panel "
        "follows.</p>"
        "</div>"
    )


__all__ = ["assets_html", "write_comparator"]
