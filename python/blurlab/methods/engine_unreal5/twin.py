"""engine_unreal5, docs/spec.md §17.7, in NumPy float64: Unreal Engine 5's motion blur as its
console variables and talks describe it, the whole filter. The twin computes every class's path
on every pixel and keeps the one of the pixel's tile class, as a full dispatch of the classes
would; the GPU runs each class over its own tile list (docs/spec.md §9.3). The passes' twins
are blurlab.twins.unreal5 (and blurlab.twins.unreal, engine_unreal's, for the velocity
flatten); the GPU passes are the shaders beside this file.
"""

from __future__ import annotations

import numpy as np

from ...twins.hashing import rand
from ...twins.inputs import sanitize_color
from ...twins.polar_fixed_point import ANGLE_CODES, decode_polar
from ...twins.unreal import TILE, max_radius_px, mirrored_pairs, velocity_flatten
from ...twins.unreal5 import (
    GATHER_2,
    GATHER_HALF,
    MIXED_DEPTH,
    MIXED_PX,
    QUAD,
    SKIP,
    UNIFORM,
    UNIFORM_HALF,
    half_color,
    line_from_half,
    line_pairs,
    neighbor_dilate2,
    tile_minmax2,
    unpack,
)


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
