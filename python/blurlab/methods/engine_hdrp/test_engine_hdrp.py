"""engine_hdrp (docs/spec.md §17.4) on the GPU against its twin (twin.py): the B10G11R11 codes of
the polar velocity and depth, the camera clamp modes, the min/max tiles, the 3 x 3 and scattered
neighbourhoods, each per-tile path, each class dispatched over its tile list with the bits of
one pass over every pixel, and the filter's promises: still images unchanged, output
inside the input range, no NaN, same seed same bits."""

from __future__ import annotations

import math

import numpy as np
import pytest
from conftest import assert_matches_twin, assert_timings_name, random_frame

import blurlab as bl
from blurlab.methods.engine_hdrp import twin as ref
from blurlab.methods.passes import frame_textures
from blurlab.twins import gathers
from blurlab.twins.polar_small_float import polar_codes, polar_decode
from blurlab.twins.small_float import UF10_MANTISSA, UF11_MANTISSA, largest_finite, quantize

METHOD = "engine_hdrp"


def classes_of(result) -> np.ndarray:
    return result.buffers["neighborhood"][..., 3].astype(int)


def test_velocity_and_tile_passes_equal_their_twins(ctx, rng):
    frame = random_frame(rng, 150, 90, k=10)
    result = bl.blur(ctx, frame, METHOD, maximum_velocity=15.0)
    setup = {k: result.params[k] for k in ref.SETUP_PARAMS}
    codes = ref.velocity_setup(frame.depth, frame.motion, None, **setup)
    gpu_codes = result.buffers["velocity"][..., :3]
    assert (gpu_codes == codes).all(axis=-1).mean() >= 0.999  # float32 atan may move a code
    tiles = ref.tile_min_max(gpu_codes.astype(np.float64), 32)
    np.testing.assert_array_equal(result.buffers["tiles"][..., :3], tiles)
    neighbors = ref.neighborhood(tiles)
    np.testing.assert_array_equal(result.buffers["neighborhood"][..., :3], neighbors)
    np.testing.assert_array_equal(classes_of(result), ref.classify(neighbors, 2.0, 0.5))


def test_scattered_neighbourhood_equals_its_twin(ctx):
    frame = ctx.render(bl.scenes.get("fan"), (160, 90))
    result = bl.blur(ctx, frame, METHOD, scatter=True)
    tiles = result.buffers["tiles"].astype(np.float64)
    assert tiles.shape[:2] == (6, 10)  # 16 px tiles
    expected = ref.scatter_neighborhood(tiles[..., :3], 16, 200.0)
    np.testing.assert_array_equal(result.buffers["neighborhood"][..., :3], expected)


def test_scatter_reaches_only_along_the_motion():
    tiles = np.zeros((1, 9, 3))
    tiles[..., 1] = 0.5  # still tiles: length 0, turn 1/2
    tiles[0, 4, :2] = polar_codes(np.array([64.0, 0.0]))  # 4 tiles of 16 px along +x
    dilated = ref.scatter_neighborhood(tiles, 16, 200.0)
    assert (dilated[0, 2:7, 0] == 64.0).all()  # ±2 tiles: half the length on each side
    assert (dilated[0, [0, 1, 7, 8], 0] == 0.0).all()
    column = np.zeros((9, 1, 3))
    column[..., 1] = 0.5
    column[4, 0, :2] = polar_codes(np.array([64.0, 0.0]))
    assert (ref.scatter_neighborhood(column, 16, 200.0)[[3, 5], 0, 0] == 0.0).all()  # not across


def test_small_floats_round_as_hand_values_say():
    uf11 = quantize([1.0, 1.0078125, 1.0234375, 200.3, 65024.0, 1e6, np.inf], UF11_MANTISSA)
    # 1 + 2^-7 lies halfway between 1 and 1 + 2^-6: ties go to the even mantissa (1); 1 + 3·2^-7
    # lies halfway between 1 + 2^-6 and 1 + 2^-5: the even one is 1 + 2^-5.
    assert list(uf11) == [1.0, 1.0, 1.03125, 200.0, 65024.0, 65024.0, np.inf]
    assert largest_finite(UF11_MANTISSA) == 65024.0 and largest_finite(UF10_MANTISSA) == 64512.0
    uf10 = quantize([3.3, 0.0, -2.0, np.nan, 2.0**-16 * 1.3], UF10_MANTISSA)
    # 3.3 = 2·1.65, step 2/32: 3.3125 = 2·(1 + 21/32) is nearest; 1.3·2^-16: a denormal, step 2^-19
    assert list(uf10) == [3.3125, 0.0, 0.0, 0.0, 2.0**-16 * 1.25]


