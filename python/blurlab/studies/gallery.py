"""A scene's pictures in a study's report (`write_pictures`): the reference, each method's
image and error map at full size, the crops where each errs most, the image grid and the
comparator, encoded on a thread pool while the study goes on."""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np

from .. import metrics
from ..io import images as io
from . import comparator, plots

# zlib level of the report's full-size PNGs: 1 encodes in about 2/3 of the default 6's time,
# for files about 30 % larger (docs/benchmarks.md).
REPORT_PNG_COMPRESSION = 1


def _write_png(path: Path, image) -> Path:
    return io.write(path, image, png_compression=REPORT_PNG_COMPRESSION)


def write_pictures(
    name: str, reference: np.ndarray, images: dict, out: Path, pool, look: bool = False
) -> tuple[str, list]:
    """Writes one scene's pictures into `out` as <name>_*.png: the reference, each method's
    image and error map at full size (the colour bar, shared by the scene, apart), the crops of
    the windows where each method errs most, and the image grid. Returns the HTML that shows
    them (each thumbnail links to its full-size file; with `look`, then the comparator of the
    same files) and the futures of the work left running on `pool` (a ThreadPoolExecutor):
    every picture is NumPy and Pillow/OpenImageIO work that mostly releases the GIL, so the
    caller's thread goes on while they encode."""
    rgb = lambda image: image[..., :3]  # noqa: E731 (the pictures carry no alpha)
    reference = rgb(reference)
    images = {method_name: rgb(image) for method_name, image in images.items()}
    encodes = [pool.submit(_write_png, out / f"{name}_reference.png", reference)]
    maps = pool.map(lambda image: metrics.error_map(reference, image), images.values())
    errors = dict(zip(images, maps, strict=True))
    vmax = plots.error_scale(errors.values())
    side = plots.crop_side(reference.shape)
    pictures = {
        f"{name}_error_scale.png": lambda: plots.colour_bar(vmax),
        f"{name}_crops.png": lambda: plots.crops_picture(reference, images, side, errors),
        f"{name}_images.png": lambda: plots.image_grid_picture(
            reference, images, error_maps=errors
        ),
    }
    cells = [
        f"<figure><a href='{name}_reference.png'><img src='{name}_reference.png'></a>"
        "<figcaption>reference</figcaption></figure>"
    ]
    for method_name, image in images.items():
        picture, error = f"{name}_{method_name}.png", f"{name}_{method_name}_error.png"
        encodes.append(pool.submit(_write_png, out / picture, image))
        pictures[error] = functools.partial(plots.error_colours, errors[method_name], vmax)
        cells.append(
            f"<figure><a href='{picture}'><img src='{picture}'></a>"
            f"<a href='{error}'><img src='{error}'></a><figcaption>{method_name}</figcaption>"
            "</figure>"
        )
    for file_name, draw in pictures.items():
        encodes.append(
            pool.submit(lambda path, draw: _write_png(path, draw()), out / file_name, draw)
        )
    html_text = (
        f"<p>|error| (linear), 0 to {vmax:.3g}: <img src='{name}_error_scale.png' "
        "style='width:360px;vertical-align:middle'></p>"
        "<div class='gallery'>" + "".join(cells) + "</div>"
        f"<p>Where each method errs most ({side}×{side} px windows, the same window cut from "
        f"every image, pixels as rendered): <a href='{name}_crops.png'>"
        f"<img src='{name}_crops.png'></a></p>"
    )
    if look:
        files = {m: (f"{name}_{m}.png", f"{name}_{m}_error.png") for m in images}
        height, width = reference.shape[:2]
        html_text += comparator.comparator_of_files(
            name, (width, height), f"{name}_reference.png", files, vmax
        )
    return html_text, encodes
