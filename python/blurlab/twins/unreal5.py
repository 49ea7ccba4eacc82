"""engine_unreal5's passes, docs/spec.md §17.7, in NumPy float64: the motion blur of Unreal
Engine 5 as its console variables and talks describe it. One function per pass; the GPU passes
(the shaders of methods/engine_unreal5/) must match them, and the whole filter is
methods/engine_unreal5/twin.py. Velocities and depths are engine_unreal's 11:11:10 codes
(§17.5 step 1); tiles compare integer codes, so the GPU and this twin choose the same tiles,
velocities and classes.
"""

from __future__ import annotations

import numpy as np

from .inputs import sanitize_color
from .polar_fixed_point import ANGLE_CODES, LENGTH_CODE_MAX
from .unreal import (
    NEIGHBORHOOD_REACH,
    SAMPLES_BY_QUALITY,
    SKIP_BELOW,
    TILE,
    neighborhood_sources,
    reaches,
    tile_minmax,
)

AXIS_APART = 256  # angle codes (45°): two velocities whose axes differ more are two directions
HALF_TURN = ANGLE_CODES // 2  # v and -v blur along the same axis
PACK = ANGLE_CODES  # a second velocity travels as c_l·PACK + c_a, exact in float32
SKIP, UNIFORM, GATHER, GATHER_2, UNIFORM_HALF, GATHER_HALF = range(6)
# The tile classes in the order of their values and of the method's tile lists; uniform_half and
# gather_half gather at half resolution.
CLASS_NAMES = ("skip", "uniform", "gather", "gather_2", "uniform_half", "gather_half")
SCATTER_BEYOND = 3  # tiles of velocity from which a tile scatters past the 7 x 7 (48 px)
PAIR_SPACING = 0.5  # px of a line's longest half-vector per pair of taps
HALF_RES_SPACING = 8.0  # px between a line's taps from which they read the half-size colour
QUAD = ((0, 0), (0, 1), (1, 0), (1, 1))  # (dy, dx) of a 2 x 2 block's pixels, row-major
MIXED_DEPTH = 0.5  # depth_extent: a pixel this far from its block's depth ...
MIXED_PX = 1.0  # ... or this far from its velocity makes a gather_half block mixed


def axis_gap(a, b) -> np.ndarray:
    """Angle codes between the axes of two directions, 0..HALF_TURN/2."""
    d = np.abs(np.asarray(a) - np.asarray(b)) % HALF_TURN
    return np.minimum(d, HALF_TURN - d)


def unpack(packed) -> np.ndarray:
    """(..., 2) codes (c_l, c_a) of a packed second velocity."""
    return np.stack([np.floor(packed / PACK), packed % PACK], -1)


def tile_minmax2(codes: np.ndarray) -> np.ndarray:
    """§17.7 step 2: (ceil(H/16), ceil(W/16), 4): per tile engine_unreal's longest velocity
    (c_l1, c_a1) and smallest length code, and the packed codes of its longest velocity whose
    axis lies more than AXIS_APART from the first's (0: none; the first in row-major order
    among equal lengths)."""
    first = tile_minmax(codes)
    h, w = codes.shape[:2]
    th, tw = first.shape[:2]
    second = np.zeros((th, tw, 2))
    for dy in range(TILE):
        for dx in range(TILE):
            ys, xs = np.arange(th) * TILE + dy, np.arange(tw) * TILE + dx
            inside = (ys < h)[:, None] & (xs < w)[None, :]
            c = codes[np.minimum(ys, h - 1)][:, np.minimum(xs, w - 1), :2]
            apart = axis_gap(c[..., 1], first[..., 1]) > AXIS_APART
            better = inside & apart & (c[..., 0] > second[..., 0])
            second = np.where(better[..., None], c, second)
    return np.concatenate([first, (second[..., 0] * PACK + second[..., 1])[..., None]], -1)


def far_tiles(tiles: np.ndarray, radius: float, directions: int) -> tuple[np.ndarray, np.ndarray]:
    """§17.7 step 3a, the scatter: for each tile D, over the velocities (each tile's first, and
    with two directions its second) of the tiles S outside D's 7 x 7 that reach it, the largest
    (c_l, c_a) by length code, then angle code ((-1, 0): none), and the smallest minimum of
    those tiles (inf: none). Only tiles with a velocity of SCATTER_BEYOND tiles or longer can
    reach past the 7 x 7."""
    th, tw = tiles.shape[:2]
    ty, tx = np.mgrid[0:th, 0:tw]
    key = np.full((th, tw), -1.0)
    shortest = np.full((th, tw), np.inf)
    for sy, sx in np.ndindex(th, tw):
        source = tiles[sy, sx]
        velocities = [source[:2]] + ([unpack(source[3])] if directions == 2 else [])
        for codes in velocities:
            if codes[0] / LENGTH_CODE_MAX * radius < SCATTER_BEYOND * TILE:
                continue
            offset = np.stack([tx - sx, ty - sy], -1)
            far = np.maximum(np.abs(tx - sx), np.abs(ty - sy)) > NEIGHBORHOOD_REACH
            hit = far & reaches(np.broadcast_to(codes, (th, tw, 2)), offset, radius)
            key = np.where(hit, np.maximum(key, codes[0] * ANGLE_CODES + codes[1]), key)
            shortest = np.where(hit, np.minimum(shortest, source[2]), shortest)
    codes = np.stack([np.floor(key / ANGLE_CODES), key % ANGLE_CODES], -1)
    return np.where((key < 0)[..., None], [-1.0, 0.0], codes), shortest


