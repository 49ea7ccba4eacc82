"""engine_unreal's passes, docs/spec.md §17.5, in NumPy float64: the motion blur of Unreal
Engine 4 as its algorithm is described (Jimenez 2014, which it follows). One function per pass,
shared with engine_unreal5 (and the mirrored pairs with engine_jimenez2014); the GPU passes
(shaders/passes/unreal_velocity_flatten.glsl and the shaders of methods/engine_unreal/) must
match them. The whole filter is methods/engine_unreal/twin.py.

Velocities travel as polar 11-bit codes and depths as 10-bit floats (twins.polar_fixed_point).
Tiles compare length codes, exact integers, so the GPU and this twin choose the same tiles.
"""

from __future__ import annotations

import numpy as np

from .guertin2014 import mirror_pair, mirrored_taps
from .inputs import sanitize_depth, sanitize_motion
from .polar_fixed_point import LENGTH_CODE_MAX, decode_polar, float10, polar_codes
from .tile_reach import reach_widening, segment_meets_box

TILE = 16  # tile side, pixels
NEIGHBORHOOD_REACH = 3  # the 7 x 7 tiles around a tile
SKIP_BELOW = 0.5  # px: a tile whose longest reaching velocity is shorter keeps C
SKIP, FAST, SLOW = 0, 1, 2
CLASS_NAMES = ("skip", "fast", "slow")
SAMPLES_BY_QUALITY = {1: 4, 2: 6, 3: 8, 4: 16}  # r.MotionBlurQuality 1..4


def max_radius_px(width: int, max_blur: float) -> float:
    """R: the longest blur radius, Unreal's Max (max_blur % of the image width), pixels."""
    return max_blur / 100.0 * width


def velocity_flatten(depth, motion, *, exposure: float, radius: float) -> np.ndarray:
    """§17.5 step 1: (H, W, 3): the half-vector E·M/2 as polar codes (c_l, c_a), its length
    clamped to R by the length code, and the depth as a 10-bit float."""
    v = sanitize_motion(motion) * exposure / 2
    z = float10(sanitize_depth(depth))
    return np.concatenate([polar_codes(v, radius), z[..., None]], axis=-1)


