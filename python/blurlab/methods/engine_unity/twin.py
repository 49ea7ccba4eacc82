"""engine_unity, docs/spec.md §17.3, in NumPy float64: the motion blur of Unity's
PostProcessing v2 (the KinoMotion lineage) as its algorithm is described. One
function per pass; the GPU passes (the shaders beside it) must match them.

Velocities travel as 10-bit codes c in 0..1023, as in the engine's 10:10:10:2 buffer:
v = (2c/1023 - 1)·R. Tiles compare the exact integer key (2c_x - 1023)² + (2c_y - 1023)², so
the GPU and this twin choose the same tile among equal lengths.
"""

from __future__ import annotations

import math

import numpy as np

from ...twins.eevee import lookup_tile
from ...twins.guertin2014 import mirror_pair, mirrored_taps
from ...twins.hashing import rand
from ...twins.inputs import sanitize_color, sanitize_depth, sanitize_motion
from ...twins.mcguire2012 import cone

CODE_MAX = 1023
EARLY_EXIT = 2.0  # px: a neighbourhood whose NeighborMax is shorter keeps C
CENTER_BIAS = np.float32(1.0201)  # NeighborMax: 1.01 on the center's length, squared
JITTER_SALTS = (0x1B873593, 0xCC9E2D51)  # reconstruct.glsl


def max_radius_px(height: int, max_radius: float) -> float:
    """R: the largest blur radius, max_radius % of the image height, in pixels."""
    return max_radius / 100.0 * height


def tile_size(height: int, max_radius: float) -> int:
    """T: R rounded up to a multiple of 8 pixels (at least 8)."""
    return max(8, 8 * math.ceil(max_radius_px(height, max_radius) / 8))


def quantize(x) -> np.ndarray:
    """A value in [0, 1] as a 10-bit unorm code: floor(x·1023 + 1/2)."""
    return np.floor(np.clip(x, 0.0, 1.0) * CODE_MAX + 0.5)


def decode(codes: np.ndarray, radius: float) -> np.ndarray:
    return (2.0 * codes / CODE_MAX - 1.0) * radius


def key(codes: np.ndarray) -> np.ndarray:
    """Squared length of a coded velocity, an exact integer (in units of (R/1023)²)."""
    return ((2 * codes - CODE_MAX) ** 2).sum(axis=-1)


def velocity_setup(depth, motion, *, exposure: float, radius: float, far: float) -> np.ndarray:
    """§17.3 step 1: (H, W, 3) codes: the half-vector E·M/2 clamped to R, mapped from [-R, R]
    to [0, 1], and the linear depth Z/far clamped to [0, 1], each as a 10-bit code."""
    v = sanitize_motion(motion) * exposure / 2
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        v = v * np.where(n > radius, radius / n, 1.0)
    with np.errstate(invalid="ignore"):
        d = np.minimum(sanitize_depth(depth) / far, 1.0)
    return np.concatenate([quantize((v / radius + 1) / 2), quantize(d)[..., None]], axis=-1)


