"""reconstruct_mcguire2012, docs/spec.md §3.4 (spec.md here), in NumPy float64, vectorized over
pixels. GPU pass: reconstruct.glsl beside it, after TileMax and NeighborMax, whose twins are the
tile filters' shared ones (blurlab.twins.mcguire2012)."""

from __future__ import annotations

import numpy as np

from ...twins.hashing import rand
from ...twins.inputs import round_to_half
from ...twins.mcguire2012 import cone, cylinder, filter_start, len_half, soft_depth_compare


def reconstruct_mcguire2012(
    color,
    depth,
    motion,
    *,
    k: int,
    samples: int,
    soft_z: float,
    exposure: float,
    seed: int,
    jitter_tiles: int,
    adaptive_samples: int,
    early_exit: float,
    packed_inputs: bool,
    half_result: bool,
    neighbor: np.ndarray | None = None,
) -> np.ndarray:
    """§3.4: (H, W, C) float64 blurred color, with the options of docs/guertin2014.md
    (jitter_tiles, adaptive_samples, early_exit; 0 is off) and packed_inputs (docs/spec.md
    §19: the inputs rounded as the packed textures hold them), half_result (the result rounded to
    half floats as the RGBA16F target holds it). `neighbor` is NeighborMax if already computed."""
    options = (jitter_tiles, adaptive_samples, early_exit, packed_inputs)
    start = filter_start(color, depth, motion, neighbor, k, samples, exposure, seed, options)
    color, depth, v, x, y, vn, vn_length, moving, n = start
    h, w = depth.shape

    vx = v
    weight = 1 / len_half(vx)
    total = color * weight[..., None]
    j = rand(x, y, seed) - 0.5
    center = np.stack([x, y], -1) + 0.5
    skip = np.where(n % 2 == 1, (n - 1) // 2, -1)
    for i in range(samples):
        active = (i < n) & (i != skip)
        t = -1 + 2 * (i + j + 1) / (n + 1)
        p = np.floor(center + vn * t[..., None]).astype(np.int64)
        py, px = np.clip(p[..., 1], 0, h - 1), np.clip(p[..., 0], 0, w - 1)
        dist = np.hypot(px - x, py - y)
        vy = v[py, px]
        zx, zy = depth, depth[py, px]
        f = soft_depth_compare(zx, zy, soft_z)
        b = soft_depth_compare(zy, zx, soft_z)
        a = f * cone(dist, vy) + b * cone(dist, vx) + cylinder(dist, vy) * cylinder(dist, vx) * 2
        a = np.where(active, a, 0.0)
        weight = weight + a
        total = total + a[..., None] * color[py, px]
    result = np.where(moving[..., None], total / weight[..., None], color)
    return round_to_half(result) if half_result else result
