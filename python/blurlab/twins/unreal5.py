"""engine_unreal5, docs/spec.md §17.7, in NumPy float64: the motion blur of Unreal Engine 5 as
its console variables and talks describe it. One function per pass; the GPU passes
(shaders/passes/unreal5_*.glsl) must match them. Velocities and depths are engine_unreal's
11:11:10 codes (§17.5 step 1); tiles compare integer codes, so the GPU and this twin choose the
same tiles, velocities and classes.
"""

from __future__ import annotations

import numpy as np

from .hashing import rand
from .inputs import sanitize_color
from .polar_fixed_point import ANGLE_CODES, LENGTH_CODE_MAX, decode_polar
from .unreal import (
    NEIGHBORHOOD_REACH,
    SAMPLES_BY_QUALITY,
    SKIP_BELOW,
    TILE,
    max_radius_px,
    mirrored_pairs,
    reaches,
    tile_minmax,
    velocity_flatten,
)

AXIS_APART = 256  # angle codes (45°): two velocities whose axes differ more are two directions
HALF_TURN = ANGLE_CODES // 2  # v and -v blur along the same axis
PACK = ANGLE_CODES  # a second velocity travels as c_l·PACK + c_a, exact in float32
SKIP, UNIFORM, GATHER, GATHER_2 = 0, 1, 2, 3
CLASS_NAMES = ("skip", "uniform", "gather", "gather_2")
PAIR_SPACING = 0.5  # px of a line's longest half-vector per pair of taps
HALF_RES_SPACING = 8.0  # px between a line's taps from which they read the half-size colour


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


def neighbor_dilate2(tiles: np.ndarray, radius: float, directions: int) -> np.ndarray:
    """§17.7 step 3: (tiles_h, tiles_w, 4): for each tile D, among the velocities of the
    7 x 7 tiles around it that reach it (each tile's first, and with two directions its
    second), the longest (c_l1, c_a1), with two directions the longest whose axis lies more
    than AXIS_APART from it (packed, 0: none), and D's class."""
    th, tw = tiles.shape[:2]
    ty, tx = np.mgrid[0:th, 0:tw]
    candidates = []  # (codes, reaches D) in scan order: tiles row-major, first before second
    shortest = np.full((th, tw), np.inf)
    reach = NEIGHBORHOOD_REACH
    for oy in range(-reach, reach + 1):
        for ox in range(-reach, reach + 1):
            sy, sx = ty + oy, tx + ox
            valid = (sy >= 0) & (sy < th) & (sx >= 0) & (sx < tw)
            source = tiles[np.clip(sy, 0, th - 1), np.clip(sx, 0, tw - 1)]
            velocities = [source[..., :2]] + ([unpack(source[..., 3])] if directions == 2 else [])
            met = np.zeros((th, tw), bool)
            for codes in velocities:
                hit = valid & reaches(codes, (-ox, -oy), radius)
                candidates.append((codes, hit))
                met |= hit
            shortest = np.where(met, np.minimum(shortest, source[..., 2]), shortest)
    longest = np.zeros((th, tw, 2))
    longest[..., 0] = -1
    for codes, hit in candidates:
        better = hit & (codes[..., 0] > longest[..., 0])
        longest = np.where(better[..., None], codes, longest)
    second = np.zeros((th, tw, 2))
    for codes, hit in candidates if directions == 2 else []:
        apart = axis_gap(codes[..., 1], longest[..., 1]) > AXIS_APART
        better = hit & apart & (codes[..., 0] > second[..., 0])
        second = np.where(better[..., None], codes, second)
    kind = np.where(5 * shortest > 2 * longest[..., 0], UNIFORM, GATHER)
    two = second[..., 0] / LENGTH_CODE_MAX * radius >= SKIP_BELOW
    kind = np.where(two, GATHER_2, kind)
    kind = np.where(longest[..., 0] / LENGTH_CODE_MAX * radius < SKIP_BELOW, SKIP, kind)
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


def engine_unreal5(
    color,
    depth,
    motion,
    *,
    quality: int,
    max_blur: float,
    directions: int,
    half_res_gather: int,
    depth_extent: float,
    exposure: float,
    seed: int,
) -> np.ndarray:
    """§17.7 step 5: (H, W, C) float64 blurred color."""
    color = sanitize_color(color)
    h, w = color.shape[:2]
    radius = max_radius_px(w, max_blur)
    codes = velocity_flatten(depth, motion, exposure=exposure, radius=radius)
    neighbors = neighbor_dilate2(tile_minmax2(codes), radius, directions)
    half = half_color(color)
    y, x = np.mgrid[0:h, 0:w]
    tile = neighbors[y // TILE, x // TILE]
    kind = tile[..., 3]
    own = decode_polar(codes[..., :2], radius)
    z = codes[..., 2]
    speed = codes[..., 0]
    j = rand(x, y, seed)
    lines = [(tile[..., :2], kind != SKIP), (unpack(tile[..., 2]), kind == GATHER_2)]
    shares, coverage = np.zeros_like(color), np.zeros((h, w))
    for line_codes, on in lines:
        vmax = decode_polar(line_codes, radius)
        angle = line_codes[..., 1] * (2 * np.pi / ANGLE_CODES)
        axis = np.stack([np.cos(angle), np.sin(angle)], -1)
        pairs = line_pairs(line_codes[..., 0], radius, quality)
        spacing = line_codes[..., 0] / LENGTH_CODE_MAX * radius / pairs
        from_half = (half_res_gather == 1) & (spacing >= HALF_RES_SPACING)

        def along(py, px, axis=axis):  # blur radii along this line
            return np.abs((own[py, px] * axis).sum(-1))

        def read(py, px, from_half=from_half):
            return np.where(from_half[..., None], half[py // 2, px // 2], color[py, px])

        share, covered = mirrored_pairs(
            color, z, speed, vmax, j, pairs, depth_extent, along, kind == UNIFORM, read
        )
        shares = shares + np.where(on[..., None], share, 0.0)
        coverage = coverage + np.where(on, covered, 0.0)
    blurred = (shares + np.maximum(1 - coverage, 0)[..., None] * color) / np.maximum(coverage, 1)[
        ..., None
    ]
    return np.where((kind == SKIP)[..., None], color, blurred)
