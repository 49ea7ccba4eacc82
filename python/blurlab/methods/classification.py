"""Tile classification (Jimenez 2014) as an option of the reconstruction filters: still tiles
copy the color, uniform tiles take the cheap single-direction gather, the rest the filter's
own reconstruct pass — each run by an indirect dispatch over its class's tile list.
docs/classify_and_steps.md; NumPy twin blurlab.twins.classify.

A filter opts in with the parameters CLASSIFY_PARAMS; tile_filter.run_filter then runs TileMax
with each tile's bounds and `run_classified` in place of its reconstruct dispatch, handing over
a function that runs its own reconstruct pass on a class's tiles.
"""

from __future__ import annotations

from collections.abc import Callable

from .. import _core
from ..twins.classify import FULL, STILL, STILL_THRESHOLD, UNIFORM
from .core import Param, Pass, run_pass, timed

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


# The passes that write the still and uniform tiles (docs/classify_and_steps.md).
STILL_COPY = Pass("still_copy", "passes/tile_copy.glsl", whole_tiles=True)
UNIFORM_GATHER = Pass("uniform_gather", "passes/uniform_gather.glsl", ("k", "samples", "seed"))


def run_classified(
    ctx,
    timings: dict,
    params: dict,
    values: dict,
    inputs: dict,
    neighbors,
    bounds,
    result,
    run_full: Callable,
    still_threshold: float = STILL_THRESHOLD,
) -> dict:
    """Classifies the tiles, then writes `result` class by class: the still tiles' color, the
    uniform tiles' gather, and `run_full((lists, FULL))` (the filter's reconstruct pass,
    restricted to the full tiles). Returns the class map texture as {"tile_class": texture}."""
    grid = tuple(neighbors.shape[:2])
    lists = tile_lists(ctx, grid, values["k"])
    classes = ctx.pooled(grid)
    classify = ctx.cached("classify_tiles", lambda: _core.ClassifyTilesPass(ctx.native))
    timed(
        ctx,
        timings,
        "classify_tiles",
        lambda: classify.run(
            bounds.native,
            neighbors.native,
            classes.native,
            lists,
            still_threshold,
            values["uniform_spread"],
        ),
    )
    color = {"color": inputs["color"]}
    out = {"result": result}
    run_pass(ctx, timings, STILL_COPY, params, values, color, out, tiles=(lists, STILL))
    gather_inputs = {**color, "neighbor_max": neighbors}
    run_pass(
        ctx, timings, UNIFORM_GATHER, params, values, gather_inputs, out, tiles=(lists, UNIFORM)
    )
    run_full((lists, FULL))
    return {"tile_class": classes}
