"""engine_jimenez2014, docs/spec.md §17.8, in NumPy float64: the reconstruction filter of
Jimenez 2014 ("Next Generation Post Processing in Call of Duty: Advanced Warfare") as the talk
describes it, on §3's TileMax and NeighborMax. The GPU pass (reconstruct.glsl beside it) must
match it; the interleaved gradient noise is computed in float32, step by step as the shader
does, so both jitter the taps by the same bits."""

from __future__ import annotations

import numpy as np

from ...twins.inputs import sanitize_color, sanitize_depth
from ...twins.mcguire2012 import half_velocity, neighbor_max, tile_max
from ...twins.unreal import mirrored_pairs_blur

# The talk's interleaved gradient noise: fract(C · fract(dot(p, (A, B)))), p the pixel's center
# moved by FRAME_STEP per frame.
IGN_A, IGN_B, IGN_C = np.float32(0.06711056), np.float32(0.00583715), np.float32(52.9829189)
FRAME_STEP = np.float32(5.588238)
FRAMES = 64  # the seed picks one of 64 frames of the noise
EARLY_EXIT = 0.5 + 0.01  # px: §3.4's test on |vN|


def interleaved_gradient_noise(x, y, seed: int) -> np.ndarray:
    """In [0, 1), float32 arithmetic in the shader's order, no fused multiply-add."""
    shift = FRAME_STEP * np.float32(seed % FRAMES)
    px = np.asarray(x, np.float32) + np.float32(0.5) + shift
    py = np.asarray(y, np.float32) + np.float32(0.5) + shift
    s = IGN_A * px + IGN_B * py
    s = s - np.floor(s)
    t = IGN_C * s
    return (t - np.floor(t)).astype(np.float64)


def engine_jimenez2014(
    color, depth, motion, *, k: int, samples: int, soft_z: float, exposure: float, seed: int
) -> np.ndarray:
    """§17.8: (H, W, C) float64 blurred color."""
    color = sanitize_color(color)
    z = sanitize_depth(depth)
    h, w = z.shape
    v = half_velocity(motion, exposure, k)
    neighbors = neighbor_max(tile_max(v, k))
    y, x = np.mgrid[0:h, 0:w]
    vn = neighbors[y // k, x // k]
    length = np.linalg.norm(v, axis=-1)
    pairs = max(samples // 2, 1)
    j = interleaved_gradient_noise(x, y, seed)
    blurred = mirrored_pairs_blur(color, z, length, vn, j, pairs, soft_z)
    still = np.linalg.norm(vn, axis=-1) <= EARLY_EXIT
    return np.where(still[..., None], color, blurred)
