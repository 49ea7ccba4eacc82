"""Charts of speed against accuracy (matplotlib: Pareto fronts, parameter curves; `save`
writes PNG or SVG) and the report's pictures (uint8 arrays drawn with NumPy and Pillow: image
grids, error maps, colour bars, crops; the *_figure functions show them in a notebook)."""

from __future__ import annotations

import functools
import os
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from ..io.images import srgb8, srgb_to_linear
from ..methods.tile_filter import FILTER_OPTIONS
from ..metrics import error_map, get, registered, tone_map


def _pyplot():
    import matplotlib

    # Headless (no display is needed), except in a Jupyter kernel, whose inline backend shows
    # the figures a notebook cell returns.
    if "ipykernel" not in sys.modules and "MPLBACKEND" not in os.environ:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def charted_metrics(rows: pd.DataFrame) -> list[str]:
    """The registered metrics that `rows` has values of, in the order charts offer them and
    the study ranks by the first: HDR metrics first (a scene that has them is charted by them:
    the LDR ones clip its lights), then in registry order. A metric with no direction (best
    at a value, as energy_ratio) is tabled, not charted."""
    names = [
        n
        for n in registered()
        if get(n).higher_is_better is not None and n in rows and rows[n].notna().any()
    ]
    return sorted(names, key=lambda n: not get(n).hdr)


def pareto_front(table: pd.DataFrame, metric: str = "psnr") -> pd.DataFrame:
    """Rows no other row beats in both time (lower) and `metric` (better, as the registry says
    which way), sorted by time."""
    goodness = get(metric).goodness(table[metric])
    # By position: the table's own index may repeat labels.
    order = pd.DataFrame({"ms": table["total_ms"].to_numpy(), "goodness": goodness.to_numpy()})
    order = order.sort_values(["ms", "goodness"], ascending=[True, False])
    front, best = [], -np.inf
    for position, value in order["goodness"].items():
        if value > best:
            front.append(table.iloc[position])
            best = value
    return pd.DataFrame(front)


def pareto(
    table: pd.DataFrame,
    scene: str,
    metric: str = "psnr",
    budget_ms: float | None = None,
    budget_label: str | None = None,
):
    """Time per frame against error for one scene, one color per method, front marked; with
    budget_ms a dashed line there, named budget_label (default "budget N ms")."""
    rows = table[table["scene"] == scene]
    if rows.empty:
        raise ValueError(
            f"blurlab.plots.pareto: no rows for scene {scene!r}; the table has "
            f"{sorted(set(table['scene']))}"
        )
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(9, 4.5))
    variants = rows.apply(_variant, axis=1)
    series = rows.groupby([rows["method"], variants])
    for i, ((name, options), group) in enumerate(series):
        colour, marker = series_style(i)
        ax.scatter(
            group["total_ms"],
            group[metric],
            label=name + (f" +{options}" if options else ""),
            s=28,
            alpha=0.85,
            color=colour,
            marker=marker,
        )
    front = pareto_front(rows, metric)
    ax.step(
        front["total_ms"], front[metric], where="post", color="black", lw=1, label="Pareto front"
    )
    # Labels of points in the right part of the chart go to their left, inside the axes.
    span = np.log(rows["total_ms"].max() / rows["total_ms"].min()) or 1.0
    labels = []
    for _, row in front.iterrows():
        right = np.log(row["total_ms"] / rows["total_ms"].min()) / span > 0.7
        labels.append(
            ax.annotate(
                _short(row),
                (row["total_ms"], row[metric]),
                fontsize=6,
                alpha=0.7,
                xytext=(-LABEL_OFFSET[0], LABEL_OFFSET[1]) if right else LABEL_OFFSET,
                ha="right" if right else "left",
                textcoords="offset points",
            )
        )
    if budget_ms:
        label = budget_label or f"budget {budget_ms} ms"
        ax.axvline(budget_ms, color="gray", ls="--", lw=1, label=label)
    ax.set_xscale("log")
    ax.set_xlabel(f"time per frame, ms ({rows['clock'].iloc[0]}, {rows['renderer'].iloc[0]})")
    ax.set_ylabel(get(metric).axis_title)
    ax.set_title(
        f"{scene}: speed against accuracy, {rows['width'].iloc[0]}x{rows['height'].iloc[0]}"
    )
    ax.grid(True, which="both", alpha=0.3)
    # Outside the axes: with a dozen methods and options a legend inside hides points.
    ax.legend(
        fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), ncols=_legend_columns(series)
    )
    fig.tight_layout()
    separate_labels(fig, labels)
    return fig


