"""NeighborMax (docs/spec.md §3.3) on the GPU against bl.twins.mcguire2012.neighbor_max, and
where it runs (§3.6): its own pass, or the compute reconstruct pass's prologue with the same
bits."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_frame

import blurlab as bl
from blurlab.methods import guertin2014, mcguire2012
from blurlab.methods.core import choice_defines, pass_uniforms
from blurlab.twins import mcguire2012 as ref


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize(
    ("k", "size"), [(1, (19, 13)), (5, (64, 40)), (20, (160, 90)), (64, (200, 70))]
)
def test_neighbor_max_equals_reference(ctx, rng, backend, k, size):
    frame = random_frame(rng, *size, k=k)
    result = bl.blur(ctx, frame, "reconstruct_mcguire2012", backend=backend, k=k)
    expected = ref.neighbor_max(result.buffers["tile_max"].astype(np.float64))
    np.testing.assert_array_equal(result.buffers["neighbor_max"], expected.astype(np.float32))


def test_neighbor_max_spreads_one_tile_to_its_ring():
    tiles = np.zeros((5, 6, 2))
    tiles[2, 3] = (3.0, 4.0)
    spread = ref.neighbor_max(tiles)
    ring = np.zeros((5, 6), bool)
    ring[1:4, 2:5] = True
    assert (np.linalg.norm(spread, axis=-1) == 5.0).sum() == 9
    assert (np.linalg.norm(spread[ring], axis=-1) == 5.0).all()


FILTERS = {"reconstruct_mcguire2012": mcguire2012, "reconstruct_guertin2014": guertin2014}


@pytest.mark.parametrize(
    ("name", "backend", "params", "passes"),
    [  # docs/spec.md §3.6: compute folds NeighborMax into reconstruct, the others keep three
        ("reconstruct_mcguire2012", "compute", {}, ["tile_max", "reconstruct"]),
        ("reconstruct_guertin2014", "compute", {}, ["tile_max", "reconstruct"]),
        ("reconstruct_guertin2014", "fragment", {}, ["tile_max", "neighbor_max", "reconstruct"]),
        ("reconstruct_mcguire2012", "compute", {"classify": True}, ["tile_max", "neighbor_max"]),
    ],
)
def test_where_neighbor_max_runs(ctx, rng, name, backend, params, passes):
    result = bl.blur(ctx, random_frame(rng, 64, 36), name, backend=backend, **params)
    assert list(result.timings)[: len(passes)] == passes


@pytest.mark.parametrize("name", FILTERS)
@pytest.mark.parametrize(
    ("k", "size", "jitter"),
    [(1, (37, 23), 1), (3, (53, 37), 1), (20, (160, 90), 0), (7, (97, 61), 1)],
)
def test_the_fused_prologue_gives_the_separate_bits(ctx, rng, name, k, size, jitter):
    """The compute reconstruct with NeighborMax in its prologue against the same shader reading
    the grid of the separate pass, bit for bit (k = 1: the most tiles a work group reaches)."""
    frame = random_frame(rng, *size, k=k)
    fused = bl.blur(ctx, frame, name, k=k, samples=9, jitter_tiles=jitter)
    tiles = fused.buffers["tile_max"].astype(np.float64)
    separate = ref.neighbor_max(tiles, diagonal_reach=name == "reconstruct_guertin2014")
    np.testing.assert_array_equal(fused.buffers["neighbor_max"], separate.astype(np.float32))
    method, step = bl.method(name), FILTERS[name].RECONSTRUCT
    shader = ctx.shader_pass(step.shader, choice_defines(method.params, step.params))
    out = ctx.empty((size[1], size[0], 4))
    inputs = {"color": frame.color, "depth": frame.depth, "motion": frame.motion}
    inputs = {key: ctx.upload(value) for key, value in inputs.items()}
    inputs["neighbor_max"] = ctx.upload(fused.buffers["neighbor_max"])
    shader.run(inputs, {"result": out}, pass_uniforms(method.params, fused.params, step.params))
    assert fused.color.tobytes() == out.download().tobytes()


def test_the_fused_grid_is_written_anew_each_call(ctx, rng):
    """Every tile of the neighbor_max buffer is written by exactly one work group: a second
    frame of the same size (the same pooled texture) leaves nothing of the first."""
    for seed in (1, 2):
        frame = random_frame(np.random.default_rng(seed), 90, 50, k=6)
        result = bl.blur(ctx, frame, "reconstruct_mcguire2012", k=6, jitter_tiles=1)
        expected = ref.neighbor_max(result.buffers["tile_max"].astype(np.float64))
        np.testing.assert_array_equal(result.buffers["neighbor_max"], expected.astype(np.float32))
