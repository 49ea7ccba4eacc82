"""The tile filters in one dispatch (docs/spec.md §3.7, common/tile_chain.glsl): the same bits
as the three passes, for both filters, stored and packed inputs, grids of one tile to many,
partial edge tiles, and runs in a row (each run leaves the tile counters at zero for the next);
where the one dispatch cannot run (jittered lookup, a thread per tile, fragment) the filter
runs as three passes. uint32 textures, which hold the counters, bind only to unsigned uniforms."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_frame

import blurlab as bl
from blurlab.methods import tile_filter

FILTERS = ("reconstruct_mcguire2012", "reconstruct_guertin2014")


def both_ways(ctx, frame, name, **params):
    """{layout: (color, tile_max, neighbor_max, pass names)} of one run under each layout."""
    out = {}
    for layout in tile_filter.FILTER_DISPATCH_VARIANTS:
        with tile_filter.FILTER_DISPATCH.use(layout):
            result = bl.blur(ctx, frame, name, **params)
            buffers = result.buffers
            out[layout] = (
                result.color.copy(),
                buffers["tile_max"].copy(),
                buffers["neighbor_max"].copy(),
                list(result.timings),
            )
    return out


def group_per_tile_k(ctx, k: int) -> int:
    """`k`, raised above the largest tile one thread scans on this device (llvmpipe: 32)."""
    return max(k, tile_filter.largest_tile_for_one_thread(ctx) + 1)


@pytest.mark.parametrize("name", FILTERS)
@pytest.mark.parametrize("packed", [False, True])
@pytest.mark.parametrize(
    ("k", "size"), [(20, (160, 90)), (33, (200, 70)), (48, (160, 90)), (100, (160, 90))]
)
def test_one_dispatch_gives_the_three_passes_bits(ctx, rng, name, packed, k, size):
    k = group_per_tile_k(ctx, k) if k == 20 else k
    frame = random_frame(rng, *size, k=k)
    runs = both_ways(ctx, frame, name, k=k, packed_inputs=packed)
    separate, chained = runs["three_passes"], runs["one_dispatch"]
    assert separate[3] == ["tile_max", "neighbor_max", "reconstruct"]
    assert chained[3] == ["tile_filter"]
    for a, b in zip(separate[:3], chained[:3], strict=True):
        np.testing.assert_array_equal(a, b)


@pytest.mark.parametrize("name", FILTERS)
def test_runs_in_a_row_leave_the_counters_at_zero(ctx, rng, name):
    k = group_per_tile_k(ctx, 40)
    frames = [random_frame(rng, 160, 90, k=k) for _ in range(3)]
    with tile_filter.FILTER_DISPATCH.use("one_dispatch"):
        for frame in frames * 2:
            bl.blur(ctx, frame, name, k=k)
    grid = (-(-90 // k), -(-160 // k))
    counters = tile_filter.tile_counters(ctx, grid).download()
    assert counters.dtype == np.uint32 and not counters.any()
    for frame in frames:  # and the later runs still match the three passes
        runs = both_ways(ctx, frame, name, k=k)
        np.testing.assert_array_equal(runs["three_passes"][0], runs["one_dispatch"][0])


@pytest.mark.parametrize(
    ("params", "backend"),
    [({"jitter_tiles": 1}, "compute"), ({}, "fragment"), ({"k": 4}, "compute")],
)
def test_three_passes_where_one_dispatch_cannot_run(ctx, rng, params, backend):
    params = {"k": group_per_tile_k(ctx, 40), **params}
    frame = random_frame(rng, 160, 90, k=params["k"])
    with tile_filter.FILTER_DISPATCH.use("one_dispatch"):
        result = bl.blur(ctx, frame, "reconstruct_mcguire2012", backend=backend, **params)
    assert list(result.timings) == ["tile_max", "neighbor_max", "reconstruct"]


def test_uint32_textures_bind_only_to_unsigned_uniforms(ctx):
    counters = ctx.empty((4, 4), "uint32")
    assert counters.dtype == np.uint32 and not counters.download().any()
    floats = ctx.empty((4, 4, 4))
    with pytest.raises(ValueError, match="cannot take a uint32 texture"):
        ctx.shader_pass("passes/film_filter.glsl", {"FILM_RADIUS": 1}).run(
            {"color": counters}, {"result": floats}, {"film_filter": 0.5}
        )
    with pytest.raises(TypeError, match="allowed dtypes"):
        ctx.upload(np.zeros((4, 4), np.uint32))
