"""The shared core of the tile-based reconstruction filters (docs/spec.md §3): their common
parameters, TileMax → NeighborMax, and the filter pipeline that ends in a method's own
reconstruct pass. reconstruct_mcguire2012, reconstruct_guertin2014 and reconstruct_urho3d are
built on it; the tile classification of mcguire2012 plugs into its last step.
"""

from __future__ import annotations

from collections.abc import Callable

from .. import _core
from ..context import Context, Timing
from ..frame import Frame
from . import classification
from .core import FLOAT32_MAX, PARAM_SCALE_MAX, SEED, Param, timed


def depth_range_soft_z(frame: Frame) -> float:
    """docs/spec.md §3 default soft_z: 1 % of the frame's finite depth range."""
    if frame.depth_range is None:
        return 0.01
    near, far = frame.depth_range
    span = far - near
    return 0.01 * (span if span > 0 else max(abs(far), 1.0))


# docs/spec.md §3's parameters, shared by every tile-based filter.
TILE_FILTER_PARAMS = {
    "k": Param(20, int, "tile size = largest blur radius, pixels", 1, 256),
    "samples": Param(15, int, "samples S per pixel", 1, 256),
    "soft_z": Param(
        depth_range_soft_z, float, "soft depth extent, depth units", 0, FLOAT32_MAX, True
    ),
    "exposure": Param(1.0, float, "exposure E, fraction of the shutter", 0, PARAM_SCALE_MAX),
    "seed": SEED,
}
# The engines' refinements (docs/guertin2014.md "Options"), off by default so that docs/spec.md
# §3.4 holds; mcguire2012 and guertin2014 offer them.
FILTER_OPTIONS = {
    "jitter_tiles": Param(0, int, "1: jittered NeighborMax lookup against tile blockiness", 0, 1),
    "adaptive_samples": Param(0, int, "1: S scaled with the neighborhood's motion length", 0, 1),
    "early_exit": Param(0.0, float, "pixels whose neighborhood moves < this many px keep C", 0),
}

# The sweep grid every filter shares: each option gets one point beside the default
# configuration instead of multiplying the k × S product.
OPTIONS_AT_DEFAULT = [
    {"k": [20], "samples": [15], "jitter_tiles": [1]},
    {"k": [20], "samples": [15], "adaptive_samples": [1]},
    {"k": [20], "samples": [15], "early_exit": [2.0]},
]


def filter_params(values: dict, params=None):
    """The C++ parameter struct of the filter passes from validated values."""
    p = params if params is not None else _core.McGuire2012Params()
    for key in ("k", "samples", "soft_z", "exposure", "seed"):
        setattr(p, key, values[key])
    for key in FILTER_OPTIONS:
        if key in values:
            setattr(p, key, values[key])
    return p


def tile_passes(
    ctx: Context, motion, params, backend: str, diagonal_reach=False, with_bounds=False
):
    """TileMax (§3.2) and NeighborMax (§3.3, or the direction-keeping dilation of
    docs/guertin2014.md): (tiles, neighbors, timings, bounds). `with_bounds` has TileMax also
    write each tile's motion bounds for classification (docs/classify_and_steps.md)."""
    height, width = motion.shape[:2]
    grid = (-(-height // params.k), -(-width // params.k), 2)
    tiles, neighbors = ctx.pooled(grid), ctx.pooled(grid)
    tile_pass = ctx.cached("tile_max", lambda: _core.TileMaxPass(ctx.native))
    neighbor_pass = ctx.cached("neighbor_max", lambda: _core.NeighborMaxPass(ctx.native))
    timings: dict[str, Timing] = {}
    bounds = []
    if with_bounds:

        def run_tile_max():
            bounds.append(
                classification.tile_max_with_bounds(ctx, tile_pass, motion, tiles, params)
            )
    else:

        def run_tile_max():
            tile_pass.run(motion.native, tiles.native, params, backend)

    timed(ctx, timings, "tile_max", run_tile_max)
    timed(
        ctx,
        timings,
        "neighbor_max",
        lambda: neighbor_pass.run(tiles.native, neighbors.native, backend, diagonal_reach),
    )
    return tiles, neighbors, timings, (bounds[0] if bounds else None)


def run_filter(name: str, pass_type, make_params: Callable, diagonal_reach: bool):
    """TileMax → NeighborMax → the reconstruct pass `name` (docs/spec.md §3, docs/guertin2014.md),
    the last one tile class by tile class where the method offers classify=True."""

    def run(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
        params = make_params(values)
        classified = values.get("classify", False)
        if classified:
            classification.check_request(name, values, backend, FILTER_OPTIONS)
        tiles, neighbors, timings, bounds = tile_passes(
            ctx, inputs["motion"], params, backend, diagonal_reach, classified
        )
        result = ctx.pooled(inputs["color"].shape[:2] + (4,))
        reconstruct = ctx.cached(name, lambda: pass_type(ctx.native))

        def run_reconstruct():
            reconstruct.run(
                inputs["color"].native,
                inputs["depth"].native,
                inputs["motion"].native,
                neighbors.native,
                result.native,
                params,
                backend,
            )

        extra = {}
        if classified:
            extra["tile_bounds"] = bounds
            extra.update(
                classification.run_classified(
                    ctx,
                    lambda pass_name, fn: timed(ctx, timings, pass_name, fn),
                    inputs,
                    neighbors,
                    bounds,
                    result,
                    params,
                    values["uniform_spread"],
                    reconstruct,
                    run_reconstruct,
                )
            )
        else:
            timed(ctx, timings, "reconstruct", run_reconstruct)
        return {"color": result, "tile_max": tiles, "neighbor_max": neighbors, **extra}, timings

    return run
