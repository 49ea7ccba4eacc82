"""gather_pixel (docs/spec.md §17.9) on the GPU against bl.twins.pixel_gather on both backends,
the tap count that follows each pixel's speed, the depth test against the pixel, and the
filter's promises: still images unchanged, output inside the input range, no NaN, same seed
same bits."""

from __future__ import annotations

import numpy as np
from conftest import assert_matches_twin, assert_timings_name

import blurlab as bl
from blurlab.methods.gather_pixel import twin as ref

METHOD = "gather_pixel"


def test_taps_follow_the_speed():
    # Half-vectors of 0, 0.5, 2, 2.1, 7 and 100 px at spacing 2, at most 8 on each side.
    motion = np.array([[[0, 0], [1, 0], [0, 4], [4.2, 0], [0, -14], [200, 0]]], np.float32)
    taps = ref.pixel_taps(motion, exposure=1.0, spacing=2.0, samples=8)
    assert taps.tolist() == [[0, 1, 1, 2, 4, 8]]


def test_a_tap_in_front_is_dropped(ctx):
    """A background moving 16 px in x behind a still post (nearer by 5): the background's taps
    on the post weigh nothing, so no post colour bleeds into it; the post stays sharp."""
    width, height = 48, 8
    color = np.zeros((height, width, 4), np.float32)
    color[..., 3] = 1
    color[..., 1] = np.linspace(0, 1, width)[None, :]  # a green ramp behind
    color[:, 20:24, :3] = (1.0, 0.0, 0.0)  # the post, red
    depth = np.full((height, width), 10.0, np.float32)
    depth[:, 20:24] = 5.0
    motion = np.zeros((height, width, 2), np.float32)
    motion[..., 0] = np.where(depth == 10.0, 16.0, 0.0)
    frame = bl.Frame(color=color, depth=depth, motion=motion)
    out = bl.blur(ctx, frame, METHOD).color
    np.testing.assert_array_equal(out[:, 20:24], color[:, 20:24])
    background = np.ones(width, bool)
    background[20:24] = False
    assert out[:, background, 0].max() == 0.0  # no red bleeds into the background
    assert np.abs(out[:, background, 1] - color[:, background, 1]).max() > 0.01  # it blurred
    assert_matches_twin(bl.blur(ctx, frame, METHOD), frame)


def test_timings_name_its_pass(ctx, rng):
    assert_timings_name(ctx, rng, METHOD, ["gather"])
