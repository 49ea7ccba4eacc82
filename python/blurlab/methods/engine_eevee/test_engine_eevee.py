"""engine_eevee (docs/spec.md §17.2) on the GPU against its twins (the tile passes':
blurlab.twins.eevee): each pass, the dilation along each tile's motion, and the filter's
promises: still images unchanged, output inside the input range, no NaN, same seed same
bits."""

from __future__ import annotations

import numpy as np
from conftest import assert_timings_name, random_frame
from filter_promises import (
    two_sided_frame,
)

import blurlab as bl
from blurlab.twins import eevee as ref

METHOD = "engine_eevee"


def test_tile_passes_equal_their_twins(ctx, rng):
    frame = two_sided_frame(rng, 150, 90, reach=60.0)
    params = {"tile_size": 8, "max_blur": 50.0, "exposure": 0.8}
    result = bl.blur(ctx, frame, METHOD, **params)
    prev = ref.scaled_motion(frame.motion_prev, 0.8)
    next_ = ref.scaled_motion(frame.motion_next, 0.8)
    tiles = ref.tile_flatten(prev, next_, 8)
    np.testing.assert_allclose(result.buffers["tiles"], tiles, rtol=1e-6, atol=1e-5)
    dilated = ref.tile_dilate(result.buffers["tiles"].astype(np.float64), 8, 50.0)
    np.testing.assert_allclose(result.buffers["dilated"], dilated, rtol=1e-6, atol=1e-5)


def test_dilation_follows_each_tile_motion_not_a_3x3_block():
    tiles = np.zeros((9, 9, 4))
    tiles[4, 4, 2:] = (3 * 16.0, 0.0)  # next half: 3 tiles to the right (16 px tiles)
    tiles[4, 4, :2] = (0.0, 2 * 16.0)  # prev half: spread against it, 2 tiles up
    dilated = ref.tile_dilate(tiles, 16, 64.0)
    reached_next = np.linalg.norm(dilated[..., 2:], axis=-1) > 0
    reached_prev = np.linalg.norm(dilated[..., :2], axis=-1) > 0
    assert reached_next[4, 4:8].all() and not reached_next[4, 8]  # 3 tiles on and its end
    assert not reached_next[4, 3] and not reached_next[3, 4] and not reached_next[5, 4]
    assert reached_prev[2:5, 4].all() and not reached_prev[1, 4] and not reached_prev[5, 4]
    assert reached_next.sum() == 4 and reached_prev.sum() == 3


def test_motion_under_half_a_pixel_exits_early(ctx, rng):
    frame = random_frame(rng, 64, 48)
    frame.motion[:] = 0.45 * 2 * np.array([0.6, 0.8], np.float32)  # each half 0.45 px
    result = bl.blur(ctx, frame, METHOD)
    assert result.color.tobytes() == frame.color.tobytes()


def test_two_sided_motion_is_what_it_reads(ctx, rng):
    """Frames with the same M but other halves blur differently: the halves are its input."""
    frame = two_sided_frame(rng, 80, 60)
    derived = bl.Frame(frame.color, frame.depth, frame.motion)
    a = bl.blur(ctx, frame, METHOD, tile_size=16).color
    b = bl.blur(ctx, derived, METHOD, tile_size=16).color
    assert np.abs(a - b).max() > 0.05


def test_timings_name_every_pass(ctx, rng):
    assert_timings_name(ctx, rng, METHOD, ["tile_flatten", "tile_dilate", "gather"])
