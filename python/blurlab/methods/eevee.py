"""EEVEE's tile passes (docs/spec.md §17.2 steps 1-2), shared by engine_eevee (its folder,
python/blurlab/methods/engine_eevee/, has the gather) and gather_coverage: the two-sided motion
of §17.1 as a texture, tile flatten (shaders/passes/eevee_tile_flatten.glsl) and dilation
along each tile's motion (eevee_tile_dilate.glsl; by scatter, reach_keys_clear.glsl and
eevee_tile_resolve.glsl), with the layouts of their work groups. NumPy twins:
blurlab.twins.eevee.
"""

from __future__ import annotations

import weakref
from typing import NamedTuple

import numpy as np

from ..core.context import Context
from ..core.frame import Frame
from ..core.gl import Texture
from ..twins import eevee as twin
from .core import Pass, PassRunner, frame_textures
from .tile_filter import TILE_FILTER_PARAMS
from .variants import PassVariants

# The parameter the tile passes take (the flatten scales motion by exposure): a method that runs
# them declares it among its own params; a call of dilated_tiles outside a method passes these.
PARAMS = {"exposure": TILE_FILTER_PARAMS["exposure"]}
# Tile size and limit come as uniforms in pixels (dilated_tiles): gather_coverage runs the same
# passes with sizes of its own.
FLATTEN = Pass("tile_flatten", "passes/eevee_tile_flatten.glsl", ("exposure",))
DILATE = Pass("tile_dilate", "passes/eevee_tile_dilate.glsl")
CLEAR_KEYS = Pass("reach_keys_clear", "passes/reach_keys_clear.glsl")
RESOLVE = Pass("tile_resolve", "passes/eevee_tile_resolve.glsl")

# The layouts of the tile passes' work group per tile (shaders/common/tile_pick.glsl): the
# #defines of each. All give the same bits; `blurlab bench layouts` times them.
TILE_PICK_VARIANTS = {
    "grid_16x16": {},
    "rows_64": {"TILE_PICK_THREADS": 64},
    "rows_128": {"TILE_PICK_THREADS": 128},
    "rows_32_subgroup": {"TILE_PICK_THREADS": 32, "TILE_PICK_SUBGROUP": 1},
    "rows_64_subgroup": {"TILE_PICK_THREADS": 64, "TILE_PICK_SUBGROUP": 1},
    "rows_128_subgroup": {"TILE_PICK_THREADS": 128, "TILE_PICK_SUBGROUP": 1},
    "rows_256_subgroup": {"TILE_PICK_THREADS": 256, "TILE_PICK_SUBGROUP": 1},
}
# rows_64 measured fastest on the H100 at 1080p where its clocks held (teapot_pass: flatten +
# dilate 0.044 ms against grid_16x16's 0.056, rows_64_subgroup's 0.049), and second to
# rows_64_subgroup (0.0648 against 0.0667) in the 15-scene medians of the same run, whose later
# scenes ran slow; it needs no subgroup extension (the layouts benchmark, 2026-11-24).
TILE_PICK_LAYOUT = PassVariants("tile pick", TILE_PICK_VARIANTS, "rows_64")

# How the dilation runs where lengths compare in steps (gather_coverage; docs/spec.md §17.6):
# each tile gathers from every tile within reach (passes/eevee_tile_dilate.glsl, about 600
# candidates a tile at 1080p), or the flatten pass scatters each tile's reach by atomic max on
# 32-bit keys and a small pass resolves them (EEVEE's own way; the same bits), or the gather
# resolves the keys itself (GATHER_READS_KEYS in methods/gather_coverage/gather.glsl: one pass
# fewer, a dependent read more a pixel; the keys, not the dilated tiles, come back as a buffer). The
# keys hold a 14-bit tile index (shaders/common/reach_keys.glsl), so larger grids gather, as
# engine_eevee always does: its exact lengths do not fit a key. On the H100 at 1080p the
# scatter_in_gather layout is the fastest of the three, and the 15-scene medians rank them the
# same way (`blurlab bench layouts` times each; docs/performance.md).
DILATION_VARIANTS = {
    "gather": {},
    "scatter": {"SCATTER_DILATION": 1},
    "scatter_in_gather": {"SCATTER_DILATION": 1, "GATHER_READS_KEYS": 1},
}
DILATION_LAYOUT = PassVariants("tile dilation", DILATION_VARIANTS, "scatter_in_gather")
SCATTER_MAX_TILES = 2**twin.REACH_INDEX_BITS  # the tiles a key's index can name


