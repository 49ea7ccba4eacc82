"""Charts of speed against accuracy (matplotlib): Pareto fronts, parameter curves, image grids.

Every function returns a matplotlib Figure; `save(fig, path)` writes PNG or SVG.
"""

from __future__ import annotations

import functools
import os
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from ..io import linear_to_srgb, srgb8, srgb_to_linear
from ..methods.tile_filter import FILTER_OPTIONS
from ..metrics import error_map, tone_map

# HDR metrics first: a scene that has them is charted by them (the LDR ones clip its lights).
# energy_ratio is best at 1, neither higher nor lower, so it is not charted.
HIGHER_IS_BETTER = {
    "psnr_tm": True,
    "ssim_tm": True,
    "hdr_flip": False,
    "log_lum_error": False,
    "psnr": True,
    "ssim": True,
    "flip": False,
}


def _pyplot():
    import matplotlib

    # Headless (no display is needed), except in a Jupyter kernel, whose inline backend shows
    # the figures a notebook cell returns.
    if "ipykernel" not in sys.modules and "MPLBACKEND" not in os.environ:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def pareto_front(table: pd.DataFrame, metric: str = "psnr") -> pd.DataFrame:
    """Rows no other row beats in both time (lower) and `metric` (better), sorted by time."""
    better = HIGHER_IS_BETTER[metric]
    rows = table.sort_values(["total_ms", metric], ascending=[True, not better])
    front, best = [], -np.inf
    for _, row in rows.iterrows():
        value = row[metric] if better else -row[metric]
        if value > best:
            front.append(row)
            best = value
    return pd.DataFrame(front)


def pareto(table: pd.DataFrame, scene: str, metric: str = "psnr", budget_ms: float | None = None):
    """Time per frame against error for one scene, one color per method, front marked."""
    rows = table[table["scene"] == scene]
    if rows.empty:
        raise ValueError(
            f"blurlab.plots.pareto: no rows for scene {scene!r}; the table has "
            f"{sorted(set(table['scene']))}"
        )
    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(9, 4.5))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    methods = sorted(set(rows["method"]))
    variants = rows.apply(_variant, axis=1)
    for (name, options), group in rows.groupby([rows["method"], variants]):
        ax.scatter(
            group["total_ms"],
            group[metric],
            label=name + (f" +{options}" if options else ""),
            s=28,
            alpha=0.85,
            color=colors[methods.index(name) % len(colors)],
            marker=OPTION_MARKERS.get(options, "*") if options else "o",
        )
    front = pareto_front(rows, metric)
    ax.step(
        front["total_ms"], front[metric], where="post", color="black", lw=1, label="Pareto front"
    )
    for _, row in front.iterrows():
        ax.annotate(
            _short(row),
            (row["total_ms"], row[metric]),
            fontsize=6,
            alpha=0.7,
            xytext=(3, 3),
            textcoords="offset points",
        )
    if budget_ms:
        ax.axvline(budget_ms, color="gray", ls="--", lw=1, label=f"budget {budget_ms} ms")
    ax.set_xscale("log")
    ax.set_xlabel(f"time per frame, ms ({rows['clock'].iloc[0]}, {rows['renderer'].iloc[0]})")
    ax.set_ylabel(
        metric.upper()
        + (
            " (dB, higher is better)"
            if metric in ("psnr", "psnr_tm")
            else " (higher is better)"
            if HIGHER_IS_BETTER[metric]
            else " (lower is better)"
        )
    )
    ax.set_title(
        f"{scene}: speed against accuracy, {rows['width'].iloc[0]}x{rows['height'].iloc[0]}"
    )
    ax.grid(True, which="both", alpha=0.3)
    # Outside the axes: with a dozen methods and options a legend inside hides points.
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    fig.tight_layout()
    return fig


# The filters' options (declared in blurlab.methods.tile_filter), each its own marker on the
# Pareto chart.
OPTION_MARKERS = {
    "jitter_tiles": "^",
    "adaptive_samples": "s",
    "early_exit": "D",
    "packed_inputs": "P",
}


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


