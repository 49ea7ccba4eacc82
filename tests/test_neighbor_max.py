"""NeighborMax (docs/spec.md §3.3) on the GPU against bl.twins.mcguire2012.neighbor_max, and
where it runs (§3.6): its own pass in every tile filter, or the compute reconstruct pass's
prologue with the same bits in the filters that offer the tile-filter options."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_frame
from method_picks import pick, picks
from pass_records import recorded_passes, the_pass

import blurlab as bl
from blurlab.methods.tile_filter import FILTER_OPTIONS
from blurlab.twins import mcguire2012 as ref

# A tile filter on both backends, and the filters whose reconstruct takes the tile-filter
# options: their compute reconstruct shader (shaders/common/tile_filter.glsl) can compute
# NeighborMax in its prologue (FUSED_NEIGHBOR_MAX).
TILE_FILTER = pick(kind="filter", params=("k",), backends=("compute", "fragment"))
OPTIONS_FILTERS = picks(kind="filter", params=tuple(FILTER_OPTIONS), backends=("compute",))


def blur_recorded(ctx, frame, name, **params):
    """bl.blur(ctx, frame, name, **params) and the passes it ran."""
    with recorded_passes() as runs:
        result = bl.blur(ctx, frame, name, **params)
    return result, runs


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize(
    ("k", "size"), [(1, (19, 13)), (5, (64, 40)), (20, (160, 90)), (64, (200, 70))]
)
def test_neighbor_max_equals_reference(ctx, rng, backend, k, size):
    frame = random_frame(rng, *size, k=k)
    result, runs = blur_recorded(ctx, frame, TILE_FILTER, backend=backend, k=k)
    diagonal_reach = bool(the_pass(runs, "neighbor_max").uniforms["diagonal_reach"])
    tiles = result.buffers["tile_max"].astype(np.float64)
    expected = ref.neighbor_max(tiles, diagonal_reach=diagonal_reach)
    np.testing.assert_array_equal(result.buffers["neighbor_max"], expected.astype(np.float32))


def test_neighbor_max_spreads_one_tile_to_its_ring():
    tiles = np.zeros((5, 6, 2))
    tiles[2, 3] = (3.0, 4.0)
    spread = ref.neighbor_max(tiles)
    ring = np.zeros((5, 6), bool)
    ring[1:4, 2:5] = True
    assert (np.linalg.norm(spread, axis=-1) == 5.0).sum() == 9
    assert (np.linalg.norm(spread[ring], axis=-1) == 5.0).all()


@pytest.mark.parametrize(
    ("name", "backend"),
    # docs/spec.md §3.6: a pass of its own on every backend and device
    [(name, backend) for name in picks(kind="filter") for backend in bl.method(name).backends],
)
def test_where_neighbor_max_runs(ctx, rng, name, backend):
    result = bl.blur(ctx, random_frame(rng, 64, 36), name, backend=backend)
    assert list(result.timings)[:2] == ["tile_max", "neighbor_max"]


def run_reconstruct(ctx, runs, frame, tiles, fused):
    """The compute reconstruct pass of a recorded call (`runs`) on `frame`: reading the
    NeighborMax grid of the separate pass, or (`fused`) computing it from `tiles` in its
    prologue, with the diagonal reach of the call's own NeighborMax pass. (color, grid)."""
    reconstruct = the_pass(runs, "reconstruct")
    defines, uniforms = dict(reconstruct.defines), dict(reconstruct.uniforms)
    diagonal_reach = bool(the_pass(runs, "neighbor_max").uniforms["diagonal_reach"])
    height, width = frame.color.shape[:2]
    inputs = {"color": frame.color, "depth": frame.depth, "motion": frame.motion}
    inputs = {key: ctx.upload(value) for key, value in inputs.items()}
    color, grid = ctx.empty((height, width, 4)), ctx.empty(tiles.shape)
    if fused:
        defines["FUSED_NEIGHBOR_MAX"] = 1
        inputs["tile_max"] = ctx.upload(tiles)
        outputs = {"result": color, "neighbor_max": grid}
        uniforms["diagonal_reach"] = diagonal_reach
    else:
        separate = ref.neighbor_max(tiles.astype(np.float64), diagonal_reach=diagonal_reach)
        inputs["neighbor_max"] = ctx.upload(separate.astype(np.float32))
        outputs = {"result": color}
    ctx.shader_pass(reconstruct.step.shader, defines).run(inputs, outputs, uniforms)
    return color.download(), grid.download()


@pytest.mark.parametrize("name", OPTIONS_FILTERS)
@pytest.mark.parametrize(
    ("k", "size", "jitter"),
    [(1, (37, 23), 1), (3, (53, 37), 1), (20, (160, 90), 0), (7, (97, 61), 1)],
)
def test_the_fused_prologue_gives_the_separate_bits(ctx, rng, name, k, size, jitter):
    """The compute reconstruct with NeighborMax in its prologue against the same shader reading
    the grid of the separate pass, bit for bit (k = 1: the most tiles a work group reaches),
    and the grid it writes against the NumPy twin."""
    frame = random_frame(rng, *size, k=k)
    result, runs = blur_recorded(ctx, frame, name, k=k, samples=9, jitter_tiles=jitter)
    tiles = result.buffers["tile_max"]
    color, grid = run_reconstruct(ctx, runs, frame, tiles, fused=True)
    separate, _ = run_reconstruct(ctx, runs, frame, tiles, fused=False)
    assert color.tobytes() == separate.tobytes() == result.color.tobytes()
    np.testing.assert_array_equal(grid, result.buffers["neighbor_max"])


def test_the_fused_grid_is_written_whole(ctx, rng):
    """Every tile of the fused pass's neighbor_max grid is written by one work group, also
    where k does not divide the image or the work group."""
    frame = random_frame(rng, 90, 50, k=6)
    name = OPTIONS_FILTERS[0]
    result, runs = blur_recorded(ctx, frame, name, k=6, jitter_tiles=1)
    tiles = result.buffers["tile_max"]
    _, grid = run_reconstruct(ctx, runs, frame, tiles, True)
    diagonal_reach = bool(the_pass(runs, "neighbor_max").uniforms["diagonal_reach"])
    expected = ref.neighbor_max(tiles.astype(np.float64), diagonal_reach=diagonal_reach)
    expected = expected.astype(np.float32)
    assert np.linalg.norm(expected, axis=-1).min() > 0  # an unwritten (zero) tile would show
    np.testing.assert_array_equal(grid, expected)
