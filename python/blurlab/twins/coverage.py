"""gather_coverage's parts, docs/spec.md §17.6, in NumPy float64: the sizes relative to the
height, the trails' reach and weights, the tap layout, each pixel's tile lines and tap plan
(§17.6.1) and the still blocks (§17.6.2), which studies and benchmarks read too. Tiles:
engine_eevee's flatten and dilation (blurlab.twins.eevee). The whole filter is
methods/gather_coverage/twin.py; its GPU pass, methods/gather_coverage/gather.glsl.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .eevee import clamp_length, dilated_half_motions, lookup_tile

JITTER_SALTS = (0x510E527F, 0x9B05688C)  # methods/gather_coverage/gather.glsl
MOVING = 1.0  # px: a half-motion at least this long moves; shorter ones count as still
SMALLEST_TILE = 8  # px
ACROSS = 2.0  # px
ACROSS_SHARE = 0.05  # ... plus this share of the trail's length
MOVING_DEPTH = 10.0  # soft depth extent, multiple of X's depth, where X moves
DISPLAY_WHITE = 1.0  # colour above it is the hot share, gathered only where a pixel crosses X
# The tile passes compare lengths in steps of 1/16 px (eevee.pick_key): on a turning object
# many tiles move almost equally fast, and exact lengths, rounded differently by each device,
# picked differently on the GPU and here (moire: whole tiles apart, 139 of 14400 pixels).
TILE_LENGTH_STEPS = 16.0
# The jittered lookup (eevee.lookup_tile) moves a pixel up to 1/4 tile each way, so each tile's
# reach is widened by as much: a pixel at a tile's edge reads its neighbour, which must hold
# the motions passing that pixel (a streak one pixel from a tile's edge went missing).
JITTER_REACH = 0.25  # tiles


def tile_size(height: int, percent: float) -> int:
    """§17.6: the tile side, `percent` of the image height rounded, at least SMALLEST_TILE."""
    return max(SMALLEST_TILE, round(height * percent / 100))


def max_blur_px(height: int, percent: float) -> float:
    """§17.6: the longest half-motion, `percent` of the image height, in pixels."""
    return height * percent / 100


def trail_reaches(d: np.ndarray, v: np.ndarray, bend: np.ndarray) -> np.ndarray:
    """§17.6: how far (0..1) the trail of a pixel at offset d from X, moving by v over the
    half-shutter towards X, passes over X. The trail is the parabola through the pixel's three
    positions (shutter open, centre, close): d = τ·v + τ(1 − τ)·bend, τ in [0, 1], with
    bend = (next − prev)/2 of the pixel's half-motions (0 on a straight, even motion; a turning
    pixel's chord strays from its arc by up to |bend|/4). It reaches X fully up to |v| along v
    and within ACROSS + ACROSS_SHARE·|v| − 1 px across the parabola, each falling to 0 one
    pixel further. A still pixel (v = 0) reaches within ACROSS px."""
    return trail_weights(d, v, bend)[0]


def trail_weights(d: np.ndarray, v: np.ndarray, bend: np.ndarray):
    """§17.6: (trail_reaches, on_pixel) from one pass over the trail's geometry, as the GPU
    computes them together. on_pixel, the hot share's weight: the same reach along the trail,
    with the moving pixel's own width w across its trail (|û.x| + |û.y|, 1 to √2 px) as the
    tolerance, 1 within w/2 and 0 from w on; a still pixel reaches X only less than 1 px away."""
    length = np.linalg.norm(v, axis=-1)
    moving = length > 0
    unit = v / np.where(moving, length, 1.0)[..., None]
    dist = np.linalg.norm(d, axis=-1)
    along = np.where(moving, np.sum(d * unit, -1), dist)
    tau = np.clip(along / np.where(moving, length, 1.0), 0, 1)
    off_line = cross(d, unit) - tau * (1 - tau) * cross(bend, unit)
    across = np.where(moving, np.abs(off_line), dist)
    ahead = along > -0.5
    reach_along = np.clip(length + 1 - along, 0, 1) * ahead
    widest = np.where(moving, ACROSS + ACROSS_SHARE * length, ACROSS)
    width = np.where(moving, np.abs(unit[..., 0]) + np.abs(unit[..., 1]), 1.0)
    within_pixel = np.where(moving, np.clip(2 - 2 * across / width, 0, 1), 1.0)
    return reach_along * np.clip(widest - across, 0, 1), reach_along * within_pixel


def hot(color: np.ndarray) -> np.ndarray:
    """§17.6: the share of (H, W, C) colour above DISPLAY_WHITE in RGB, 0 in alpha."""
    excess = np.maximum(color - DISPLAY_WHITE, 0.0)
    if color.shape[-1] > 3:
        excess[..., 3:] = 0.0
    return excess


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The 2D cross product a.x·b.y − a.y·b.x: a's signed distance across unit vector b."""
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def family_overlap(line: np.ndarray, own: np.ndarray) -> np.ndarray:
    """§17.6: |cos| of the angle between the tile's line and X's own motion, 0 where X is
    still: the share of the two tap families that sample the same trails."""
    lt, lo = np.linalg.norm(line, axis=-1), np.linalg.norm(own, axis=-1)
    cos = np.sum(line * own, -1) / np.maximum(lt * lo, 1e-12)
    return np.where(lo < MOVING, 1.0, np.clip(cos, 0.0, 1.0))