# Every series of a Pareto chart (a method, or a method with filter options on) gets its own
# pair of colour and marker: colours from a qualitative palette, and markers that advance one
# more each round of the colours, so that up to len(COLOURS) * len(MARKERS) series are told
# apart and neighbours in the legend differ in both.
# matplotlib's tab10
COLOURS = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f")
COLOURS += ("#bcbd22", "#17becf")
MARKERS = ("o", "s", "^", "D", "v", "P", "X", "<", ">", "p", "h", "*")
LABEL_OFFSET = (3, 3)  # points from a front point to its label, before separate_labels
LEGEND_ROWS = 24  # legend entries in a column before another column starts


def series_style(i: int) -> tuple[str, str]:
    """The (colour, marker) of the i-th series, i = q * len(COLOURS) + r: colour r, marker
    r + q * (len(COLOURS) + 1) modulo len(MARKERS). Distinct for i < len(COLOURS) *
    len(MARKERS), since len(COLOURS) + 1 (11) is prime to len(MARKERS) (12)."""
    colours, markers = len(COLOURS), len(MARKERS)
    if i >= colours * markers:
        raise ValueError(f"blurlab.plots: at most {colours * markers} series on one chart")
    return COLOURS[i % colours], MARKERS[(i + i // colours) % markers]


def _legend_columns(series) -> int:
    return max(1, -(-series.ngroups // LEGEND_ROWS))


def separate_labels(fig, labels, tries: int = 60) -> None:
    """Moves annotations (`labels`, in order) up or down from their offset, each to the
    nearest place where its box overlaps no label placed before it."""
    if not labels:
        return
    renderer = fig.canvas.get_renderer()
    points_per_pixel = 72.0 / fig.dpi
    placed = []
    for label in labels:
        dx, dy = label.xyann
        box = label.get_window_extent(renderer)
        step = (box.height + 1.0) * points_per_pixel
        for k in range(tries):
            shift = (k + 1) // 2 * step * (1 if k % 2 else -1)  # 0, +1, -1, +2, -2 ... rows
            label.xyann = (dx, dy + shift)
            box = label.get_window_extent(renderer)
            if not any(box.overlaps(other) for other in placed):
                break
        placed.append(box)


def _variant(row) -> str:
    """The filter options a row turns on, "+"-joined ("" for none)."""
    return "+".join(
        o for o in FILTER_OPTIONS if pd.notna(row.get(f"param_{o}")) and row[f"param_{o}"] != 0
    )


def _short(row) -> str:
    params = {k[6:]: v for k, v in row.items() if k.startswith("param_") and pd.notna(v)}
    text = ", ".join(
        f"{k}={int(v) if float(v).is_integer() else v}"
        for k, v in params.items()
        if isinstance(v, (int, float))
    )
    return f"{row['method'].replace('reconstruct_', '')} {text}".strip()


def parameter_curves(
    table: pd.DataFrame, method: str, param: str, fixed: dict | None = None, metric: str = "psnr"
):
    """Time and error against one parameter (the thesis's Tables 5.2 and 5.3, with accuracy),
    one line per scene."""
    plt = _pyplot()
    rows = table[table["method"] == method]
    for key, value in (fixed or {}).items():
        rows = rows[rows[f"param_{key}"] == value]
    # Only the configurations that set nothing but `param` and `fixed` (not, say, an option).
    others = [c for c in rows if c.startswith("param_") and c[6:] not in {param, *(fixed or {})}]
    rows = rows[rows[others].isna().all(axis=1)] if others else rows
    fig, (left, right) = plt.subplots(1, 2, figsize=(9, 3.5))
    for scene, group in rows.groupby("scene"):
        group = group.sort_values(f"param_{param}")
        left.plot(group[f"param_{param}"], group["total_ms"], marker="o", label=scene)
        right.plot(group[f"param_{param}"], group[metric], marker="o", label=scene)
    fixed_text = ", ".join(f"{k} = {v}" for k, v in (fixed or {}).items())
    left.set(xlabel=param, ylabel="ms per frame", title=f"{method}: time ({fixed_text})")
    right.set(xlabel=param, ylabel=metric.upper(), title=f"{method}: {metric} ({fixed_text})")
    for ax in (left, right):
        ax.grid(True, alpha=0.3)
    right.legend(fontsize=7)
    fig.tight_layout()
    return fig


GRID_CELL_PIXELS = 320  # thumbnail width in image_grid_picture
GRID_LABEL, GRID_GAP = 14, 4


def shrink(array: np.ndarray, most: int = GRID_CELL_PIXELS) -> np.ndarray:
    """`array` ((H, W) or (H, W, C)) averaged over f x f blocks, f the smallest whole factor
    that brings its width to `most` pixels or fewer (rows and columns beyond whole blocks are
    dropped): linear values, averaged as light adds up."""
    factor = -(-array.shape[1] // most)
    if factor <= 1:
        return array
    height, width = array.shape[0] // factor * factor, array.shape[1] // factor * factor
    if height == 0:
        return array[:, ::factor]
    # Rows first, then columns, in strided adds: 2f adds over ever smaller arrays, 2.4x faster
    # than f² adds at 1080p, and several times faster than a mean over a reshaped view.
    rows = array[0:height:factor, :width].astype(np.float32)
    for y in range(1, factor):
        rows += array[y:height:factor, :width]
    total = rows[:, 0::factor].copy()
    for x in range(1, factor):
        total += rows[:, x::factor]
    return total / np.float32(factor * factor)


def image_grid_picture(
    reference: np.ndarray,
    images: dict[str, np.ndarray],
    errors: bool = True,
    error_scale: float = 0.25,
    error_maps: dict[str, np.ndarray] | None = None,
    cell: int = GRID_CELL_PIXELS,
) -> np.ndarray:
    """(H, W, 3) uint8 sRGB: the reference and each method's image in a row, each shrunk
    (`shrink`) to `cell` px wide or less and named above; below each image (with `errors`),
    its error map, |error| through magma with `error_scale` white. `error_maps`: each image's
    metrics.error_map, if already made. Drawn with NumPy and Pillow, no figure."""
    from PIL import Image, ImageDraw

    if not (np.isfinite(error_scale) and error_scale > 0):
        raise ValueError(f"blurlab.plots.image_grid: error_scale must be > 0, not {error_scale}")
    columns = {"reference": reference, **images}
    thumbs = [srgb8(shrink(image[..., :3], cell)) for image in columns.values()]
    height, width = thumbs[0].shape[:2]
    rows = 2 if errors else 1
    row_height = GRID_LABEL + height + GRID_GAP
    picture = np.full((rows * row_height, len(thumbs) * (width + GRID_GAP), 3), 255, np.uint8)
    for col, thumb in enumerate(thumbs):
        left = col * (width + GRID_GAP)
        picture[GRID_LABEL : GRID_LABEL + height, left : left + width] = thumb
    if errors:
        for col, (name, image) in enumerate(images.items(), start=1):
            error = error_maps[name] if error_maps is not None else error_map(reference, image)
            left, top = col * (width + GRID_GAP), row_height + GRID_LABEL
            picture[top : top + height, left : left + width] = error_colours(
                shrink(error, cell), error_scale
            )
    canvas = Image.fromarray(picture)
    draw = ImageDraw.Draw(canvas)
    for col, name in enumerate(columns):
        text = _fitted(draw, name.replace("reconstruct_", ""), width)
        draw.text((col * (width + GRID_GAP), 1), text, fill=(0, 0, 0))
    if errors:
        draw.text((2, row_height + GRID_LABEL + height // 2 - 12), "|error|", fill=(0, 0, 0))
        draw.text(
            (2, row_height + GRID_LABEL + height // 2), f"white = {error_scale:g}", fill=(0, 0, 0)
        )
    return np.asarray(canvas)


def image_grid(
    reference: np.ndarray, images: dict[str, np.ndarray], title: str | None = None, **options
):
    """image_grid_picture(reference, images, **options) as a matplotlib figure (for
    notebooks), `title` above it."""
    return picture_figure(image_grid_picture(reference, images, **options), title)


def picture_figure(picture: np.ndarray, title: str | None = None):
    """A matplotlib figure showing a uint8 picture pixel for pixel (at 100 dpi), `title` in a
    strip above it."""
    plt = _pyplot()
    height, strip = picture.shape[0] / 100, 0.3 if title else 0.0
    fig, ax = plt.subplots(figsize=(picture.shape[1] / 100, height + strip), dpi=100)
    ax.imshow(picture, interpolation="nearest")
    ax.axis("off")
    fig.subplots_adjust(0, 0, 1, height / (height + strip))
    if title:
        fig.suptitle(title, fontsize=8)
    return fig


@functools.lru_cache(maxsize=8)
def _colour_table(cmap: str) -> np.ndarray:
    """(256, 3) uint8: a matplotlib colour map's colours as its bytes=True gives them."""
    import matplotlib

    return matplotlib.colormaps[cmap](np.arange(256), bytes=True)[:, :3]


def error_colours(error: np.ndarray, vmax: float, cmap: str = "magma") -> np.ndarray:
    """(H, W, 3) uint8 sRGB picture of an (H, W) error map, 0 .. vmax through `cmap`'s 256
    colours (the bins matplotlib's imshow uses for vmin = 0, vmax), one pixel per pixel: a
    lookup in NumPy, no figure."""
    if not (np.isfinite(vmax) and vmax > 0):
        raise ValueError(f"blurlab.plots.error_colours: vmax must be finite and > 0, not {vmax}")
    error = np.asarray(error)
    if error.ndim != 2 or not np.isfinite(error).all():
        raise ValueError(
            f"blurlab.plots.error_colours: needs a finite (H, W) error map, not shape {error.shape}"
        )
    index = np.clip(error / vmax * 256.0, 0.0, 255.0).astype(np.uint8)
    return _colour_table(cmap)[index]


ERROR_SCALE_PERCENTILE = 99.5
ERROR_SCALE_SAMPLES = 1 << 21  # a 1080p study scene has 29 M errors: a regular sample will do


def error_scale(error_maps, percentile: float = ERROR_SCALE_PERCENTILE) -> float:
    """The top of a scene's error colour scale: the `percentile` of its error maps' pixels
    (every pixel up to ERROR_SCALE_SAMPLES in all, a regular stride through each map beyond),
    at least 1e-3. A percentile, not the maximum, so that a few outliers do not darken the
    rest."""
    maps = [np.asarray(error).ravel() for error in error_maps]
    total = sum(m.size for m in maps)
    if total == 0:
        raise ValueError("blurlab.plots.error_scale: no error values")
    stride = -(-total // ERROR_SCALE_SAMPLES)
    sample = np.concatenate([m[::stride] for m in maps])
    return max(float(np.percentile(sample, percentile)), 1e-3)


COLOUR_BAR_SIZE = (360, 18)  # the bar itself, px


def colour_bar(vmax: float, label: str = "|error| (linear)", cmap: str = "magma") -> np.ndarray:
    """(H, W, 3) uint8: a horizontal colour bar, 0 .. vmax, with three ticks and `label`: the
    key of error_colours' pictures, drawn with NumPy and Pillow."""
    from PIL import Image, ImageDraw

    if not (np.isfinite(vmax) and vmax > 0):
        raise ValueError(f"blurlab.plots.colour_bar: vmax must be finite and > 0, not {vmax}")
    width, height = COLOUR_BAR_SIZE
    margin = 24  # room for the end ticks' labels
    picture = np.full((height + 34, width + 2 * margin, 3), 255, np.uint8)
    ramp = np.linspace(0.0, vmax, width, endpoint=False) + vmax / (2 * width)  # bin centres
    picture[:height, margin : margin + width] = error_colours(ramp[None, :], vmax, cmap)
    canvas = Image.fromarray(picture)
    draw = ImageDraw.Draw(canvas)
    for fraction in (0.0, 0.5, 1.0):
        x = margin + round(fraction * (width - 1))
        draw.line([(x, height), (x, height + 3)], fill=(0, 0, 0))
        text = f"{fraction * vmax:.3g}"
        draw.text((x - draw.textlength(text) / 2, height + 4), text, fill=(0, 0, 0))
    draw.text((margin + (width - draw.textlength(label)) / 2, height + 19), label, fill=(0, 0, 0))
    return np.asarray(canvas)


def worst_window(error: np.ndarray, side: int) -> tuple[int, int]:
    """(y, x) of the side x side window with the largest mean error (summed-area table)."""
    height, width = error.shape[:2]
    side = max(1, min(side, height, width))
    table = np.zeros((height + 1, width + 1))
    table[1:, 1:] = np.cumsum(np.cumsum(error, 0, dtype=np.float64), 1)  # float32 would drift
    sums = table[side:, side:] - table[:-side, side:] - table[side:, :-side] + table[:-side, :-side]
    y, x = np.unravel_index(int(np.argmax(sums)), sums.shape)
    return int(y), int(x)


CROP_MIN_PIXELS = 96  # crops smaller than this are enlarged (nearest) to be seen
# The widest window: artefacts are a few pixels wide, and the picture is every window cut from
# every image (a 270-pixel window at 1080p made it 26 Mpx, 5 s to draw and encode).
CROP_MAX_SIDE = 128


def crop_side(shape) -> int:
    """The side of crops_picture's windows for images of `shape` (H, W, ...): a quarter of the
    shorter side, 16 to CROP_MAX_SIDE pixels."""
    return max(16, min(CROP_MAX_SIDE, min(shape[:2]) // 4))


CROP_LABEL_WIDTH, CROP_HEADER, CROP_GAP = 120, 16, 2


def crops_picture(
    reference: np.ndarray, images: dict[str, np.ndarray], side: int, errors=None
) -> np.ndarray:
    """(H, W, 3) uint8 sRGB: for each method, the window where its error is largest, cut from
    the reference and from every method's image alike (rows: whose worst window; columns: the
    images, named above), the pixels as they are (enlarged by whole pixels when `side` is
    small). `errors`: each image's error map, if already computed."""
    from PIL import Image, ImageDraw

    windows: dict[tuple[int, int], str] = {}
    for name, image in images.items():
        error = errors[name] if errors is not None else error_map(reference, image)
        windows.setdefault(worst_window(error, side), name)
    columns = {"reference": reference, **images}
    side = max(1, min(side, *reference.shape[:2]))
    zoom = -(-CROP_MIN_PIXELS // side)  # ceil
    cell = side * zoom
    height = CROP_HEADER + len(windows) * (cell + CROP_GAP)
    width = CROP_LABEL_WIDTH + len(columns) * (cell + CROP_GAP)
    picture = np.full((height, width, 3), 255, np.uint8)
    for row, (y, x) in enumerate(windows):
        top = CROP_HEADER + row * (cell + CROP_GAP)
        for col, image in enumerate(columns.values()):
            crop = srgb8(image[y : y + side, x : x + side, :3])
            left = CROP_LABEL_WIDTH + col * (cell + CROP_GAP)
            picture[top : top + cell, left : left + cell] = crop.repeat(zoom, 0).repeat(zoom, 1)
    canvas = Image.fromarray(picture)
    draw = ImageDraw.Draw(canvas)
    for col, name in enumerate(columns):
        text = _fitted(draw, name.replace("reconstruct_", ""), cell)
        draw.text((CROP_LABEL_WIDTH + col * (cell + CROP_GAP), 2), text, fill=(0, 0, 0))
    for row, owner in enumerate(windows.values()):
        top = CROP_HEADER + row * (cell + CROP_GAP)
        label = _fitted(draw, owner.replace("reconstruct_", ""), CROP_LABEL_WIDTH - 4)
        draw.text((2, top + cell // 2 - 12), "worst of", fill=(0, 0, 0))
        draw.text((2, top + cell // 2), label, fill=(0, 0, 0))
    return np.asarray(canvas)


def _fitted(draw, text: str, width: int) -> str:
    """`text`, cut short with "…" where it is wider than `width` pixels."""
    if draw.textlength(text) <= width:
        return text
    while text and draw.textlength(text + "…") > width:
        text = text[:-1]
    return text + "…"


def crops_figure(reference: np.ndarray, images: dict[str, np.ndarray], side: int):
    """crops_picture(reference, images, side) as a matplotlib figure (for notebooks)."""
    return picture_figure(crops_picture(reference, images, side))


def motion_picture(motion: np.ndarray) -> np.ndarray:
    """(H, W, 3) linear colour of a motion field: hue = direction, brightness = length (up to
    the longest), black where nothing moves."""
    import colorsys

    length = np.linalg.norm(motion, axis=-1)
    hue = (np.arctan2(motion[..., 1], motion[..., 0]) / (2 * np.pi)) % 1.0
    value = length / max(float(length.max()), 1e-6)
    rgb = np.vectorize(colorsys.hsv_to_rgb)(hue, np.where(length > 0, 1.0, 0.0), value)
    return np.stack(rgb, axis=-1).astype(np.float32)


def tone_mapped(image: np.ndarray, exposure: float) -> np.ndarray:
    """(H, W, 3) float32 linear colour whose sRGB encoding is `metrics.tone_map(image,
    exposure)`: written as a PNG or drawn by the functions here, an HDR image shows
    tone-mapped (docs/spec.md §6.2) instead of clipped."""
    return srgb_to_linear(tone_map(image, exposure)).astype(np.float32)


def load_matplotlib() -> None:
    """Imports matplotlib's pyplot (the first import on a machine builds its font cache): a
    process that will draw calls it early, while it would otherwise wait."""
    _pyplot()


def draw_and_save(draw, args: tuple, path: str | Path) -> Path:
    """save(draw(*args), path): a chart drawn where it is saved, e.g. in another process."""
    return save(draw(*args), path)


def save(fig, path: str | Path) -> Path:
    """Writes PNG or SVG (by extension) and closes the figure."""
    path = Path(path)
    if path.suffix.lower() not in (".png", ".svg"):
        raise ValueError(f"blurlab.plots.save: write .png or .svg, not {path.name}")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130)
    _pyplot().close(fig)
    return path
