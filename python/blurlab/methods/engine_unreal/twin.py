"""engine_unreal, docs/spec.md §17.5, in NumPy float64: Unreal Engine 4's motion blur as its
algorithm is described, the whole filter. Its passes' twins are shared with engine_unreal5 and
live in blurlab.twins.unreal; the GPU passes are the shaders beside this file and
shaders/passes/unreal_velocity_flatten.glsl."""

from __future__ import annotations

import numpy as np

from ...twins.hashing import rand
from ...twins.inputs import sanitize_color
from ...twins.polar_fixed_point import LENGTH_CODE_MAX, decode_polar
from ...twins.unreal import (
    SAMPLES_BY_QUALITY,
    SKIP,
    SLOW,
    TILE,
    max_radius_px,
    mirrored_pairs_blur,
    neighbor_dilate,
    tile_minmax,
    velocity_flatten,
)


def engine_unreal(
    color,
    depth,
    motion,
    *,
    quality: int,
    max_blur: float,
    depth_extent: float,
    exposure: float,
    seed: int,
) -> np.ndarray:
    """§17.5 step 4: (H, W, C) float64 blurred color."""
    color = sanitize_color(color)
    h, w = color.shape[:2]
    radius = max_radius_px(w, max_blur)
    codes = velocity_flatten(depth, motion, exposure=exposure, radius=radius)
    neighbors = neighbor_dilate(tile_minmax(codes), radius)
    taps = SAMPLES_BY_QUALITY[quality]
    pairs = taps // 2

    y, x = np.mgrid[0:h, 0:w]
    tile = neighbors[y // TILE, x // TILE]
    kind = tile[..., 3]
    slow = kind == SLOW
    vmax = decode_polar(tile[..., :2], radius)
    length = codes[..., 0] / LENGTH_CODE_MAX * radius
    z = codes[..., 2]
    # Length codes and decoded lengths order the pairs' speeds alike.
    blurred = mirrored_pairs_blur(
        color, z, length, vmax, rand(x, y, seed), pairs, depth_extent, uniform=~slow
    )
    return np.where((kind == SKIP)[..., None], color, blurred)
