"""Tile classification (Jimenez 2014) as an option of the reconstruction filters: still tiles
copy the color, uniform tiles take the cheap single-direction gather, the rest the filter's
own reconstruct pass — each run by an indirect dispatch over its class's tile list.
docs/classify_and_steps.md; NumPy twin blurlab.reference.classify.

A filter opts in with two parameters (CLASSIFY_PARAMS) and two calls: TileMax with bounds
(`tile_max_with_bounds`) instead of plain TileMax, then `run_classified` in place of its
reconstruct dispatch, handing over a function that runs its own reconstruct pass.
"""

from __future__ import annotations

from collections.abc import Callable

from . import _core
from .reference.classify import STILL, STILL_THRESHOLD, UNIFORM

FULL_CLASS = 2


def classify_params():
    """The parameters a filter adds to offer classification (methods.Param entries)."""
    from .methods import Param

    return {
        "classify": Param(
            False,
            bool,
            "tile classification: skip still tiles, cheap gather on uniform ones (compute backend)",
        ),
        "uniform_spread": Param(
            0.5,
            float,
            "classification: largest |V - NeighborMax| of a uniform tile, px (0..512)",
            0.0,
            512.0,
        ),
    }


def check_backend(values: dict, backend: str, name: str) -> None:
    if values["classify"] and backend != "compute":
        raise ValueError(
            f"blurlab: {name} with classify=True runs on the compute backend, not {backend!r}"
        )


def tile_lists(ctx, grid: tuple[int, int], k: int) -> _core.TileLists:
    """The context's tile-list buffer for a (tiles_h, tiles_w) grid of k-pixel tiles."""
    key = ("tile_lists", grid, k)
    if key not in ctx._passes:
        ctx._passes[key] = _core.TileLists(ctx._core, grid[1], grid[0], k)
    return ctx._passes[key]


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
    classes = ctx._pooled(grid)
    cp = _core.ClassifyParams()
    cp.still_threshold = still_threshold
    cp.uniform_spread = uniform_spread
    cp.validate()
    classify = ctx._pass("classify_tiles", _core.ClassifyTilesPass)
    copy = ctx._pass("tile_copy", _core.TileCopyPass)
    gather = ctx._pass("uniform_gather", _core.UniformGatherPass)
    timed(
        "classify_tiles",
        lambda: classify.run(bounds._core, neighbors._core, classes._core, lists, cp),
    )

    def restricted(pass_, tile_class, fn):
        pass_.restrict_to_tiles(lists, tile_class)
        try:
            fn()
        finally:
            pass_.restrict_to_tiles(None, 0)

    timed(
        "still_copy",
        lambda: restricted(copy, STILL, lambda: copy.run(inputs["color"]._core, result._core)),
    )
    timed(
        "uniform_gather",
        lambda: restricted(
            gather,
            UNIFORM,
            lambda: gather.run(inputs["color"]._core, neighbors._core, result._core, params),
        ),
    )
    timed("reconstruct", lambda: restricted(full_pass, FULL_CLASS, run_full))
    return {"tile_class": classes}


def tile_max_with_bounds(ctx, tile_pass, motion, tiles, params) -> object:
    """TileMax that also writes each tile's bounds of V; returns the bounds texture."""
    bounds = ctx._pooled((*tiles.shape[:2], 4))
    tile_pass.run_with_bounds(motion._core, tiles._core, bounds._core, params)
    return bounds
