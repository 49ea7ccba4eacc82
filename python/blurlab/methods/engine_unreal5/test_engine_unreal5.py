"""engine_unreal5 (spec.md, docs/spec.md §17.7) on the GPU against its twin (twin.py, and
blurlab.twins.unreal5 pass by pass): the tiles with a second direction, the 7 x 7
scatter-as-gather with the scatter past it and its six classes, the half-size colour, the
half-resolution classes, the per-tile sample counts, the two-direction path on crossed motions;
the reconstruction over each class's tile list giving the bits of one dispatch over every tile;
and the filter's promises: still images unchanged, output inside the input range, no NaN, same
seed same bits."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import assert_matches_twin, assert_timings_name, random_frame

import blurlab as bl
from blurlab.methods.engine_unreal5 import method as unreal5
from blurlab.methods.passes import frame_textures
from blurlab.twins import polar_fixed_point as polar
from blurlab.twins import unreal as ue4
from blurlab.twins import unreal5 as ref

METHOD = "engine_unreal5"


def _fast_block(rng, width=320, height=64, speed=200.0):
    """A still random frame with one 16 px block moving `speed` px along x: its half-vector
    reaches 6 tiles at max_blur 40 (R = 128 px), past the 7 x 7."""
    frame = random_frame(rng, width, height)
    frame.motion[:] = 0.0
    frame.motion[16:32, 144:160] = (speed, 0.0)
    return frame


def _check_tiles(result, frame, max_blur, directions, quality=3, half_res_gather=1):
    width = frame.color.shape[1]
    radius = ue4.max_radius_px(width, max_blur)
    codes = result.buffers["velocity"][..., :3].astype(np.float64)
    tiles = ref.tile_minmax2(codes)
    np.testing.assert_array_equal(result.buffers["tiles"], tiles)
    expected = ref.neighbor_dilate2(tiles, radius, directions, quality, half_res_gather)
    np.testing.assert_array_equal(result.buffers["neighbors"], expected)
    counts = result.buffers["tile_counts"][0, :, 0].reshape(-1, 4)[:, 0]
    by_class = np.bincount(expected[..., 3].astype(int).ravel(), minlength=len(ref.CLASS_NAMES))
    np.testing.assert_array_equal(counts[: len(ref.CLASS_NAMES)], by_class)
    return expected, counts[unreal5.LISTS.index("far")]


@pytest.mark.parametrize("directions", [1, 2])
def test_tile_passes_equal_their_twins(ctx, rng, directions):
    frame = random_frame(rng, 150, 90, k=10)
    result = bl.blur(ctx, frame, METHOD, max_blur=8.0, directions=directions)
    _check_tiles(result, frame, 8.0, directions)
    half = ref.half_color(frame.color)
    np.testing.assert_allclose(result.buffers["half_color"], half, atol=1e-6)


@pytest.mark.parametrize("directions", [1, 2])
def test_the_dilation_scatters_velocities_past_the_neighbourhood(ctx, rng, directions):
    """A block whose blur reaches 6 tiles and more: the tiles 4 to 7 tiles away, which the 7 x 7
    gather cannot see, take its velocity from the scatter, as the twin says."""
    frame = _fast_block(rng)
    result = bl.blur(ctx, frame, METHOD, max_blur=40.0, directions=directions)
    neighbors, far = _check_tiles(result, frame, 40.0, directions)
    assert far == 1  # the block's tile alone
    row = neighbors[1, :, 3]  # the block is tile (1, 9); its blur spans x 9.5 ± 6.25 tiles
    assert (row[2:17] != ref.SKIP).all() and row[1] == ref.SKIP and row[17] == ref.SKIP
    assert (neighbors[1, [2, 3, 4, 5, 13, 14, 15, 16], 0] == neighbors[1, 9, 0]).all()
    assert_matches_twin(result, frame)


@pytest.mark.parametrize(
    "params",
    [
        {"max_blur": 8.0},
        {"max_blur": 8.0, "directions": 2, "half_res_gather": 0},
        {"max_blur": 60.0, "directions": 2},
        {"max_blur": 40.0, "quality": 4},
    ],
)
def test_tile_lists_give_the_bits_of_one_dispatch_over_every_tile(ctx, rng, params):
    """Each class's pass over its own list (indirect dispatch) against one dispatch in which
    every tile takes its class's path (docs/spec.md §9.3): the same bits on llvmpipe. NVIDIA's
    compiler contracts each class's own program differently from the one of every class (the
    H100 differs in the last bit of a few pixels), so there the two agree to float rounding."""
    frames = {
        8.0: lambda: random_frame(rng, 150, 90, k=10),
        60.0: lambda: random_frame(rng, 200, 120, k=40),  # half-resolution classes
        40.0: lambda: _fast_block(rng),  # the scatter
    }
    frame = frames[params["max_blur"]]()
    method = bl.method(METHOD)
    values = method.defaults(frame, **params)
    inputs = frame_textures(ctx, frame)
    listed, timings = unreal5.run(ctx, frame, inputs, values, "compute")
    one = {**values, "tile_dispatch": "one"}
    full, _ = unreal5.run(ctx, frame, inputs, one, "compute")
    counts = listed["tile_counts"].download()[0, :, 0].reshape(-1, 4)[:, 0]
    assert (counts[:-1] > 0).sum() >= 1
    if "llvmpipe" in ctx.info()["renderer"]:
        assert listed["color"].download().tobytes() == full["color"].download().tobytes()
    else:
        np.testing.assert_allclose(listed["color"].download(), full["color"].download(), atol=1e-5)
    assert any(name.startswith("reconstruct[") for name in timings)
    assert ctx.gl_errors() == []


def test_axis_gap_and_packing_hand_values():
    # Codes: 0 = +x, 512 = +y, 1024 = -x, 1536 = -y; 256 = 45°.
    gaps = ref.axis_gap([0, 0, 0, 0, 100, 2000], [512, 1024, 1536, 256, 1900, 30])
    assert gaps.tolist() == [512, 0, 512, 256, 248, 78]
    np.testing.assert_array_equal(ref.unpack(np.array(1500.0 * ref.PACK + 77)), [1500, 77])


def test_a_tile_keeps_a_second_direction_only_across_its_first():
    """One tile: a pixel moving 6 px in x, one 4 px in y, one 5 px at 30° from x."""
    codes = np.zeros((16, 16, 3))
    radius = 10.0
    for (y, x), v in {(0, 0): (6, 0), (3, 3): (0, 4), (5, 5): (4.33, 2.5)}.items():
        codes[y, x, :2] = polar.polar_codes(np.array(v, float), radius)
    tile = ref.tile_minmax2(codes)[0, 0]
    first, second = tile[:2], ref.unpack(tile[3])
    assert first[0] == polar.polar_codes(np.array([6.0, 0]), radius)[0]
    assert second[1] == 512 and second[0] == polar.polar_codes(np.array([0, 4.0]), radius)[0]
    assert tile[2] == 0  # its still pixels


def test_classes_on_crossed_motions(ctx):
    """Where the two bars cross, two directions make gather_2 tiles that one direction makes
    gather tiles; the still wall is skipped."""
    frame = ctx.render(bl.scenes.get("crossed_motions"), (160, 90))
    one = bl.blur(ctx, frame, METHOD, directions=1).buffers["neighbors"][..., 3]
    two = bl.blur(ctx, frame, METHOD, directions=2).buffers["neighbors"][..., 3]
    assert not (one == ref.GATHER_2).any()
    assert (two == ref.GATHER_2).sum() >= 2
    assert (two[one == ref.GATHER] != ref.SKIP).all() and (one == ref.SKIP).sum() > 20
    np.testing.assert_array_equal(one == ref.SKIP, two == ref.SKIP)


def test_uniform_motion_takes_the_uniform_path_everywhere(ctx, rng):
    frame = random_frame(rng, 64, 48)
    frame.motion[:] = (7.0, -3.0)
    result = bl.blur(ctx, frame, METHOD, directions=2)
    assert (result.buffers["neighbors"][..., 3] == ref.UNIFORM).all()
    assert_matches_twin(result, frame)


@pytest.mark.parametrize("motion", ["uniform", "ramp", "random"])
def test_long_blurs_gather_at_half_resolution(ctx, rng, motion):
    """Taps 8 px apart or more: uniform tiles become uniform_half, the others gather_half; the
    half-resolution gather and its composite match the twin, odd sizes included: blocks of one
    depth and nearly one velocity (ramp) blend, blocks of random depths (random) are mixed and
    gather each pixel."""
    frame = random_frame(rng, 99, 61, k=40)
    if motion == "uniform":
        frame.motion[:] = (80.0, 10.0)
    elif motion == "ramp":  # a still band, then motion growing along x, one depth
        frame.depth[:] = 3.0
        frame.motion[:] = 0.0
        frame.motion[..., 0] = np.where(np.arange(99) < 20, 0.0, 20.0 + 0.5 * np.arange(99))
    result = bl.blur(ctx, frame, METHOD, max_blur=50.0)
    kinds = result.buffers["neighbors"][..., 3]
    if motion == "uniform":
        assert (kinds == ref.UNIFORM_HALF).all()
    else:
        assert (kinds == ref.GATHER_HALF).sum() >= 4
    assert_matches_twin(result, frame)


def test_sample_counts_follow_the_tile_motion():
    radius = 100.0  # half-vectors of 0.4, 0.6, 1.2, 1.7 and 50 px: a pair per 1/2 px
    lengths = np.array([0.4, 0.6, 1.2, 1.7, 50.0]) / radius * polar.LENGTH_CODE_MAX
    assert ref.line_pairs(lengths, radius, 3).tolist() == [1, 2, 3, 4, 4]
    assert ref.line_pairs(lengths, radius, 4).tolist() == [1, 2, 3, 4, 8]
    assert ref.line_pairs(lengths, radius, 1).tolist() == [1, 2, 2, 2, 2]


def test_half_res_gather_reads_the_half_size_colour_for_long_blurs(ctx, rng):
    """A uniform 80 px motion (taps 10 px apart): with half_res_gather every tap reads the
    2 x 2 means, so the result changes; with it off the half-size colour is not made."""
    frame = random_frame(rng, 96, 64)
    frame.motion[:] = (80.0, 0.0)
    on = bl.blur(ctx, frame, METHOD, max_blur=50.0)
    off = bl.blur(ctx, frame, METHOD, max_blur=50.0, half_res_gather=0)
    assert "half_color" in on.buffers and "half_color" not in off.buffers
    assert np.abs(on.color - off.color).max() > 0.01
    assert_matches_twin(on, frame)
    assert_matches_twin(off, frame)


def test_timings_name_every_pass(ctx, rng):
    passes = ["velocity_flatten", "tile_minmax", "neighbor_dilate", "half_color"]
    classes = [f"reconstruct[{name}]" for name in ("skip", "uniform", "gather")]
    halves = ["reconstruct[uniform_half]", "reconstruct[gather_half]"]
    assert_timings_name(ctx, rng, METHOD, passes + classes + halves)
    assert_timings_name(ctx, rng, METHOD, passes[:3] + classes, half_res_gather=0)
    two = [*classes, "reconstruct[gather_2]"]
    assert_timings_name(ctx, rng, METHOD, passes[:3] + two, half_res_gather=0, directions=2)
    scatter = ["velocity_flatten", "tile_minmax", "tile_scatter[far]", "neighbor_dilate"]
    assert_timings_name(ctx, rng, METHOD, scatter + classes, half_res_gather=0, max_blur=80.0)