def tile_minmax(codes: np.ndarray) -> np.ndarray:
    """§17.5 step 2: (ceil(H/16), ceil(W/16), 3): per tile the codes of its longest velocity
    (the first in row-major order among equal length codes) and its smallest length code."""
    h, w = codes.shape[:2]
    th, tw = -(-h // TILE), -(-w // TILE)
    longest = np.zeros((th, tw, 2))
    longest[..., 0] = -1
    shortest = np.full((th, tw), np.inf)
    for dy in range(TILE):
        for dx in range(TILE):
            ys, xs = np.arange(th) * TILE + dy, np.arange(tw) * TILE + dx
            inside = (ys < h)[:, None] & (xs < w)[None, :]
            c = codes[np.minimum(ys, h - 1)][:, np.minimum(xs, w - 1), :2]
            better = inside & (c[..., 0] > longest[..., 0])
            longest = np.where(better[..., None], c, longest)
            shortest = np.where(inside, np.minimum(shortest, c[..., 0]), shortest)
    return np.concatenate([longest, shortest[..., None]], axis=-1)


def reaches(tiles: np.ndarray, offset: tuple[int, int], radius: float) -> np.ndarray:
    """Whether each tile's longest velocity, as a segment from c - v to c + v through its center
    c (tile units), reaches the tile `offset` = (dx, dy) tiles away from it: whether the segment
    meets that tile's square widened by h + REACH_MARGIN (twins.tile_reach)."""
    v = decode_polar(tiles[..., :2], radius) / TILE
    widen = reach_widening(TILE)
    center = np.broadcast_to(0.5 - np.asarray(offset, np.float64), v.shape)
    return segment_meets_box(center - v, 2 * v, -widen, 1 + widen)


def classify(longest: np.ndarray, shortest: np.ndarray, radius: float) -> np.ndarray:
    """SKIP where the longest length is under SKIP_BELOW px, FAST where the shortest is more than
    0.4 times the longest (5·min > 2·max, exact in codes), else SLOW."""
    kind = np.where(5 * shortest > 2 * longest, FAST, SLOW)
    return np.where(longest / LENGTH_CODE_MAX * radius < SKIP_BELOW, SKIP, kind)


def neighborhood_sources(tiles: np.ndarray):
    """The scatter-as-gather scan of §17.5 step 3 and §17.7 step 3: for each offset (ox, oy) of
    the 7 x 7 around every tile D, in row-major order, the (tiles_h, tiles_w) mask of the D whose
    source tile D + (ox, oy) lies in the grid, and the (tiles_h, tiles_w, 4) source tiles (edges
    clamped where it does not)."""
    th, tw = tiles.shape[:2]
    ty, tx = np.mgrid[0:th, 0:tw]
    reach = NEIGHBORHOOD_REACH
    for oy in range(-reach, reach + 1):
        for ox in range(-reach, reach + 1):
            sy, sx = ty + oy, tx + ox
            inside = (sy >= 0) & (sy < th) & (sx >= 0) & (sx < tw)
            yield (ox, oy), inside, tiles[np.clip(sy, 0, th - 1), np.clip(sx, 0, tw - 1)]


def neighbor_dilate(tiles: np.ndarray, radius: float) -> np.ndarray:
    """§17.5 step 3: (tiles_h, tiles_w, 4): for each tile D, the codes of the longest velocity
    among the tiles of its 7 x 7 neighbourhood that reach it (the first in row-major order
    among equal length codes), their smallest length code, and D's class."""
    th, tw = tiles.shape[:2]
    longest = np.zeros((th, tw, 2))
    longest[..., 0] = -1
    shortest = np.full((th, tw), np.inf)
    for (ox, oy), inside, source in neighborhood_sources(tiles):
        valid = inside & reaches(source, (-ox, -oy), radius)
        better = valid & (source[..., 0] > longest[..., 0])
        longest = np.where(better[..., None], source[..., :2], longest)
        shortest = np.where(valid, np.minimum(shortest, source[..., 2]), shortest)
    kind = classify(longest[..., 0], shortest, radius)
    return np.concatenate([longest, shortest[..., None], kind[..., None]], axis=-1)


def spread(dist, length) -> np.ndarray:
    """1 where a blur of radius `length` reaches `dist` pixels, falling to 0 over its last
    pixel."""
    return np.clip(1.0 + length - dist, 0.0, 1.0)


def tap_weight(z_x, len_x, z_y, len_y, dist, depth_extent: float) -> np.ndarray:
    """A slow-path tap's weight: the soft depth split of whether X's blur or the tap's reaches
    it, at most 1."""
    with np.errstate(invalid="ignore"):
        d = np.where(z_y == z_x, 0.0, (z_y - z_x) / depth_extent)
    behind = np.clip(0.5 + d, 0.0, 1.0)
    return np.minimum(behind * spread(dist, len_x) + (1 - behind) * spread(dist, len_y), 1.0)


def mirrored_pairs(
    color,
    z,
    speed,
    vmax,
    j,
    pairs,
    extent: float,
    radius_at,
    uniform=None,
    color_at=None,
    own=None,
    center=None,
):
    """Jimenez 2014's taps (§17.5 step 4, §17.7, §17.8): `pairs` (an int or per pixel)
    mirrored pairs at X ± t·vmax, t = (i + j)/pairs, each tap weighted by tap_weight (depths z,
    extent `extent`, blur radii radius_at(rows, columns) of the pixels there), each pair by
    §7.2's mirror on z and `speed`; where `uniform` (an (H, W) bool) every tap weighs 1. A tap
    reads color_at(rows, columns), by default the color there. Returns (share, coverage): per
    pixel Σa·C/2P and Σa/2P. By default X runs over every pixel, its line through the pixel's
    center; `own` = (rows, columns) and `center` ((..., 2) x, y) give other points X instead,
    each weighed as the pixel `own` names (engine_unreal5's half-resolution blocks)."""
    h, w = z.shape
    y, x = np.mgrid[0:h, 0:w] if own is None else own
    if center is None:
        center = np.stack([x, y], -1) + 0.5
    pairs = np.broadcast_to(pairs, y.shape)
    radius_x = radius_at(y, x)
    z_x = z[y, x]
    total = np.zeros(y.shape + color.shape[2:])
    weight = np.zeros(y.shape)
    for i in range(int(pairs.max(initial=1))):
        t = (i + j) / pairs
        taps_at = []
        for py, px in mirrored_taps(center, t[..., None] * vmax, h, w):
            dist = np.hypot(px - x, py - y)
            a = tap_weight(z_x, radius_x, z[py, px], radius_at(py, px), dist, extent)
            c = color[py, px] if color_at is None else color_at(py, px)
            taps_at.append((a, py, px, c))
        (a1, py1, px1, c1), (a2, py2, px2, c2) = taps_at
        a1, a2 = mirror_pair(a1, a2, z[py1, px1], z[py2, px2], speed[py1, px1], speed[py2, px2])
        if uniform is not None:
            a1, a2 = np.where(uniform, 1.0, a1), np.where(uniform, 1.0, a2)
        a1, a2 = np.where(i < pairs, a1, 0.0), np.where(i < pairs, a2, 0.0)
        weight = weight + a1 + a2
        total = total + a1[..., None] * c1 + a2[..., None] * c2
    n = 2 * pairs
    return total / n[..., None], weight / n


def mirrored_pairs_blur(color, z, length, vmax, j, pairs: int, extent: float, uniform=None):
    """The pairs of `mirrored_pairs` along vmax, blur radii and speeds `length`, and the
    weight the taps leave kept for C(X): Σa·C/2P + (1 − Σa/2P)·C(X)."""
    share, coverage = mirrored_pairs(
        color, z, length, vmax, j, pairs, extent, lambda py, px: length[py, px], uniform
    )
    return share + (1 - coverage)[..., None] * color
