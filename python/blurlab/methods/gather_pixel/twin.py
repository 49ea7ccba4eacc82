"""gather_pixel, docs/spec.md §17.9, in NumPy float64: the tile-free gather along each pixel's
own motion of Bevy (0.14) and Unity URP, its tap count following the pixel's speed. GPU pass:
gather.glsl beside it."""

from __future__ import annotations

import numpy as np

from ...twins.hashing import rand
from ...twins.inputs import sanitize_color, sanitize_depth, sanitize_motion


def pixel_taps(motion, *, exposure: float, spacing: float, samples: int) -> np.ndarray:
    """(H, W) int: the taps on each side of X, n = min(ceil(|E·M/2| / spacing), samples)."""
    half = np.linalg.norm(sanitize_motion(motion) * exposure / 2, axis=-1)
    return np.minimum(np.ceil(half / spacing), samples).astype(np.int64)


def front_weight(z_x, z_y, depth_extent: float) -> np.ndarray:
    """A tap's weight: 1 at or behind X's depth, falling to 0 where it lies depth_extent or
    more in front of X (a nearer surface does not bleed into X's own blur)."""
    with np.errstate(invalid="ignore"):
        d = np.where(z_y == z_x, 0.0, (z_y - z_x) / depth_extent)
    return np.clip(1.0 + d, 0.0, 1.0)


def gather_pixel(
    color,
    depth,
    motion,
    *,
    samples: int,
    spacing: float,
    depth_extent: float,
    exposure: float,
    seed: int,
) -> np.ndarray:
    """(H, W, C): C(X) and n mirrored pairs at X ± (i + j)/n · E·M(X)/2, i < n, j = rand(x, y,
    seed), each tap weighted by front_weight, normalised; taps clamp to the image."""
    color = sanitize_color(color)
    h, w = color.shape[:2]
    z = sanitize_depth(depth)
    v = sanitize_motion(motion) * exposure / 2
    n = pixel_taps(motion, exposure=exposure, spacing=spacing, samples=samples)
    y, x = np.mgrid[0:h, 0:w]
    j = rand(x, y, seed)
    center = np.stack([x, y], -1) + 0.5
    total = color.copy()
    weight = np.ones((h, w))
    for i in range(int(n.max(initial=0))):
        active = i < n
        t = (i + j) / np.maximum(n, 1)
        for sign in (1.0, -1.0):
            p = np.floor(center + sign * t[..., None] * v).astype(np.int64)
            py, px = np.clip(p[..., 1], 0, h - 1), np.clip(p[..., 0], 0, w - 1)
            a = np.where(active, front_weight(z, z[py, px], depth_extent), 0.0)
            total += a[..., None] * color[py, px]
            weight += a
    return total / weight[..., None]
