"""The reconstruction filter of McGuire, Hennessy, Bukowski and Osman (I3D 2012), docs/spec.md §3,
in NumPy float64: what the tile filters share, vectorized over pixels. TileMax and NeighborMax
(shaders/passes/tile_max.glsl, neighbor_max.glsl) must match it; the filter's reconstruct pass
is methods/reconstruct_mcguire2012/twin.py, built on filter_start and the weights here.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .hashing import rand
from .inputs import pack_half, sanitize_color, sanitize_depth, sanitize_motion


def half_velocity(motion: np.ndarray, exposure: float, k: float) -> np.ndarray:
    """§3.1: q = M·E/2; V = q · clamp(|q|, 0.5, k) / max(|q|, 1e-6); V = 0 where q = 0.
    M is read as the GPU reads it (twins.inputs: non-finite vectors are zero motion)."""
    q = sanitize_motion(motion) * exposure / 2
    n = np.linalg.norm(q, axis=-1, keepdims=True)
    scale = np.clip(n, 0.5, k) / np.maximum(n, 1e-6)
    return np.where(n > 0, q * scale, 0.0)


def len_half(v: np.ndarray) -> np.ndarray:
    """§3: max(|v|, 0.5), wherever a length divides."""
    return np.maximum(np.linalg.norm(v, axis=-1), 0.5)


def cone(dist: np.ndarray, v: np.ndarray) -> np.ndarray:
    return np.clip(1 - dist / len_half(v), 0, 1)


def cylinder(dist: np.ndarray, v: np.ndarray) -> np.ndarray:
    length = len_half(v)
    return 1 - smoothstep(0.95 * length, 1.05 * length, dist)


def smoothstep(edge0, edge1, x):
    t = np.clip((x - edge0) / (edge1 - edge0), 0, 1)
    return t * t * (3 - 2 * t)


def soft_depth_compare(za: np.ndarray, zb: np.ndarray, soft_z: float) -> np.ndarray:
    """sdc(za, zb) = clamp(1 - (zb - za) / soft_z, 0, 1); equal depths (both +inf on the
    background) compare as equal."""
    with np.errstate(invalid="ignore"):
        d = np.where(za == zb, 0.0, zb - za)
    return np.clip(1 - d / soft_z, 0, 1)


def tap_positions(samples: int, j) -> list:
    """§3.4's sample positions t in (-1, 1) along vN for a fixed S: t_i = -1 + 2(i + j + 1)/(S + 1)
    for i = 0..S-1, the middle one skipped when S is odd (it is X itself)."""
    skip = (samples - 1) // 2 if samples % 2 == 1 else -1
    return [-1 + 2 * (i + j + 1) / (samples + 1) for i in range(samples) if i != skip]


def tile_max(v: np.ndarray, k: int, key=None) -> np.ndarray:
    """§3.2: (ceil(H/k), ceil(W/k), 2): the half-vector of largest length in each k x k tile,
    the first in row order among equal lengths; `key` maps lengths to what is compared
    (default: the lengths)."""
    h, w = v.shape[:2]
    th, tw = -(-h // k), -(-w // k)
    padded = np.zeros((th * k, tw * k, 2))
    padded[:h, :w] = v
    tiles = padded.reshape(th, k, tw, k, 2).transpose(0, 2, 1, 3, 4).reshape(th, tw, k * k, 2)
    lengths = np.linalg.norm(tiles, axis=-1)
    best = np.argmax(lengths if key is None else key(lengths), axis=-1)
    return np.take_along_axis(tiles, best[..., None, None], axis=2)[:, :, 0]


def length_key(steps: int):
    """What TileMax and NeighborMax compare lengths as with LENGTH_KEY_STEPS = `steps`
    (shaders/common/length_key.glsl): floor(length · steps + 1/4), the length rounded to
    float32 first as the GPU holds it."""

    def key(length):
        return np.floor(np.asarray(length, np.float32).astype(np.float64) * steps + 0.25)

    return key


def neighbor_max(tiles: np.ndarray, diagonal_reach: bool = False, key=None) -> np.ndarray:
    """§3.3: the TileMax of largest length among the 3 x 3 tiles around each tile (lengths
    compared as `key` maps them, by default as they are).

    `diagonal_reach` (reconstruct_guertin2014, docs/guertin2014.md step 1): a diagonal tile at
    offset (dx, dy) counts only where (v.x dx)(v.y dy) > 0, i.e. where its motion, extended
    both ways, can reach the center tile."""
    th, tw = tiles.shape[:2]
    lengths = np.full((th + 2, tw + 2), -1.0)  # outside the grid: never chosen
    norms = np.linalg.norm(tiles, axis=-1)
    lengths[1:-1, 1:-1] = norms if key is None else key(norms)
    padded = np.zeros((th + 2, tw + 2, 2))
    padded[1:-1, 1:-1] = tiles
    best_length = np.full((th, tw), -np.inf)
    best = np.zeros((th, tw, 2))
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            candidate = lengths[1 + dy : th + 1 + dy, 1 + dx : tw + 1 + dx]
            v = padded[1 + dy : th + 1 + dy, 1 + dx : tw + 1 + dx]
            better = candidate > best_length
            if diagonal_reach and dx and dy:
                better &= (v[..., 0] * dx) * (v[..., 1] * dy) > 0
            best_length = np.where(better, candidate, best_length)
            best = np.where(better[..., None], v, best)
    return best


# --- Options of the filters (docs/guertin2014.md "Options"; GLSL twin:
# shaders/common/filter_options.glsl). Each is off at its default.

TILE_JITTER_SALT = 0x68E31DA4


def lookup_tile(x, y, k: int, seed: int, jitter: bool, grid) -> tuple[np.ndarray, np.ndarray]:
    """(tile row, tile column) whose NeighborMax pixel (x, y) reads: its own tile, or with
    `jitter` the tile containing its center + k/4 (cos a, sin a), a = 2π rand(x, y, seed ^
    salt), clamped to the grid, never a diagonal neighbor (the axis of the smaller offset stays
    the pixel's own)."""
    own_x, own_y = x // k, y // k
    if not jitter:
        return own_y, own_x
    a = 2 * np.pi * rand(x, y, np.uint32(seed) ^ np.uint32(TILE_JITTER_SALT))
    ox, oy = 0.25 * k * np.cos(a), 0.25 * k * np.sin(a)
    tx = np.clip(np.floor((x + 0.5 + ox) / k).astype(np.int64), 0, grid[1] - 1)
    ty = np.clip(np.floor((y + 0.5 + oy) / k).astype(np.int64), 0, grid[0] - 1)
    diagonal = (tx != own_x) & (ty != own_y)
    keep_x = np.abs(ox) >= np.abs(oy)
    ty = np.where(diagonal & keep_x, own_y, ty)
    tx = np.where(diagonal & ~keep_x, own_x, tx)
    return ty, tx


def sample_count(vn_length: np.ndarray, samples: int, adaptive: bool) -> np.ndarray:
    """S, or with `adaptive` about one sample per 2 px of the span 2|vN|: clamp(⌊|vN| + 0.5⌋,
    2, S) (S where S < 2)."""
    if not adaptive:
        return np.full(np.shape(vn_length), samples, np.int64)
    return np.minimum(samples, np.maximum(2, np.floor(vn_length + 0.5).astype(np.int64)))


def exits_early(vn_length: np.ndarray, early_exit: float) -> np.ndarray:
    """§3.4's test |vN| <= 0.5 + 0.01, or the longest motion nearby, 2|vN|, under `early_exit`
    pixels."""
    return (vn_length <= 0.5 + 0.01) | (2 * vn_length < early_exit)


def neighborhood(v, k, seed, jitter_tiles, neighbor, diagonal_reach=False):
    """(x, y, vN) for every pixel: its coordinates and the NeighborMax it reads."""
    h, w = v.shape[:2]
    if neighbor is None:
        neighbor = neighbor_max(tile_max(v, k), diagonal_reach)
    y, x = np.mgrid[0:h, 0:w]
    ty, tx = lookup_tile(x, y, k, seed, jitter_tiles, neighbor.shape[:2])
    return x, y, neighbor[ty, tx]


class FilterStart(NamedTuple):
    """What §3.4's filters (McGuire 2012, Guertin 2014) read before their taps."""

    color: np.ndarray  # (H, W, C) sanitized
    depth: np.ndarray  # (H, W) sanitized
    v: np.ndarray  # (H, W, 2) half-velocity
    x: np.ndarray  # pixel columns
    y: np.ndarray  # pixel rows
    vn: np.ndarray  # the NeighborMax each pixel reads
    vn_length: np.ndarray
    moving: np.ndarray  # False where the pixel exits early and keeps its color
    n: np.ndarray  # samples per pixel


def filter_start(
    color, depth, motion, neighbor, k, samples, exposure, seed, options, diagonal_reach=False
) -> FilterStart:
    """The inputs (packed as docs/spec.md §19 packs them where packed_inputs), the
    half-velocity, the NeighborMax read, the early exit and the sample count. `options`:
    (jitter_tiles, adaptive_samples, early_exit, packed_inputs), as the filters take them."""
    jitter_tiles, adaptive_samples, early_exit, packed_inputs = options
    if packed_inputs:  # docs/spec.md §19: what the packed textures hold
        color, depth, motion = pack_half(color, depth, motion)
    v = half_velocity(motion, exposure, k)
    x, y, vn = neighborhood(v, k, seed, jitter_tiles, neighbor, diagonal_reach)
    vn_length = np.linalg.norm(vn, axis=-1)
    moving = ~exits_early(vn_length, early_exit)
    n = sample_count(vn_length, samples, adaptive_samples)
    return FilterStart(
        sanitize_color(color), sanitize_depth(depth), v, x, y, vn, vn_length, moving, n
    )
