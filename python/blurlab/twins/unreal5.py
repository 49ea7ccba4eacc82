"""engine_unreal5, docs/spec.md §17.7, in NumPy float64: the motion blur of Unreal Engine 5 as
its console variables and talks describe it. One function per pass; the GPU passes
(shaders/passes/unreal5_*.glsl) must match them. The twin computes every class's path on
every pixel and keeps the one of the pixel's tile class, as a full dispatch of the classes
would; the GPU runs each class over its own tile list (docs/spec.md §9.3). Velocities and
depths are engine_unreal's 11:11:10 codes (§17.5 step 1); tiles compare integer codes, so the
GPU and this twin choose the same tiles, velocities and classes.
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
    neighborhood_sources,
    reaches,
    tile_minmax,
    velocity_flatten,
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
    w = color.shape[1]
    radius = max_radius_px(w, max_blur)
    codes = velocity_flatten(depth, motion, exposure=exposure, radius=radius)
    tiles = neighbor_dilate2(tile_minmax2(codes), radius, directions, quality, half_res_gather)
    half = half_color(color)
    lines = _Lines(color, half, codes, radius, quality, half_res_gather, depth_extent, seed)
    y, x = np.mgrid[0 : color.shape[0], 0:w]
    kind = tiles[y // TILE, x // TILE, 3]
    full = lines.full_res(tiles)
    result = np.where((kind == SKIP)[..., None], color, full)
    if (kind >= UNIFORM_HALF).any():
        result = np.where((kind >= UNIFORM_HALF)[..., None], lines.half_res(tiles, full), result)
    return result


class _Lines:
    """§17.7 step 5's lines of taps on one frame: its colours, velocity codes and settings."""

    def __init__(self, color, half, codes, radius, quality, half_res_gather, extent, seed):
        self.color, self.half, self.radius, self.quality = color, half, radius, quality
        self.half_res_gather, self.extent, self.seed = half_res_gather, extent, seed
        self.own = decode_polar(codes[..., :2], radius)
        self.z, self.speed = codes[..., 2], codes[..., 0]

    def line(self, line_codes, y, x, center, uniform):
        """(share, coverage) of the line of `line_codes` through `center` for the pixels
        (y, x) whose blur and depth weigh its taps."""
        vmax = decode_polar(line_codes, self.radius)
        angle = line_codes[..., 1] * (2 * np.pi / ANGLE_CODES)
        axis = np.stack([np.cos(angle), np.sin(angle)], -1)
        pairs = line_pairs(line_codes[..., 0], self.radius, self.quality)
        from_half = line_from_half(
            line_codes[..., 0], self.radius, self.quality, self.half_res_gather
        )

        def along(py, px):  # blur radii along this line
            return np.abs((self.own[py, px] * axis).sum(-1))

        def read(py, px):
            return np.where(from_half[..., None], self.half[py // 2, px // 2], self.color[py, px])

        j = rand(x, y, self.seed)
        return mirrored_pairs(
            self.color,
            self.z,
            self.speed,
            vmax,
            j,
            pairs,
            self.extent,
            along,
            uniform,
            read,
            own=(y, x),
            center=center,
        )

    def full_res(self, tiles) -> np.ndarray:
        """Classes uniform, gather and gather_2 at every pixel."""
        h, w = self.z.shape
        y, x = np.mgrid[0:h, 0:w]
        tile = tiles[y // TILE, x // TILE]
        kind = tile[..., 3]
        center = np.stack([x, y], -1) + 0.5
        share, coverage = self.line(tile[..., :2], y, x, center, kind == UNIFORM)
        second, covered = self.line(unpack(tile[..., 2]), y, x, center, None)
        two = kind == GATHER_2
        share = share + np.where(two[..., None], second, 0.0)
        coverage = coverage + np.where(two, covered, 0.0)
        return _composite(share, coverage, self.color)

    def half_res(self, tiles, full) -> np.ndarray:
        """Classes uniform_half and gather_half at every pixel: the line through each 2 x 2
        block's corner, weighed as the block's fastest pixel (the first in row-major order
        among equal length codes), then each pixel's bilinear mean of the blocks of its own
        tile, composited with its C; in a gather_half block whose pixels differ from that
        pixel by MIXED_DEPTH·extent in depth or MIXED_PX in velocity, `full` (full_res)."""
        h, w = self.z.shape
        hh, hw = -(-h // 2), -(-w // 2)
        by, bx = np.mgrid[0:hh, 0:hw]
        tile = tiles[by // (TILE // 2), bx // (TILE // 2)]
        center = np.stack([2 * bx, 2 * by], -1) + 1.0
        uniform = tile[..., 3] == UNIFORM_HALF
        corners = [
            (np.minimum(2 * by + dy, h - 1), np.minimum(2 * bx + dx, w - 1)) for dy, dx in QUAD
        ]
        y0, x0 = corners[0]
        for py, px in corners[1:]:
            faster = self.speed[py, px] > self.speed[y0, x0]
            y0, x0 = np.where(faster, py, y0), np.where(faster, px, x0)
        share, coverage = self.line(tile[..., :2], y0, x0, center, uniform)
        mixed = np.zeros((hh, hw), bool)
        for py, px in corners:
            apart = np.linalg.norm(self.own[py, px] - self.own[y0, x0], axis=-1) >= MIXED_PX
            with np.errstate(invalid="ignore"):  # two pixels at +inf depth: not apart
                deeper = np.abs(self.z[py, px] - self.z[y0, x0]) >= MIXED_DEPTH * self.extent
            mixed |= apart | deeper
        mixed &= tile[..., 3] == GATHER_HALF
        y, x = np.mgrid[0:h, 0:w]
        per_pixel = []
        for rows, half_size in ((y, hh), (x, hw)):
            first = rows // TILE * (TILE // 2)
            last = np.minimum(first + TILE // 2 - 1, half_size - 1)
            u = rows * 0.5 - 0.25
            below = np.floor(u).astype(np.int64)
            f = u - below
            per_pixel.append((np.clip(below, first, last), np.clip(below + 1, first, last), f))
        (ya, yb, fy), (xa, xb, fx) = per_pixel

        def bilinear(values):
            wy, wx = (fy, fx) if values.ndim == 2 else (fy[..., None], fx[..., None])
            top = (1 - wx) * values[ya, xa] + wx * values[ya, xb]
            bottom = (1 - wx) * values[yb, xa] + wx * values[yb, xb]
            return (1 - wy) * top + wy * bottom

        blended = _composite(bilinear(share), bilinear(coverage), self.color)
        return np.where(mixed[y // 2, x // 2][..., None], full, blended)


def _composite(share, coverage, color) -> np.ndarray:
    """The taps' share, the coverage they leave kept for C(X), normalised where they cover
    more than the pixel."""
    return (share + np.maximum(1 - coverage, 0)[..., None] * color) / np.maximum(coverage, 1)[
        ..., None
    ]
