"""EEVEE's tile passes, docs/spec.md §17.2 steps 1-2, in NumPy float64: the tile flatten and
the dilation along each tile's motion of Blender EEVEE-Next's post-process motion blur as its
algorithm is described (Blender's user manual), on the two-sided motion of §17.1, and the
jittered tile lookup. One function per pass; the GPU passes (shaders/passes/eevee_tile_*.glsl)
must match them. engine_eevee's gather is its folder's twin.py (python/blurlab/methods/
engine_eevee/); gather_coverage, engine_unity and engine_hdrp use these helpers too.
"""

from __future__ import annotations

import math

import numpy as np

from .hashing import rand
from .inputs import sanitize_motion
from .mcguire2012 import tile_max
from .tile_reach import reach_widening, segment_meets_box

EARLY_EXIT = 0.5  # px: a neighbourhood whose longest half-motion is shorter keeps C
JITTER_SALTS = (0x3C6EF372, 0xA54FF53A)  # engine_eevee's gather.glsl


def scaled_motion(motion, exposure: float) -> np.ndarray:
    """§17.2: E·m (non-finite vectors are zero). Tiles are chosen by this length, before the
    clamp: clamped lengths tie at max_blur."""
    return sanitize_motion(motion) * exposure


def clamp_length(v: np.ndarray, max_len: float) -> np.ndarray:
    """v with its length clamped to max_len pixels (Blender's Max Blur)."""
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    with np.errstate(divide="ignore", invalid="ignore"):
        return v * np.where(n > max_len, max_len / n, 1.0)


REACH_INDEX_BITS = 14  # the source tile index in the scatter dilation's keys (reach_keys.glsl)
# The largest step key (shaders/common/tile_pick.glsl): key + 1 and the tile index fill the
# 32-bit keys of the scatter dilation (docs/spec.md §17.6), so lengths past 2^18 - 2 steps tie.
PICK_KEY_MAX = 2 ** (32 - REACH_INDEX_BITS) - 2


def pick_key(length: np.ndarray, length_steps: float = 0.0) -> np.ndarray:
    """What the tile passes compare a length as (shaders/common/tile_pick.glsl): the length
    itself, or with length_steps > 0 floor(length · length_steps) up to PICK_KEY_MAX, so that
    lengths within one step tie and go to the first candidate in row order."""
    if length_steps > 0:
        with np.errstate(over="ignore", invalid="ignore"):
            steps = np.floor(np.asarray(length, np.float32).astype(np.float64) * length_steps)
        return np.minimum(steps, PICK_KEY_MAX)
    return length


def tile_flatten(
    prev: np.ndarray, next_: np.ndarray, tile_size: int, length_steps: float = 0.0
) -> np.ndarray:
    """§17.2 step 1: (ceil(H/s), ceil(W/s), 4): per tile the longest E·M_prev (xy) and the
    longest E·M_next (zw), unclamped; the first in row-major order among equal lengths (as
    pick_key compares them)."""
    key = None if length_steps <= 0 else (lambda length: pick_key(length, length_steps))
    return np.concatenate(
        [tile_max(prev, tile_size, key), tile_max(next_, tile_size, key)], axis=-1
    )


def dilation_radius(max_blur: float, tile_size: int, grid) -> int:
    """How many tiles away a tile's motion can reach: ceil(max_blur / s) + 1, at most the
    grid's longer side."""
    return min(math.ceil(max_blur / tile_size) + 1, max(grid))


