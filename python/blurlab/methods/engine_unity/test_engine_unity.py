"""engine_unity (docs/spec.md §17.3) on the GPU against its twin (twin.py): the 10-bit velocity
setup, TileMax by reductions, the centre-biased NeighborMax, and the filter's promises: still
images unchanged, output inside the input range, no NaN, same seed same bits."""

from __future__ import annotations

import numpy as np
from conftest import assert_timings_name, random_frame

import blurlab as bl
from blurlab.methods.engine_unity import twin as ref

METHOD = "engine_unity"


def test_velocity_and_tile_passes_equal_their_twins(ctx, rng):
    frame = random_frame(rng, 150, 90, k=10)
    result = bl.blur(ctx, frame, METHOD, max_radius=20.0)
    radius = ref.max_radius_px(90, 20.0)
    far = result.params["far"]
    codes = ref.velocity_setup(frame.depth, frame.motion, exposure=1.0, radius=radius, far=far)
    gpu_codes = result.buffers["velocity"][..., :3]
    assert (gpu_codes == codes).mean() >= 0.999  # float32 rounding may move a code by one
    tiles = ref.tile_max(gpu_codes.astype(np.float64), ref.tile_size(90, 20.0))
    np.testing.assert_array_equal(result.buffers["tile_max"][..., :2], tiles)
    np.testing.assert_array_equal(result.buffers["neighbor_max"][..., :2], ref.neighbor_max(tiles))


def test_tile_size_is_five_percent_of_the_height_rounded_up_to_eight():
    assert ref.tile_size(360, 5.0) == 24  # R = 18 px
    assert ref.tile_size(1080, 5.0) == 56  # R = 54 px
    assert ref.tile_size(90, 5.0) == 8


def test_neighbor_max_prefers_the_center_within_one_percent():
    codes = np.full((3, 3, 2), 511.5)  # (2c - 1023) = 0: no motion
    codes[1, 1] = (611.5, 511.5)  # center: 200 units long
    codes[0, 0] = (511.5, 612.0)  # 201 units: within 1 % of the center's length
    assert (ref.neighbor_max(codes)[1, 1] == (611.5, 511.5)).all()
    codes[0, 0] = (511.5, 614.0)  # 205 units: beyond it
    assert (ref.neighbor_max(codes)[1, 1] == (511.5, 614.0)).all()


def test_timings_name_every_pass(ctx, rng):
    assert_timings_name(
        ctx,
        rng,
        METHOD,
        [
            "velocity_setup",
            "tile_max_2",
            "tile_max_4",
            "tile_max_8",
            "tile_max",
            "neighbor_max",
            "reconstruct",
        ],
    )
