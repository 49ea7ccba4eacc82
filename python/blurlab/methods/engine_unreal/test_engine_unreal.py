"""engine_unreal (spec.md, docs/spec.md §17.5) on the GPU against its twin (twin.py, and
blurlab.twins.unreal pass by pass): the 11:11:10 polar velocity, the min/max tiles, the 7 x 7
scatter-as-gather and its tile classes, each of the skip / fast / slow paths, and the filter's
promises: still images unchanged, output inside the input range, no NaN, same seed same bits."""

from __future__ import annotations

import numpy as np
from conftest import assert_matches_twin, assert_timings_name, random_frame

import blurlab as bl
from blurlab.twins import polar_fixed_point as polar
from blurlab.twins import unreal as ref

METHOD = "engine_unreal"


def test_velocity_and_tile_passes_equal_their_twins(ctx, rng):
    frame = random_frame(rng, 150, 90, k=10)
    result = bl.blur(ctx, frame, METHOD, max_blur=8.0)
    radius = ref.max_radius_px(150, 8.0)
    codes = ref.velocity_flatten(frame.depth, frame.motion, exposure=1.0, radius=radius)
    gpu_codes = result.buffers["velocity"][..., :3].astype(np.float64)
    assert (gpu_codes == codes).all(axis=-1).mean() >= 0.999  # float32 may move a code by one
    tiles = ref.tile_minmax(gpu_codes)
    np.testing.assert_array_equal(result.buffers["tiles"][..., :3], tiles)
    np.testing.assert_array_equal(result.buffers["neighbors"], ref.neighbor_dilate(tiles, radius))


def test_polar_codes_and_ten_bit_depth_hand_values(ctx):
    r = 10.0
    v = np.array([[r, 0], [0, r / 2], [-r, 0], [0, -r], [r, -1e-4], [30 * r, 0], [0, 0]])
    expected = [[2047, 0], [1024, 512], [2047, 1024], [2047, 1536], [2047, 0], [2047, 0], [0, 0]]
    np.testing.assert_array_equal(polar.polar_codes(v, r), expected)
    decoded = polar.decode_polar(np.array([1024.0, 512.0]), r)
    np.testing.assert_allclose(decoded, [0, 5.0024], atol=1e-4)
    z = [1.0, 1 + 1 / 64, 1 + 3 / 64, 3.0, 1e-9, 64512.0, 7e4, np.inf]
    assert polar.float10(z).tolist() == [1.0, 1.0, 1.0625, 3.0, 2**-14, 64512.0, np.inf, np.inf]
    # The GPU flattens the same values: M = 2V at 16 x 1 pixels, R = 5 % of 200 px = 10 px.
    motion = np.zeros((1, 200, 2), np.float32)
    depth = np.ones((1, 200), np.float32)
    motion[0, : len(v)] = 2 * v
    depth[0, : len(z)] = z
    frame = bl.Frame(color=np.zeros((1, 200, 4), np.float32), depth=depth, motion=motion)
    codes = bl.blur(ctx, frame, METHOD).buffers["velocity"]
    np.testing.assert_array_equal(codes[0, : len(v), :2], expected)
    assert codes[0, : len(z), 2].tolist() == polar.float10(z).tolist()


def test_a_tile_reaches_as_far_as_its_velocity_both_ways():
    codes = np.zeros((1, 1, 3))
    codes[0, 0, :2] = polar.polar_codes(np.array([2.0 * ref.TILE, 0.0]), 2.0 * ref.TILE)
    reach = {dx: bool(ref.reaches(codes, (dx, 0), 2.0 * ref.TILE)[0, 0]) for dx in range(-3, 4)}
    assert reach == {-3: False, -2: True, -1: True, 0: True, 1: True, 2: True, 3: False}
    assert not ref.reaches(codes, (0, 1), 2.0 * ref.TILE)[0, 0]  # nothing across the motion
    assert not ref.reaches(np.zeros((1, 1, 3)), (1, 0), 1.0)[0, 0]  # still: itself only
    assert ref.reaches(np.zeros((1, 1, 3)), (0, 0), 1.0)[0, 0]


def test_classes_follow_the_min_over_max_rule():
    longest = np.array([10.0, 10.0, 10.0, 0.0])
    shortest = np.array([5.0, 4.0, 0.0, 0.0])  # 0.5, 0.4 (not more than 0.4), 0 of the max
    radius = 2047.0  # a code is a pixel
    assert ref.classify(longest, shortest, radius).tolist() == [
        ref.FAST,
        ref.SLOW,
        ref.SLOW,
        ref.SKIP,
    ]
    assert ref.classify(np.array([1.0]), np.array([1.0]), 1000.0).tolist() == [ref.SKIP]  # 0.49 px


def _half_moving_frame(rng, width=160, height=96):
    """Still on the left, a uniform 12 px translation in x on the right third."""
    frame = random_frame(rng, width, height)
    frame.motion[:] = 0
    frame.motion[:, 2 * width // 3 :, 0] = 12.0
    return frame


def test_each_path_runs_on_the_tiles_of_its_class(ctx, rng):
    frame = _half_moving_frame(rng)
    result = bl.blur(ctx, frame, METHOD, max_blur=20.0)
    classes = result.buffers["neighbors"][..., 3].astype(int)
    counts = np.bincount(classes.ravel(), minlength=3)
    assert (counts > 0).all(), counts  # skip, fast and slow tiles all present
    assert_matches_twin(result, frame)
    big = np.kron(classes, np.ones((ref.TILE, ref.TILE), int))
    out, color = result.color, frame.color
    # Skip tiles keep C exactly; fast tiles average the taps along v_max with equal weights:
    # a uniform 12 px motion in x (half-vector 6 px) mixes only pixels of the same row.
    np.testing.assert_array_equal(out[big == ref.SKIP], color[big == ref.SKIP])
    fast = big == ref.FAST
    assert np.abs(out[fast] - color[fast]).max() > 0.05
    rows = np.nonzero(fast.any(axis=1))[0]
    for y in rows[:3]:
        xs = np.nonzero(fast[y])[0]
        lo, hi = color[y, xs[0] - 8 :, :3].min(), color[y, xs[0] - 8 :, :3].max()
        assert lo - 1e-6 <= out[y, xs, :3].min() and out[y, xs, :3].max() <= hi + 1e-6


def test_uniform_motion_takes_the_fast_path_everywhere(ctx, rng):
    frame = random_frame(rng, 64, 48)
    frame.motion[:] = (7.0, -3.0)
    result = bl.blur(ctx, frame, METHOD)
    assert (result.buffers["neighbors"][..., 3] == ref.FAST).all()
    assert_matches_twin(result, frame)


def test_rendered_scene_counts_its_tiles(ctx):
    frame = ctx.render(bl.scenes.get("teapot_pass"), (160, 90))
    result = bl.blur(ctx, frame, METHOD)
    radius = ref.max_radius_px(160, result.params["max_blur"])
    codes = ref.velocity_flatten(frame.depth, frame.motion, exposure=1.0, radius=radius)
    expected = ref.neighbor_dilate(ref.tile_minmax(codes), radius)[..., 3]
    gpu = result.buffers["neighbors"][..., 3]
    np.testing.assert_array_equal(gpu, expected)
    assert (gpu == ref.SKIP).sum() > 0 and (gpu == ref.SLOW).sum() > 0


def test_timings_name_every_pass(ctx, rng):
    assert_timings_name(
        ctx,
        rng,
        METHOD,
        [
            "velocity_flatten",
            "tile_minmax",
            "neighbor_dilate",
            "reconstruct",
        ],
    )