def motion_sides_texture(ctx: Context, frame: Frame):
    """The frame's two-sided motion (§17.1) as one RGBA texture of `ctx`: the rendered one where
    the frame came from this context, uploaded (once per frame) otherwise."""
    texture = frame.textures.get("motion_sides")
    if texture is not None and texture.context is ctx:
        return texture
    if frame.sides_derived:  # f·M and (1 − f)·M, made on the GPU from the motion texture
        motion = frame_textures(ctx, frame)["motion"]
        texture = ctx.pooled(motion.shape[:2] + (4,))
        f = frame.instant_fraction
        ctx.shader_pass("passes/motion_sides.comp").run(
            {"motion": motion},
            {"motion_sides": texture},
            {"share_prev": np.float32(f), "share_next": np.float32(1.0 - f)},
        )
        weakref.finalize(frame, ctx.recycle, texture)
    else:
        texture = ctx.upload(np.concatenate([frame.motion_prev, frame.motion_next], axis=-1))
    frame.textures["motion_sides"] = texture
    return texture


def tile_groups(ctx: Context) -> bool:
    """Whether the tile flatten and dilation run a work group per tile (its threads share the
    tile's pixels or sources, then reduce) rather than one thread per tile: on a GPU one thread
    per tile leaves it mostly idle (about 2000 threads at 1080p). llvmpipe runs a group's
    threads as SIMD lanes and its barriers are costly: there groups took 4 to 34 times as long
    (measured at 640 x 360; docs/performance.md), so it keeps one thread per tile."""
    return not ctx.software


class TileGrids(NamedTuple):
    """What dilated_tiles makes: the frame's two-sided motion texture, the flattened tiles, and
    either the dilated tiles or (DILATION_LAYOUT scatter_in_gather) the keys that name them,
    for the gather to resolve (the other None)."""

    sides: Texture
    tiles: Texture
    dilated: Texture | None
    keys: Texture | None


def dilated_tiles(
    ctx: Context,
    frame: Frame,
    timings: dict,
    params: dict,
    values: dict,
    size,
    tile_size,
    max_blur,
    group_per_tile: bool | None = None,
    length_steps: float = 0.0,
    jitter_reach: float = 0.0,
):
    """§17.2 steps 1-2 on the frame's two-sided motion for an image of `size` (H, W): tile
    flatten and dilation at `tile_size` px and `max_blur` px (a method's params and values give
    the exposure). `group_per_tile`: both passes run a work group per tile (laid out as
    TILE_PICK_LAYOUT says), else one thread per tile (same bits either way); None: as
    tile_groups(ctx) says. `length_steps`: lengths compare as twins.eevee.pick_key says (0:
    exactly, as EEVEE does); with steps the dilation runs as DILATION_LAYOUT says.
    `jitter_reach`: tiles added to each reach (twins.eevee.tile_dilate; 0 for EEVEE's)."""
    passes = PassRunner(ctx, params, values, timings)
    height, width = size
    grid = (-(-height // tile_size), -(-width // tile_size), 4)
    tiles = ctx.pooled(grid)
    sides = motion_sides_texture(ctx, frame)
    if group_per_tile is None:
        group_per_tile = tile_groups(ctx)
    sized = {"tile_size": tile_size, "length_steps": length_steps}
    # common/group_pick.glsl's mode is a #define; the layout applies to a group per tile only.
    layout = {"GROUP_PER_TILE": int(group_per_tile)}
    if group_per_tile:
        layout.update(TILE_PICK_LAYOUT.defines())
    scatter = DILATION_LAYOUT.defines()
    if not (scatter and length_steps > 0 and grid[0] * grid[1] <= SCATTER_MAX_TILES):
        scatter = {}
    flattened = {"tiles": tiles}
    if scatter:  # the flatten also offers each tile's reach to the keys
        flattened["reach_keys"] = ctx.pooled((2 * grid[0], grid[1]), "uint32")  # prev above next
        passes.run(CLEAR_KEYS, {}, {"reach_keys": flattened["reach_keys"]})
    passes.run(
        FLATTEN,
        {"motion_sides": sides},
        flattened,
        uniforms={**sized, "max_blur": max_blur, "reach_jitter": jitter_reach}
        if scatter
        else sized,
        defines={**layout, **scatter},
        group_per_texel=group_per_tile,
    )
    if "GATHER_READS_KEYS" in scatter:
        return TileGrids(sides, tiles, None, flattened["reach_keys"])
    dilated = ctx.pooled(grid)
    if scatter:
        passes.run(RESOLVE, flattened, {"dilated": dilated})
        ctx.recycle(flattened["reach_keys"])
        return TileGrids(sides, tiles, dilated, None)
    passes.run(
        DILATE,
        {"tiles": tiles},
        {"dilated": dilated},
        uniforms={**sized, "max_blur": max_blur, "reach_jitter": jitter_reach},
        defines=layout,
        group_per_texel=group_per_tile,
    )
    return TileGrids(sides, tiles, dilated, None)