def neighbor_dilate2(
    tiles: np.ndarray, radius: float, directions: int, quality: int, half_res_gather: int
) -> np.ndarray:
    """§17.7 step 3: (tiles_h, tiles_w, 4): for each tile D, among the velocities of the
    7 x 7 tiles around it that reach it (each tile's first, and with two directions its
    second), the longest (c_l1, c_a1), replaced by the scatter's (far_tiles) where that is
    longer, with two directions the longest of the 7 x 7 whose axis lies more than AXIS_APART
    from it (packed, 0: none), and D's class."""
    th, tw = tiles.shape[:2]
    candidates = []  # (codes, reaches D) in scan order: tiles row-major, first before second
    shortest = np.full((th, tw), np.inf)
    for (ox, oy), inside, source in neighborhood_sources(tiles):
        velocities = [source[..., :2]] + ([unpack(source[..., 3])] if directions == 2 else [])
        met = np.zeros((th, tw), bool)
        for codes in velocities:
            hit = inside & reaches(codes, (-ox, -oy), radius)
            candidates.append((codes, hit))
            met |= hit
        shortest = np.where(met, np.minimum(shortest, source[..., 2]), shortest)
    longest = np.zeros((th, tw, 2))
    longest[..., 0] = -1
    for codes, hit in candidates:
        better = hit & (codes[..., 0] > longest[..., 0])
        longest = np.where(better[..., None], codes, longest)
    far, far_min = far_tiles(tiles, radius, directions)
    longest = np.where((far[..., 0] > longest[..., 0])[..., None], far, longest)
    shortest = np.minimum(shortest, far_min)
    second = np.zeros((th, tw, 2))
    for codes, hit in candidates if directions == 2 else []:
        apart = axis_gap(codes[..., 1], longest[..., 1]) > AXIS_APART
        better = hit & apart & (codes[..., 0] > second[..., 0])
        second = np.where(better[..., None], codes, second)
    kind = np.where(5 * shortest > 2 * longest[..., 0], UNIFORM, GATHER)
    two = second[..., 0] / LENGTH_CODE_MAX * radius >= SKIP_BELOW
    kind = np.where(two, GATHER_2, kind)
    length = longest[..., 0] / LENGTH_CODE_MAX * radius
    kind = np.where(length < SKIP_BELOW, SKIP, kind)
    half = line_from_half(longest[..., 0], radius, quality, half_res_gather)
    kind = np.where(half & ((kind == UNIFORM) | (kind == GATHER)), kind + UNIFORM_HALF - 1, kind)
    packed = second[..., 0] * PACK + second[..., 1]
    return np.stack([longest[..., 0], longest[..., 1], packed, kind], -1)


def half_color(color: np.ndarray) -> np.ndarray:
    """§17.7 step 4: (ceil(H/2), ceil(W/2), C): the mean of each 2 x 2 block, the last row and
    column repeated where the size is odd."""
    color = sanitize_color(color)
    h, w = color.shape[:2]
    ys, xs = np.arange(-(-h // 2)) * 2, np.arange(-(-w // 2)) * 2
    total = 0
    for dy in (0, 1):
        for dx in (0, 1):
            total = total + color[np.minimum(ys + dy, h - 1)][:, np.minimum(xs + dx, w - 1)]
    return total / 4


def line_pairs(length_code, radius: float, quality: int) -> np.ndarray:
    """Pairs of taps along a line whose longest half-vector has length code `length_code`: one
    per PAIR_SPACING px, at least 1, at most the quality level's samples / 2."""
    length = length_code / LENGTH_CODE_MAX * radius
    most = SAMPLES_BY_QUALITY[quality] // 2
    return np.clip(np.ceil(length / PAIR_SPACING), 1, most).astype(np.int64)


def line_from_half(length_code, radius: float, quality: int, half_res_gather: int) -> np.ndarray:
    """Whether a line's taps lie HALF_RES_SPACING px apart or more and read the half-size
    colour (with half_res_gather on)."""
    spacing = length_code / LENGTH_CODE_MAX * radius / line_pairs(length_code, radius, quality)
    return (half_res_gather == 1) & (spacing >= HALF_RES_SPACING)