# An image grid's panel is 2.6 in wide, 338 pixels at save()'s 130 dpi: images are averaged
# down to at most twice that before matplotlib draws them (it would resample a 1080p image
# to the same pixels, at several times the cost).
GRID_PIXELS = 676


def shrink(array: np.ndarray, most: int = GRID_PIXELS) -> np.ndarray:
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


def image_grid(
    reference: np.ndarray,
    images: dict[str, np.ndarray],
    errors: bool = True,
    error_scale: float = 0.25,
    error_maps: dict[str, np.ndarray] | None = None,
):
    """The reference, each method's image and (below) its error map, |error| scaled so that
    `error_scale` is white. `error_maps`: each image's metrics.error_map, if already made."""
    plt = _pyplot()
    columns = 1 + len(images)
    rows = 2 if errors else 1
    fig, axes = plt.subplots(
        rows, columns, figsize=(2.6 * columns, 1.7 * rows * 1.1), squeeze=False
    )
    show = lambda a: np.clip(linear_to_srgb(shrink(a[..., :3])), 0, 1)  # noqa: E731
    axes[0, 0].imshow(show(reference))
    axes[0, 0].set_title("reference", fontsize=7)
    for i, (name, image) in enumerate(images.items(), start=1):
        axes[0, i].imshow(show(image))
        axes[0, i].set_title(name, fontsize=7)
        if errors:
            error = error_maps[name] if error_maps is not None else error_map(reference, image)
            axes[1, i].imshow(np.clip(shrink(error) / error_scale, 0, 1), cmap="magma")
    for ax in axes.ravel():
        ax.axis("off")
    if errors:
        axes[1, 0].text(
            0.5,
            0.5,
            f"|error|\n(white = {error_scale})",
            ha="center",
            va="center",
            fontsize=7,
            transform=axes[1, 0].transAxes,
        )
    fig.tight_layout()
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


def colour_bar(vmax: float, label: str = "|error| (linear)", cmap: str = "magma"):
    """A horizontal colour bar alone, 0 .. vmax: the key of error_colours' pictures."""
    import matplotlib

    plt = _pyplot()
    fig, ax = plt.subplots(figsize=(4.5, 0.75))
    fig.colorbar(
        matplotlib.cm.ScalarMappable(matplotlib.colors.Normalize(0.0, vmax), cmap),
        cax=ax,
        orientation="horizontal",
        label=label,
    )
    fig.tight_layout()
    return fig


def worst_window(error: np.ndarray, side: int) -> tuple[int, int]:
    """(y, x) of the side x side window with the largest mean error (summed-area table)."""
    height, width = error.shape[:2]
    side = max(1, min(side, height, width))
    table = np.zeros((height + 1, width + 1))
    table[1:, 1:] = np.cumsum(np.cumsum(error, 0), 1)
    sums = table[side:, side:] - table[:-side, side:] - table[side:, :-side] + table[:-side, :-side]
    y, x = np.unravel_index(int(np.argmax(sums)), sums.shape)
    return int(y), int(x)


CROP_MIN_PIXELS = 96  # crops smaller than this are enlarged (nearest) to be seen
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
    plt = _pyplot()
    picture = crops_picture(reference, images, side)
    fig, ax = plt.subplots(figsize=(picture.shape[1] / 100, picture.shape[0] / 100), dpi=100)
    ax.imshow(picture, interpolation="nearest")
    ax.axis("off")
    fig.subplots_adjust(0, 0, 1, 1)
    return fig


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


def save(fig, path: str | Path) -> Path:
    """Writes PNG or SVG (by extension) and closes the figure."""
    path = Path(path)
    if path.suffix.lower() not in (".png", ".svg"):
        raise ValueError(f"blurlab.plots.save: write .png or .svg, not {path.name}")
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=130)
    _pyplot().close(fig)
    return path
