"""Tile classification (Jimenez 2014) as an option of the reconstruction filters: still tiles
copy the color, uniform tiles take the cheap single-direction gather, the rest the filter's
own reconstruct pass — each run by an indirect dispatch over its class's tile list.
docs/classify_and_steps.md; NumPy twin blurlab.reference.classify.

A filter opts in with the parameters CLASSIFY_PARAMS and two calls (tile_filter.run_filter
makes them): TileMax with bounds (`tile_max_with_bounds`) instead of plain TileMax, then
`run_classified` in place of its reconstruct dispatch, handing over a function that runs its
own reconstruct pass.
"""

from __future__ import annotations

from collections.abc import Callable

from .. import _core
from ..reference.classify import FULL, STILL, STILL_THRESHOLD, UNIFORM
from .core import Param

# The parameters a filter adds to offer classification.
CLASSIFY_PARAMS = {
    "classify": Param(
        False,
        bool,
        "tile classification: skip still tiles, cheap gather on uniform ones (compute backend)",
    ),
    "uniform_spread": Param(
        0.5,
        float,
        "classification: largest |V - NeighborMax| of a uniform tile, px",
        0.0,
        512.0,
    ),
}


def check_request(name: str, values: dict, backend: str, options) -> None:
    """Classification runs on the compute backend and takes none of the filter `options`."""
    if backend != "compute":
        raise ValueError(
            f"blurlab: {name} with classify=True runs on the compute backend, not {backend!r}"
        )
    chosen = [o for o in options if values.get(o)]
    if chosen:
        raise ValueError(
            f"blurlab: {name} with classify=True takes none of the filter options "
            f"yet; {', '.join(chosen)} set (docs/classify_and_steps.md)"
        )


def tile_lists(ctx, grid: tuple[int, int], k: int) -> _core.TileLists:
    """The context's tile-list buffer for a (tiles_h, tiles_w) grid of k-pixel tiles."""
    return ctx.cached(
        ("tile_lists", grid, k), lambda: _core.TileLists(ctx.native, grid[1], grid[0], k)
    )


def run_classified(
    ctx,
    timed: Callable,
    inputs: dict,
    neighbors,
    bounds,
    result,
    params: _core.McGuire2012Params,
    uniform_spread: float,
    full_pass,
    run_full: Callable[[], None],
    still_threshold: float = STILL_THRESHOLD,
) -> dict:
    """Classifies the tiles, then writes `result` class by class: the still tiles' color, the
    uniform tiles' gather, and `run_full()` (the filter's reconstruct pass, `full_pass`)
    restricted to the full tiles. `timed(name, fn)` runs and times one pass. Returns the
    class map texture as {"tile_class": texture}."""
    grid = tuple(neighbors.shape[:2])
    lists = tile_lists(ctx, grid, params.k)
    classes = ctx.pooled(grid)
    cp = _core.ClassifyParams()
    cp.still_threshold = still_threshold
    cp.uniform_spread = uniform_spread
    cp.validate()
    classify = ctx.cached("classify_tiles", lambda: _core.ClassifyTilesPass(ctx.native))
    copy = ctx.cached("tile_copy", lambda: _core.TileCopyPass(ctx.native))
    gather = ctx.cached("uniform_gather", lambda: _core.UniformGatherPass(ctx.native))
    timed(
        "classify_tiles",
        lambda: classify.run(bounds.native, neighbors.native, classes.native, lists, cp),
    )

    def restricted(pass_, tile_class, fn):
        pass_.restrict_to_tiles(lists, tile_class)
        try:
            fn()
        finally:
            pass_.restrict_to_tiles(None, 0)

    timed(
        "still_copy",
        lambda: restricted(copy, STILL, lambda: copy.run(inputs["color"].native, result.native)),
    )
    timed(
        "uniform_gather",
        lambda: restricted(
            gather,
            UNIFORM,
            lambda: gather.run(inputs["color"].native, neighbors.native, result.native, params),
        ),
    )
    timed("reconstruct", lambda: restricted(full_pass, FULL, run_full))
    return {"tile_class": classes}


def tile_max_with_bounds(ctx, tile_pass, motion, tiles, params) -> object:
    """TileMax that also writes each tile's bounds of V; returns the bounds texture."""
    bounds = ctx.pooled((*tiles.shape[:2], 4))
    tile_pass.run_with_bounds(motion.native, tiles.native, bounds.native, params)
    return bounds