def test_polar_codes_hold_length_and_turn():
    codes = polar_codes(np.array([[3.0, 4.0], [0.0, 0.0], [-10.0, 0.0], [0.0, -7.0]]))
    turn = math.atan2(4, 3) / (2 * math.pi) + 0.5  # 0.6476: step 2^-7 in [0.5, 1)
    assert codes[0, 0] == 5.0 and codes[0, 1] == round(turn * 128) / 128
    assert list(codes[1]) == [0.0, 0.5]  # zero motion: no direction, u = 1/2
    assert list(codes[2]) == [10.0, 1.0]  # atan2(0, -10) = π
    assert list(codes[3]) == [7.0, 0.25]
    np.testing.assert_allclose(polar_decode(codes[3]), [0.0, -7.0], atol=1e-12)


def test_maximum_velocity_clamps_the_stored_length(ctx):
    frame = bl.Frame(
        color=np.ones((32, 64, 4), np.float32),
        depth=np.full((32, 64), 5.0, np.float32),
        motion=np.tile(np.float32([300.0, 400.0]), (32, 64, 1)),
    )
    lengths = bl.blur(ctx, frame, METHOD).buffers["velocity"][..., 0]
    assert (lengths == 200.0).all()  # 500 px clamped to the default 200
    lengths = bl.blur(ctx, frame, METHOD, maximum_velocity=37.0).buffers["velocity"][..., 0]
    assert (lengths == 37.0).all()  # 37 is an 11-bit float: 32·(1 + 10/64)
    depth = bl.blur(ctx, frame, METHOD).buffers["velocity"][..., 2]
    assert (depth == 5.0).all()


def test_screen_fraction_clamp_hand_values():
    v = np.array([[160.0, 0.0], [0.0, 9.0], [80.0, 45.0]])
    clamped = ref.clamp_screen_fraction(v, 0.5, (160, 90))
    np.testing.assert_allclose(clamped[0], [80.0, 0.0])  # 1 screen width -> half of it
    np.testing.assert_allclose(clamped[1], [0.0, 9.0])  # 0.1 screen height: inside
    np.testing.assert_allclose(clamped[2], np.array([80.0, 45.0]) * 0.5 / math.sqrt(0.5))


def test_camera_clamps_split_the_orbiting_cameras_motion(ctx):
    frame = ctx.render(bl.scenes.get("camera_yaw"), (160, 90))  # the camera orbits: it turns
    whole = gathers.camera_motion(frame.depth, frame.camera, frame.size)  # and it moves
    rotation = gathers.camera_rotation_motion(frame.camera, frame.size)
    size = np.array([160.0, 90.0])

    def velocity(**params):
        result = bl.blur(ctx, frame, METHOD, **params)
        return polar_decode(result.buffers["velocity"][..., :2].astype(np.float64)), result

    def near(a, b):  # within the polar codes' precision: 2^-7 of the length, 1.4° of turn
        tolerance = 0.04 * np.linalg.norm(b, axis=-1) + 0.05
        return (np.linalg.norm(a - b, axis=-1) <= tolerance).mean()

    free, _ = velocity()
    assert near(free, frame.motion) >= 0.999
    assert np.linalg.norm(rotation / size, axis=-1).max() > 0.05  # the turn alone
    # Rotation clamped to 0: only the camera's translation is left (every point is still).
    assert (
        near(velocity(camera_clamp_mode="rotation", rotation_clamp=0.0)[0], whole - rotation) > 0.99
    )
    # ... to 0.01 of the screen: the translation plus at most that much.
    clamped, _ = velocity(camera_clamp_mode="rotation", rotation_clamp=0.01)
    extra = np.linalg.norm((clamped - (whole - rotation)) / size, axis=-1)
    assert (extra <= 0.01 + 0.003).mean() > 0.99 and extra.max() > 0.009
    # Every camera motion clamped to 0, or camera blur off: the still world keeps its color.
    for params in (
        {"camera_clamp_mode": "full", "motion_vector_clamp": 0.0},
        {"camera_motion_blur": False},
    ):
        v, result = velocity(**params)
        assert np.linalg.norm(v, axis=-1).max() < 0.05
        assert (classes_of(result) == ref.EARLY_OUT).all()
        assert result.color.tobytes() == frame.color.tobytes()


def test_translation_clamp_and_camera_blur_off_still_the_world(ctx):
    frame = ctx.render(bl.scenes.get("vehicle"), (160, 90))
    camera = gathers.camera_motion(frame.depth, frame.camera, frame.size)
    rotation = gathers.camera_rotation_motion(frame.camera, frame.size)
    np.testing.assert_allclose(rotation, 0.0, atol=1e-6)  # the following camera only moves
    world = np.linalg.norm(frame.motion - camera, axis=-1) < 0.01  # still points
    moving_camera = world & (np.linalg.norm(camera, axis=-1) > 2.0)
    assert moving_camera.mean() > 0.3

    def lengths(**params):
        return bl.blur(ctx, frame, METHOD, **params).buffers["velocity"][..., 0]

    assert lengths()[moving_camera].min() > 2.0
    assert lengths(camera_motion_blur=False)[moving_camera].max() < 0.05
    clamped = lengths(camera_clamp_mode="translation", translation_clamp=0.0)
    assert clamped[moving_camera].max() < 0.05


