"""engine_eevee, docs/spec.md §17.2 step 3, in NumPy float64: the gather of Blender EEVEE-Next's
post-process motion blur over both half-shutters of the two-sided motion (§17.1), on the tiles
of steps 1-2 (blurlab.twins.eevee, shared with other methods). GPU pass: gather.glsl beside
it."""

from __future__ import annotations

import numpy as np

from ...twins.eevee import EARLY_EXIT, clamp_length, dilated_half_motions, lookup_tile
from ...twins.hashing import rand
from ...twins.inputs import sanitize_color, sanitize_depth
from ...twins.mcguire2012 import cone, cylinder, soft_depth_compare


def engine_eevee(
    color,
    depth,
    motion_prev,
    motion_next,
    *,
    tile_size: int,
    samples: int,
    max_blur: float,
    depth_scale: float,
    exposure: float,
    seed: int,
    dilated: np.ndarray | None = None,
) -> np.ndarray:
    """§17.2 step 3: (H, W, C) float64 blurred color. `dilated` is step 2's grid if already
    computed."""
    color = sanitize_color(color)
    depth = sanitize_depth(depth)
    h, w = depth.shape
    prev, next_, dilated = dilated_half_motions(
        motion_prev, motion_next, exposure, tile_size, max_blur, dilated
    )
    y, x = np.mgrid[0:h, 0:w]
    ty, tx = lookup_tile(x, y, tile_size, seed, dilated.shape[:2])
    reach = np.concatenate(
        [clamp_length(dilated[ty, tx, :2], max_blur), clamp_length(dilated[ty, tx, 2:], max_blur)],
        axis=-1,
    )
    longest = np.maximum(
        np.linalg.norm(reach[..., :2], axis=-1), np.linalg.norm(reach[..., 2:], axis=-1)
    )
    moving = longest >= EARLY_EXIT

    soft_z = 1.0 / depth_scale
    own = np.maximum(np.linalg.norm(prev, axis=-1), np.linalg.norm(next_, axis=-1))
    weight = 1.0 / np.maximum(own, 0.5)
    total = color * weight[..., None]
    j = rand(x, y, seed)
    center = np.stack([x, y], -1) + 0.5
    # Prev side: look along +prev for the pixels whose way back to t0 crosses X; next side:
    # along -next for those whose way on to t1 crosses it.
    for direction, mine in ((reach[..., :2], prev), (-reach[..., 2:], next_)):
        for i in range(samples):
            t = (i + j) / samples
            p = np.floor(center + direction * t[..., None]).astype(np.int64)
            py, px = np.clip(p[..., 1], 0, h - 1), np.clip(p[..., 0], 0, w - 1)
            dist = np.hypot(px - x, py - y)
            vy, vx = mine[py, px], mine
            zx, zy = depth, depth[py, px]
            f = soft_depth_compare(zx, zy, soft_z)
            b = soft_depth_compare(zy, zx, soft_z)
            both = cylinder(dist, vy) * cylinder(dist, vx) * 2
            a = f * cone(dist, vy) + b * cone(dist, vx) + both
            weight = weight + a
            total = total + a[..., None] * color[py, px]
    return np.where(moving[..., None], total / weight[..., None], color)
