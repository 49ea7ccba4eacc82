"""Tile classification (Jimenez 2014, "Next Generation Post Processing in Call of Duty:
Advanced Warfare") on top of the reconstruction filter's tiles (docs/spec.md §3.2-3.3), in NumPy
float64. GPU twins: shaders/passes/tile_max.glsl (TILE_BOUNDS), classify_tiles.glsl,
tile_copy.glsl, uniform_gather.glsl. docs/classify_and_steps.md defines the classes.
"""

from __future__ import annotations

import numpy as np

from .hashing import rand
from .inputs import sanitize_color
from .mcguire2012 import (
    cone,
    cylinder,
    half_velocity,
    len_half,
    neighbor_max,
    reconstruct_mcguire2012,
    tap_positions,
    tile_max,
)

STILL, UNIFORM, FULL = 0, 1, 2
CLASS_NAMES = ("still", "uniform", "full")
STILL_THRESHOLD = 0.5 + 0.01  # docs/spec.md §3.4: the filter's early exit


def tile_bounds(v: np.ndarray, k: int) -> np.ndarray:
    """(ceil(H/k), ceil(W/k), 4): each tile's min V.x, min V.y, max V.x, max V.y."""
    h, w = v.shape[:2]
    th, tw = -(-h // k), -(-w // k)
    low = np.full((th * k, tw * k, 2), np.inf)
    high = np.full((th * k, tw * k, 2), -np.inf)
    low[:h, :w] = v
    high[:h, :w] = v
    blocks = lambda a: a.reshape(th, k, tw, k, 2)  # noqa: E731
    return np.concatenate([blocks(low).min(axis=(1, 3)), blocks(high).max(axis=(1, 3))], -1)


def classify_tiles(
    bounds: np.ndarray,
    neighbor: np.ndarray,
    still_threshold: float = STILL_THRESHOLD,
    uniform_spread: float = 0.5,
) -> np.ndarray:
    """(tiles_h, tiles_w) int: STILL where |vN| <= still_threshold; else UNIFORM where the
    corner of the 3 x 3 neighbourhood's bounding box of V farthest from vN lies within
    uniform_spread of it; else FULL."""
    th, tw = neighbor.shape[:2]
    padded = np.empty((th + 2, tw + 2, 4))
    padded[..., :2], padded[..., 2:] = np.inf, -np.inf  # outside the grid: no vectors
    padded[1:-1, 1:-1] = bounds
    low = np.full((th, tw, 2), np.inf)
    high = np.full((th, tw, 2), -np.inf)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            window = padded[1 + dy : th + 1 + dy, 1 + dx : tw + 1 + dx]
            low = np.minimum(low, window[..., :2])
            high = np.maximum(high, window[..., 2:])
    far = np.maximum(np.abs(low - neighbor), np.abs(high - neighbor))
    spread = np.linalg.norm(far, axis=-1)
    classes = np.where(spread <= uniform_spread, UNIFORM, FULL)
    return np.where(np.linalg.norm(neighbor, axis=-1) <= still_threshold, STILL, classes)


def uniform_gather(color, neighbor: np.ndarray, *, k: int, samples: int, seed: int):
    """docs/spec.md §3.4 with V[X] = V[Y] = vN and f = b = 1 at every pixel: (H, W, C) float64.

    Its own tap loop, not the filter run on a frame of V = vN: a tap in a neighbouring tile
    would then read that tile's vN, where here every tap of X uses X's."""
    color = sanitize_color(color)
    h, w = color.shape[:2]
    y, x = np.mgrid[0:h, 0:w]
    vn = neighbor[y // k, x // k]
    weight = 1 / len_half(vn)
    total = color * weight[..., None]
    j = rand(x, y, seed) - 0.5
    center = np.stack([x, y], -1) + 0.5
    for t in tap_positions(samples, j):
        p = np.floor(center + vn * t[..., None]).astype(np.int64)
        py, px = np.clip(p[..., 1], 0, h - 1), np.clip(p[..., 0], 0, w - 1)
        dist = np.hypot(px - x, py - y)
        a = 2 * cone(dist, vn) + 2 * cylinder(dist, vn) ** 2
        weight = weight + a
        total = total + a[..., None] * color[py, px]
    return total / weight[..., None]


def classified(
    color,
    depth,
    motion,
    full,
    *,
    k: int,
    samples: int,
    exposure: float,
    seed: int,
    uniform_spread: float,
    still_threshold: float = STILL_THRESHOLD,
):
    """The classified filter: C on still tiles, uniform_gather on uniform tiles and `full`
    (the unclassified filter's (H, W, C) output) on full tiles. Returns (image, class map)."""
    color = sanitize_color(color)
    v = half_velocity(motion, exposure, k)
    neighbor = neighbor_max(tile_max(v, k))
    classes = classify_tiles(tile_bounds(v, k), neighbor, still_threshold, uniform_spread)
    h, w = color.shape[:2]
    y, x = np.mgrid[0:h, 0:w]
    per_pixel = classes[y // k, x // k][..., None]
    cheap = uniform_gather(color, neighbor, k=k, samples=samples, seed=seed)
    image = np.where(per_pixel == STILL, color, np.where(per_pixel == UNIFORM, cheap, full))
    return image, classes


def reconstruct(color, depth, motion, *, classify: bool, uniform_spread: float, **filter_params):
    """reconstruct_mcguire2012 as the method runs it: the filter of blurlab.twins.
    mcguire2012 with `filter_params` (its keyword-only parameters), or with `classify` the
    classified filter, which takes none of the options: (H, W, C) float64."""
    full = reconstruct_mcguire2012(color, depth, motion, **filter_params)
    if not classify:
        return full
    return classified(
        color,
        depth,
        motion,
        full,
        k=filter_params["k"],
        samples=filter_params["samples"],
        exposure=filter_params["exposure"],
        seed=filter_params["seed"],
        uniform_spread=uniform_spread,
    )[0]