def reduce_max(codes: np.ndarray, step: int) -> np.ndarray:
    """The longest coded velocity of each step x step block (the last ones may be partial),
    the first in row-major order among equal keys."""
    h, w = codes.shape[:2]
    oh, ow = -(-h // step), -(-w // step)
    best = np.zeros((oh, ow, 2))
    best_key = np.full((oh, ow), -1.0)
    for dy in range(step):
        for dx in range(step):
            ys = np.arange(oh) * step + dy
            xs = np.arange(ow) * step + dx
            inside = (ys < h)[:, None] & (xs < w)[None, :]
            c = codes[np.minimum(ys, h - 1)][:, np.minimum(xs, w - 1), :2]
            k = key(c)
            better = inside & (k > best_key)
            best_key = np.where(better, k, best_key)
            best = np.where(better[..., None], c, best)
    return best


def tile_max(codes: np.ndarray, tile: int) -> np.ndarray:
    """§17.3 step 2: three 2 x 2 reductions, then one of tile/8 x tile/8."""
    for _ in range(3):
        codes = reduce_max(codes, 2)
    return reduce_max(codes, tile // 8)


def neighbor_max(tiles: np.ndarray) -> np.ndarray:
    """§17.3 step 3: the longest of the 3 x 3 tiles around each tile, the center's length
    counted 1.01 times (float32 comparison k_n > 1.0201·k_c, as the GPU makes it)."""
    th, tw = tiles.shape[:2]
    best = tiles.copy()
    best_key = (CENTER_BIAS * key(tiles).astype(np.float32)).astype(np.float64)
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            if dx == 0 and dy == 0:
                continue
            ys, xs = np.arange(th) + dy, np.arange(tw) + dx
            inside = ((ys >= 0) & (ys < th))[:, None] & ((xs >= 0) & (xs < tw))[None, :]
            c = tiles[np.clip(ys, 0, th - 1)][:, np.clip(xs, 0, tw - 1)]
            k = key(c)
            better = inside & (k > best_key)
            best_key = np.where(better, k, best_key)
            best = np.where(better[..., None], c, best)
    return best


def engine_unity(
    color,
    depth,
    motion,
    *,
    samples: int,
    max_radius: float,
    depth_factor: float,
    exposure: float,
    far: float,
    seed: int,
) -> np.ndarray:
    """§17.3 step 4: (H, W, C) float64 blurred color."""
    color = sanitize_color(color)
    h, w = color.shape[:2]
    radius = max_radius_px(h, max_radius)
    tile = tile_size(h, max_radius)
    codes = velocity_setup(depth, motion, exposure=exposure, radius=radius, far=far)
    neighbors = neighbor_max(tile_max(codes, tile))
    v = decode(codes[..., :2], radius)
    z = codes[..., 2] / CODE_MAX

    y, x = np.mgrid[0:h, 0:w]
    ty, tx = lookup_tile(x, y, tile, seed, neighbors.shape[:2], JITTER_SALTS)
    vmax = decode(neighbors[ty, tx], radius)
    l_max = np.linalg.norm(vmax, axis=-1)
    moving = l_max >= EARLY_EXIT

    vc = v
    l_c = np.linalg.norm(vc, axis=-1)
    with np.errstate(divide="ignore", invalid="ignore"):
        along_center = vc * (l_max / np.maximum(l_c, 1e-20))[..., None]
    v_alt = np.where((2 * l_c > l_max)[..., None], along_center, vmax)
    n = np.clip(np.floor(l_max / 2), 1, samples).astype(np.int64)

    weight = 1.0 / np.maximum(l_c, 0.5)
    total = color * weight[..., None]
    j = rand(x, y, seed)
    center = np.stack([x, y], -1) + 0.5
    for i in range(samples):
        active = i < n
        t = (i + j) / n
        d = vmax if i % 2 == 0 else v_alt
        pair = []
        for py, px in mirrored_taps(center, d * t[..., None], h, w):
            dist = np.hypot(px - x, py - y)
            front = np.clip(0.5 + depth_factor * (z - z[py, px]), 0.0, 1.0)
            a = front * cone(dist, v[py, px]) + (1 - front) * cone(dist, vc)
            pair.append((a, z[py, px], np.linalg.norm(v[py, px], axis=-1), py, px))
        (a1, z1, s1, py1, px1), (a2, z2, s2, py2, px2) = pair
        a1, a2 = mirror_pair(a1, a2, z1, z2, s1, s2)
        a1, a2 = np.where(active, a1, 0.0), np.where(active, a2, 0.0)
        weight = weight + a1 + a2
        total = total + a1[..., None] * color[py1, px1] + a2[..., None] * color[py2, px2]
    return np.where(moving[..., None], total / weight[..., None], color)