def test_each_tile_path_is_taken_and_does_what_it_says(ctx, rng):
    h, w = 96, 192  # 3 x 6 tiles of 32 px
    color = rng.random((h, w, 4), dtype=np.float32)
    motion = np.zeros((h, w, 2), np.float32)
    motion[:, 64:] = (10.0, 0.0)  # tile columns 2-5 move uniformly, 0-1 are still
    motion[:32, 128:130] = (3.0, 0.0)  # a slower stripe in tile (0, 4): 3 < 0.5 x 10
    frame = bl.Frame(color=color, depth=np.full((h, w), 4.0, np.float32), motion=motion)
    result = bl.blur(ctx, frame, METHOD, minimum_velocity=2.0, fast_ratio=0.5)
    classes = classes_of(result)
    # Column 0 sees only still tiles; columns 1 and 2 see still and moving ones; columns 3-5
    # see only moving ones, fast where the stripe's tile is not among them (the bottom row).
    expected = np.array(
        [
            [ref.EARLY_OUT, ref.SLOW, ref.SLOW, ref.SLOW, ref.SLOW, ref.SLOW],
            [ref.EARLY_OUT, ref.SLOW, ref.SLOW, ref.SLOW, ref.SLOW, ref.SLOW],
            [ref.EARLY_OUT, ref.SLOW, ref.SLOW, ref.FAST, ref.FAST, ref.FAST],
        ]
    )
    np.testing.assert_array_equal(classes, expected)
    assert_matches_twin(result, frame)
    motion[:32, 128:130] = (10.0, 0.0)  # uniform: columns 3-5 all fast
    frame = bl.Frame(color=color, depth=frame.depth, motion=motion)
    result = bl.blur(ctx, frame, METHOD, minimum_velocity=2.0, fast_ratio=0.5)
    assert (classes_of(result)[:, 3:] == ref.FAST).all()
    assert_matches_twin(result, frame)
    out = result.color
    assert out[:, :32].tobytes() == frame.color[:, :32].tobytes()  # early-out: C itself
    # A fast pixel: C(X) and n = 8 taps along (10, 0) at t = (i + j)/8 - 1/2, equal weights.
    x, y = 150, 40
    j = bl.twins.rand(x, y, 0)
    taps = [int(math.floor(x + 0.5 + 10.0 * ((i + j) / 8 - 0.5))) for i in range(8)]
    expected = (frame.color[y, x] + sum(frame.color[y, t] for t in taps)) / 9
    np.testing.assert_allclose(out[y, x], expected, atol=1e-6)


def test_sample_count_keeps_taps_a_pixel_apart():
    assert list(ref.tap_count(np.array([0.0, 3.9, 7.0, 200.0]), 8)) == [1, 3, 7, 8]


@pytest.mark.parametrize("scatter", [False, True])
def test_tile_lists_give_the_bits_of_one_pass_over_every_pixel(ctx, rng, scatter):
    """Each class's reconstruction over its own list (indirect dispatch, 32 px tiles covered by
    a 16 x 16 work group in four blocks; 16 px with scatter) against one pass in which every
    pixel takes its tile's class; the lists hold the twin's classes (docs/spec.md §9.3)."""
    frame = random_frame(rng, 250, 90, k=10)
    frame.motion[:, :96] = 0.0  # early-out tiles on the left, random motion in the middle
    frame.motion[:, 160:] = (9.0, 2.0)  # fast tiles on the right
    values = bl.method(METHOD).defaults(frame, scatter=scatter)
    inputs = frame_textures(ctx, frame)
    listed, timings = bl.method(METHOD).run(ctx, frame, inputs, values, "compute")
    one = {**values, "tile_dispatch": "one"}
    full, _ = bl.method(METHOD).run(ctx, frame, inputs, one, "compute")
    classes = listed["neighborhood"].download()[..., 3].astype(int)
    counts = listed["tile_counts"].download()[0, ::4, 0]
    np.testing.assert_array_equal(counts, np.bincount(classes.ravel(), minlength=3))
    assert (counts > 0).all()
    assert listed["color"].download().tobytes() == full["color"].download().tobytes()
    assert [k for k in timings if k.startswith("reconstruct")] == [
        f"reconstruct[{name}]" for name in ref.CLASS_NAMES
    ]
    assert ctx.gl_errors() == []


def test_timings_name_every_pass(ctx, rng):
    classes = [f"reconstruct[{name}]" for name in ref.CLASS_NAMES]
    assert_timings_name(
        ctx, rng, METHOD, ["velocity_setup", "tile_min_max", "neighborhood", *classes]
    )
