"""TileMax (docs/spec.md §3.2) on the GPU against bl.twins.mcguire2012.tile_max."""

from __future__ import annotations

import contextlib

import numpy as np
import pytest
from conftest import random_frame
from method_picks import pick

import blurlab as bl
from blurlab.methods.tile_filter import TILE_MAX_VARIANTS, tile_max_variant
from blurlab.twins import mcguire2012 as ref

# A tile filter on both backends: its TileMax is the shared one of blurlab.methods.tile_filter.
FILTER = pick(kind="filter", params=("k", "exposure"), backends=("compute", "fragment"))


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize(
    ("k", "size"), [(1, (23, 17)), (7, (61, 45)), (20, (160, 90)), (64, (97, 61))]
)
def test_tile_max_equals_reference(ctx, rng, backend, k, size):
    frame = random_frame(rng, *size, k=k)
    result = bl.blur(ctx, frame, FILTER, backend=backend, k=k, exposure=0.8)
    expected = ref.tile_max(ref.half_velocity(frame.motion, 0.8, k), k)
    assert result.buffers["tile_max"].shape == (-(-size[1] // k), -(-size[0] // k), 2)
    # The same pixel wins in every tile; its half-vector, scaled by the exposure in float32 on
    # the GPU and in float64 here, agrees to an ulp.
    np.testing.assert_allclose(result.buffers["tile_max"], expected, rtol=1e-6, atol=0)


def test_partial_tiles_only_see_their_own_pixels(ctx):
    # 25 x 25 with k = 10: the last row and column of tiles hold 5 pixels across.
    motion = np.zeros((25, 25, 2), np.float32)
    motion[24, 24] = (8.0, 0.0)  # the only mover, in the corner tile
    frame = bl.Frame(color=np.zeros((25, 25, 4)), depth=np.ones((25, 25)), motion=motion)
    # With exposure 1 the half-vector of a motion longer than a pixel is exact: equal bits.
    tiles = bl.blur(ctx, frame, FILTER, k=10).buffers["tile_max"]
    assert tiles.shape == (3, 3, 2)
    np.testing.assert_array_equal(tiles[2, 2], [4.0, 0.0])  # half of the motion
    assert not tiles[:2].any() and not tiles[:, :2].any()


def test_half_velocity_clamps_to_half_a_pixel_and_k():
    v = ref.half_velocity(np.array([[0.0, 0.0], [0.2, 0.0], [100.0, 0.0], [0.0, -3.0]]), 1.0, 20)
    np.testing.assert_allclose(v, [[0, 0], [0.5, 0], [20, 0], [0, -1.5]])


@pytest.mark.parametrize("variant", list(TILE_MAX_VARIANTS))
@pytest.mark.parametrize(("k", "size"), [(40, (97, 61)), (64, (160, 90))])
def test_every_tile_max_variant_gives_the_same_bits(ctx, rng, variant, k, size):
    # k above 32 px: a work group per tile on llvmpipe as on a GPU (largest_tile_for_one_thread).
    frame = random_frame(rng, *size, k=k)
    default = bl.blur(ctx, frame, FILTER, k=k, exposure=0.8)
    with tile_max_variant(variant):
        result = bl.blur(ctx, frame, FILTER, k=k, exposure=0.8)
    tiles = result.buffers["tile_max"]
    np.testing.assert_array_equal(tiles, default.buffers["tile_max"])
    expected = ref.tile_max(ref.half_velocity(frame.motion, 0.8, k), k)
    np.testing.assert_allclose(tiles, expected, rtol=1e-6, atol=0)


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize("variant", [None, *TILE_MAX_VARIANTS])
@pytest.mark.parametrize("k", [20, 40])
def test_ties_go_to_the_first_pixel_in_row_order(ctx, backend, variant, k):
    # Three motions whose half-vectors all clamp to length k exactly (in float32 as in float64):
    # the first in row order wins, as the twin's argmax picks it; an 8 x 8 group's thread 0
    # scans (0, 8) before thread 1 scans (1, 0).
    motion = np.zeros((2 * k, 2 * k, 2), np.float32)
    motion[8, 0] = (0.0, 2.5 * k)
    motion[0, 1] = (2.5 * k, 0.0)
    motion[k - 1, k - 1] = (-2.5 * k, 0.0)
    side = 2 * k
    frame = bl.Frame(color=np.zeros((side, side, 4)), depth=np.ones((side, side)), motion=motion)
    with tile_max_variant(variant) if variant else contextlib.nullcontext():
        tiles = bl.blur(ctx, frame, FILTER, backend=backend, k=k)
    expected = ref.tile_max(ref.half_velocity(motion, 1.0, k), k)
    np.testing.assert_array_equal(expected[0, 0], [k, 0.0])
    # The three candidates point three ways, so the winner shows in the direction; its length
    # may be 1 ulp under k on a GPU (the H100 gives 19.999998 for k = 20), equally for all three.
    np.testing.assert_allclose(tiles.buffers["tile_max"], expected, rtol=1e-6, atol=0)


def test_an_unknown_variant_is_refused():
    with pytest.raises(ValueError, match="rows_64"), tile_max_variant("rows_65"):
        pass