def tap_layout(samples: int) -> list[tuple[int, int, int]]:
    """§17.6: (family, index in family, taps in family) of each of the `samples` taps of one
    side: even taps along the tile's line (family 0), odd ones along X's own motion (1)."""
    counts = ((samples + 1) // 2, samples // 2)
    return [(i % 2, i // 2, counts[i % 2]) for i in range(samples)]


def tap_offset(j, family: int, side: int):
    """§17.6: the jitter of a tap family, j shifted by 1/2 for the second family and by 1/4 on
    the next side, so that the families' and sides' taps interleave."""
    return np.mod(j + 0.5 * family + 0.25 * side, 1.0)


def tap_offset_along(line: np.ndarray, bend: np.ndarray, t) -> np.ndarray:
    """§17.6: a tap's offset from X at t in [0, 1) of a family's line: t·line, plus
    t(1 + t)·bend for X's own family, which then follows X's arc (the parabola through X's
    three positions: on the prev side its way on from the centre, on the next side its way
    back), where the pixels that crossed X lie when X turns; bend = 0 on the tile's line."""
    t = np.asarray(t, np.float64)[..., None]
    return line * t + bend * (t * (1 + t))


@dataclass(frozen=True)
class TapPlan:
    """§17.6.1: what each pixel of gather_coverage does before any tap reads a
    colour. `prev`, `next_`: the clamped half-motions; `lines`: the tile's line of each side;
    `taps`: (H, W) taps on each side (0 where the pixel exits early); `fast`: (H, W) bool, the
    pixels of the uniform-motion path; `half`: (H, W) bool, the pixels whose quad takes the
    half-resolution path; `dilated`: the dilated tile grid."""

    prev: np.ndarray
    next_: np.ndarray
    lines: tuple[np.ndarray, np.ndarray]
    taps: np.ndarray
    fast: np.ndarray
    half: np.ndarray
    dilated: np.ndarray

    def taps_per_pixel(self) -> np.ndarray:
        """(H, W) float: the taps a pixel reads over both sides (0 where it exits early); a
        quad on the half-resolution path shares its top-left pixel's among its four."""
        h, w = self.taps.shape
        y, x = np.mgrid[0:h, 0:w]
        shared = 2 * self.taps[quad_corner(y), quad_corner(x)] / 4
        return np.where(self.half, shared, 2.0 * self.taps)


QUAD = ((0, 0), (0, 1), (1, 0), (1, 1))  # (dy, dx) of a quad's pixels from its top-left


def quad_corner(i):
    """§17.6.1, the half-resolution path: the index of the top-left pixel of i's 2 x 2 quad."""
    return 2 * (np.asarray(i) // 2)


def tile_samples(longest, samples: int, tap_spacing: float) -> np.ndarray:
    """§17.6.1, per-tile sample counts: clamp(⌈longest / tap_spacing⌉, 2, samples) taps a side,
    longest the tile's longer line in px (float32, as the GPU holds it); `samples` everywhere
    where tap_spacing is 0."""
    longest = np.asarray(longest, np.float32)
    if tap_spacing <= 0:
        return np.full(longest.shape, samples, np.int64)
    wanted = np.ceil(longest / np.float32(tap_spacing)).astype(np.int64)
    return np.clip(wanted, 2, samples)


def moves_with_tile(owns, lines, tolerance: float) -> np.ndarray:
    """§17.6.1, the uniform-motion path: on both sides X's own trail lies within `tolerance` px of
    the tile's line (False everywhere where tolerance is 0)."""
    if tolerance <= 0:
        return np.zeros(owns[0].shape[:-1], bool)
    apart = (np.linalg.norm(own - line, axis=-1) for own, line in zip(owns, lines, strict=True))
    return np.maximum(*apart) <= tolerance


@dataclass(frozen=True)
class TileLines:
    """§17.6 step 3's start: `prev`, `next_` the clamped half-motions, `lines` the lines of each
    pixel's jittered tile, `longest` the longer's length, `dilated` the dilated tile grid."""

    prev: np.ndarray
    next_: np.ndarray
    lines: tuple[np.ndarray, np.ndarray]
    longest: np.ndarray
    dilated: np.ndarray


def tile_lines(
    motion_prev,
    motion_next,
    *,
    tile_percent: float,
    max_blur: float,
    exposure: float,
    seed: int,
    dilated: np.ndarray | None = None,
) -> TileLines:
    """§17.6 steps 1–3: each pixel's half-motions and its jittered tile's lines."""
    h, w = motion_prev.shape[:2]
    s = tile_size(h, tile_percent)
    reach_limit = max_blur_px(h, max_blur)
    prev, next_, dilated = dilated_half_motions(
        motion_prev, motion_next, exposure, s, reach_limit, dilated, TILE_LENGTH_STEPS, JITTER_REACH
    )
    y, x = np.mgrid[0:h, 0:w]
    ty, tx = lookup_tile(x, y, s, seed, dilated.shape[:2], JITTER_SALTS)
    lines = (
        clamp_length(dilated[ty, tx, :2], reach_limit),
        -clamp_length(dilated[ty, tx, 2:], reach_limit),
    )
    longest = np.maximum(*(np.linalg.norm(line, axis=-1) for line in lines))
    return TileLines(prev, next_, lines, longest, dilated)


BLOCK_CLASSES = ("still", "moving")  # the gather's lists of 16 px blocks (§17.6.2)
LIST_BLOCK = 16  # px


def still_blocks(dilated: np.ndarray, size, tile: int, reach_limit: float, early_exit: float):
    """§17.6.2: (blocks_h, blocks_w) class of each 16 px block of an image of `size` (H, W):
    0 (still) where every tile a pixel of the block may look up (its centre ± a quarter tile,
    one tile more each way) has both clamped lines shorter than early_exit, else 1 (moving)."""
    grid = dilated.shape[:2]
    longest = np.maximum(
        *(
            np.linalg.norm(clamp_length(dilated[..., k : k + 2], reach_limit), axis=-1)
            for k in (0, 2)
        )
    )
    rows, columns = -(-size[0] // LIST_BLOCK), -(-size[1] // LIST_BLOCK)
    classes = np.ones((rows, columns), np.int64)
    for b in np.ndindex(rows, columns):
        span = []
        for axis in (0, 1):
            low = b[axis] * LIST_BLOCK + 0.5 - 0.25 * tile
            high = min(b[axis] * LIST_BLOCK + LIST_BLOCK, size[axis]) - 1 + 0.5 + 0.25 * tile
            first = int(np.clip(np.floor(low / tile) - 1, 0, grid[axis] - 1))
            last = int(np.clip(np.floor(high / tile) + 1, 0, grid[axis] - 1))
            span.append(slice(first, last + 1))
        classes[b] = 0 if (longest[span[0], span[1]] < early_exit).all() else 1
    return classes


def plan_taps(
    tiles: TileLines,
    *,
    samples: int,
    tap_spacing: float,
    early_exit: float,
    uniform_tolerance: float,
    half_res_above: float,
) -> TapPlan:
    """§17.6.1: each pixel's taps a side and path (TapPlan) on `tiles`."""
    prev, next_, lines, longest = tiles.prev, tiles.next_, tiles.lines, tiles.longest
    h, w = longest.shape
    y, x = np.mgrid[0:h, 0:w]
    gathers = longest >= early_exit
    taps = np.where(gathers, tile_samples(longest, samples, tap_spacing), 0)
    fast = gathers & moves_with_tile((prev, -next_), lines, uniform_tolerance)
    half = np.zeros((h, w), bool)
    if half_res_above > 0:  # the corner's tile line and every half-motion of the quad long
        cy, cx = quad_corner(y), quad_corner(x)
        slower = np.minimum(np.linalg.norm(prev, axis=-1), np.linalg.norm(next_, axis=-1))
        quad_slowest = np.min(
            [slower[np.minimum(cy + dy, h - 1), np.minimum(cx + dx, w - 1)] for dy, dx in QUAD],
            axis=0,
        )
        half = (longest[cy, cx] > half_res_above) & (quad_slowest > half_res_above)
    return TapPlan(prev, next_, lines, taps, fast, half, tiles.dilated)


def tap_plan(
    motion_prev,
    motion_next,
    *,
    tile_percent: float,
    samples: int,
    max_blur: float,
    exposure: float,
    seed: int,
    tap_spacing: float,
    early_exit: float,
    uniform_tolerance: float,
    half_res_above: float,
    dilated: np.ndarray | None = None,
) -> TapPlan:
    """§17.6.1: each pixel's tile lines, taps a side and path (TapPlan), from the motion alone:
    plan_taps on tile_lines."""
    tiles = tile_lines(
        motion_prev,
        motion_next,
        tile_percent=tile_percent,
        max_blur=max_blur,
        exposure=exposure,
        seed=seed,
        dilated=dilated,
    )
    return plan_taps(
        tiles,
        samples=samples,
        tap_spacing=tap_spacing,
        early_exit=early_exit,
        uniform_tolerance=uniform_tolerance,
        half_res_above=half_res_above,
    )
