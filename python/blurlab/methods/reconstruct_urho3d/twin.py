"""reconstruct_urho3d in NumPy float64: the Urho3D thesis's reconstruct pass (docs/spec.md §3.5,
spec.md here). GPU pass: reconstruct.glsl beside it, whose header lists the differences from
McGuire 2012. TileMax and NeighborMax are McGuire's (blurlab.twins.mcguire2012).
"""

from __future__ import annotations

import numpy as np

from ...twins.hashing import rand
from ...twins.inputs import sanitize_color, sanitize_depth, sanitize_motion
from ...twins.mcguire2012 import (
    cone,
    cylinder,
    half_velocity,
    neighbor_max,
    tap_positions,
    tile_max,
)

JITTER_SIZE = 64


def jitter_texture(seed: int) -> np.ndarray:
    """The tiled jitter texture: (64, 64) float32 values rand(x, y, seed) in [0, 1)."""
    y, x = np.mgrid[0:JITTER_SIZE, 0:JITTER_SIZE]
    return rand(x, y, seed).astype(np.float32)


def velocity_urho(motion: np.ndarray, exposure: float, k: float) -> np.ndarray:
    return np.clip(np.asarray(motion, np.float64) * exposure / 2, -k, k)


def sdc_urho(za: np.ndarray, zb: np.ndarray, soft_z: float) -> np.ndarray:
    return np.clip((za - zb) / soft_z, 0, 1)


def bilinear(image: np.ndarray, position: np.ndarray) -> np.ndarray:
    """Bilinear read at continuous positions (..., 2) (texel centers at i + 0.5), edges clamped."""
    h, w = image.shape[:2]
    u = position - 0.5
    i0 = np.floor(u).astype(np.int64)
    f = u - i0
    out = 0.0
    for dy in (0, 1):
        for dx in (0, 1):
            px = np.clip(i0[..., 0] + dx, 0, w - 1)
            py = np.clip(i0[..., 1] + dy, 0, h - 1)
            weight = (f[..., 0] if dx else 1 - f[..., 0]) * (f[..., 1] if dy else 1 - f[..., 1])
            texel = image[py, px]
            out = out + (weight[..., None] * texel if texel.ndim > weight.ndim else weight * texel)
    return out


def reconstruct_urho3d(
    color,
    depth,
    motion,
    *,
    k: int,
    samples: int,
    soft_z: float,
    exposure: float,
    seed: int,
    far: float,
) -> np.ndarray:
    color = sanitize_color(color)
    depth = np.minimum(sanitize_depth(depth), far)
    motion = sanitize_motion(motion)
    h, w = depth.shape
    y, x = np.mgrid[0:h, 0:w]
    vn = neighbor_max(tile_max(half_velocity(motion, exposure, k), k))[y // k, x // k]
    vn = np.clip(vn, -k, k)
    moving = np.linalg.norm(vn, axis=-1) > 0.5 + 0.01
    vx = velocity_urho(motion, exposure, k)
    weight = np.full((h, w), 0.75)
    total = color * 0.75
    j = jitter_texture(seed).astype(np.float64)[y % JITTER_SIZE, x % JITTER_SIZE] - 0.5
    center = np.stack([x, y], -1) + 0.5
    for t in tap_positions(samples, j):
        offset = vn * t[..., None]
        position = center + offset
        cy, zy = bilinear(color, position), bilinear(depth, position)
        vy = velocity_urho(bilinear(motion, position), exposure, k)
        dist = np.linalg.norm(offset, axis=-1)
        f = sdc_urho(depth, zy, soft_z)
        b = sdc_urho(zy, depth, soft_z)
        a = f * cone(dist, vy) + b * cone(dist, vx) + cylinder(dist, vy) * cylinder(dist, vx) * 2
        weight = weight + a
        total = total + a[..., None] * cy
    return np.where(moving[..., None], total / weight[..., None], color)