def tile_dilate(
    tiles: np.ndarray,
    tile_size: int,
    max_blur: float,
    length_steps: float = 0.0,
    jitter_reach: float = 0.0,
) -> np.ndarray:
    """§17.2 step 2: for each tile D, the longest prev (xy) and next (zw) half-motion among the
    tiles whose reach meets D: the segment from a tile's center along -prev (toward the
    positions at t0) or +next, clamped to max_blur, in tile units, meets D's square widened by
    h + REACH_MARGIN,
    h = 1/2 - 1/(2s) (how far a tile's pixel centers lie from its center), plus `jitter_reach`
    tiles (gather_coverage's: how far its jittered lookup moves a pixel, §17.6). Among equal
    lengths the first source tile in row-major order wins (as pick_key compares them)."""
    th, tw = tiles.shape[:2]
    radius = dilation_radius(max_blur, tile_size, (th, tw))
    widen = reach_widening(tile_size) + jitter_reach
    out = np.zeros((th, tw, 4))
    best = np.full((th, tw, 2), -1.0)
    dy_, dx_ = np.mgrid[0:th, 0:tw]
    for oy in range(-radius, radius + 1):
        for ox in range(-radius, radius + 1):
            sy, sx = dy_ + oy, dx_ + ox
            valid = (sy >= 0) & (sy < th) & (sx >= 0) & (sx < tw)
            source = tiles[np.clip(sy, 0, th - 1), np.clip(sx, 0, tw - 1)]
            start = np.stack([ox + 0.5 + 0 * sx, oy + 0.5 + 0 * sy], -1).astype(np.float64)
            for side, sign in ((0, -1.0), (1, 1.0)):
                v = source[..., 2 * side : 2 * side + 2]
                length = pick_key(np.linalg.norm(v, axis=-1), length_steps)
                line = sign * clamp_length(v, max_blur) / tile_size
                reach = segment_meets_box(start, line, -widen, 1 + widen)
                better = valid & reach & (length > best[..., side])
                best[..., side] = np.where(better, length, best[..., side])
                out[..., 2 * side : 2 * side + 2] = np.where(
                    better[..., None], v, out[..., 2 * side : 2 * side + 2]
                )
    return out


def resolve_reach_keys(keys: np.ndarray, tiles: np.ndarray) -> np.ndarray:
    """The dilated tiles that the scatter dilation's keys name (docs/spec.md §17.6, "Steps 1–2
    by scatter"; shaders/common/reach_keys.glsl): `keys` (2·rows, columns) uint32, prev keys
    above next keys, each (k + 1)·2^14 + (16383 − source index); `tiles` (rows, columns, 4) the
    flattened tiles. A side without a key (0) gets 0."""
    keys = np.asarray(keys, np.uint32)
    rows, columns = tiles.shape[:2]
    mask = (1 << REACH_INDEX_BITS) - 1
    out = np.zeros(tiles.shape, tiles.dtype)
    for side in range(2):
        side_keys = keys[side * rows : (side + 1) * rows]
        source = mask - (side_keys & mask).astype(np.int64)
        sy, sx = np.divmod(np.minimum(source, rows * columns - 1), columns)
        picked = tiles[sy, sx, 2 * side : 2 * side + 2]
        out[..., 2 * side : 2 * side + 2] = np.where((side_keys > 0)[..., None], picked, 0)
    return out


def lookup_tile(x, y, tile_size: int, seed: int, grid, salts=JITTER_SALTS):
    """§17.2: (tile row, tile column) that pixel (x, y) reads: the tile containing its center
    moved by up to ±1/4 tile per axis, (rand - 1/2)·s/2, clamped to the grid. engine_unity
    reads its NeighborMax the same way with its own `salts` (§17.3)."""
    seed = np.uint32(seed)
    ox = (rand(x, y, seed ^ np.uint32(salts[0])) - 0.5) * 0.5 * tile_size
    oy = (rand(x, y, seed ^ np.uint32(salts[1])) - 0.5) * 0.5 * tile_size
    tx = np.clip(np.floor((x + 0.5 + ox) / tile_size).astype(np.int64), 0, grid[1] - 1)
    ty = np.clip(np.floor((y + 0.5 + oy) / tile_size).astype(np.int64), 0, grid[0] - 1)
    return ty, tx


def dilated_half_motions(
    motion_prev,
    motion_next,
    exposure,
    tile_size,
    max_blur,
    dilated=None,
    length_steps=0.0,
    jitter_reach=0.0,
):
    """§17.2 steps 1-2: (E·M_prev, E·M_next, each clamped to max_blur px, and the dilated
    tile grid of tile_size px tiles, lengths compared as pick_key(·, length_steps) says, each
    reach widened by `jitter_reach` tiles (tile_dilate); `dilated` if already computed)."""
    prev = scaled_motion(motion_prev, exposure)
    next_ = scaled_motion(motion_next, exposure)
    if dilated is None:
        tiles = tile_flatten(prev, next_, tile_size, length_steps)
        dilated = tile_dilate(tiles, tile_size, max_blur, length_steps, jitter_reach)
    return clamp_length(prev, max_blur), clamp_length(next_, max_blur), dilated
