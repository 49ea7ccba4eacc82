"""engine_unreal5 (docs/spec.md §17.7) on the GPU against bl.twins.unreal5: the tiles with a
second direction, the 7 x 7 scatter-as-gather and its four classes, the half-size colour, the
per-tile sample counts, the two-direction path on crossed motions, and the filter's promises:
still images unchanged, output inside the input range, no NaN, same seed same bits."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import assert_timings_name, random_frame
from filter_promises import PROMISES, assert_blurs_a_rendered_scene_as_its_twin, assert_matches_twin

import blurlab as bl
from blurlab.twins import polar_fixed_point as polar
from blurlab.twins import unreal as ue4
from blurlab.twins import unreal5 as ref

METHOD = "engine_unreal5"


@pytest.mark.parametrize(
    ("size", "params"),
    [
        ((160, 90), {}),
        ((160, 90), {"directions": 2}),
        ((97, 61), {"quality": 1, "max_blur": 12.0, "depth_extent": 0.05, "directions": 2}),
        ((130, 70), {"quality": 4, "max_blur": 30.0, "exposure": 2.5, "seed": 9}),
        ((40, 30), {"quality": 2, "max_blur": 1.0, "half_res_gather": 0, "directions": 2}),
    ],
)
def test_random_frames_match_reference(ctx, rng, size, params):
    frame = random_frame(rng, *size, k=10)
    result = bl.blur(ctx, frame, METHOD, **params)
    assert params.items() <= result.params.items()
    assert_matches_twin(result, frame)


@pytest.mark.parametrize("directions", [1, 2])
@pytest.mark.parametrize("scene", ["teapot_pass", "fan", "crossed_motions"])
def test_rendered_frames_match_reference(ctx, scene, directions):
    assert_blurs_a_rendered_scene_as_its_twin(ctx, METHOD, scene, directions=directions)


@pytest.mark.parametrize("directions", [1, 2])
def test_tile_passes_equal_their_twins(ctx, rng, directions):
    frame = random_frame(rng, 150, 90, k=10)
    result = bl.blur(ctx, frame, METHOD, max_blur=8.0, directions=directions)
    radius = ue4.max_radius_px(150, 8.0)
    codes = result.buffers["velocity"][..., :3].astype(np.float64)
    tiles = ref.tile_minmax2(codes)
    np.testing.assert_array_equal(result.buffers["tiles"], tiles)
    expected = ref.neighbor_dilate2(tiles, radius, directions)
    np.testing.assert_array_equal(result.buffers["neighbors"], expected)
    half = ref.half_color(frame.color)
    np.testing.assert_allclose(result.buffers["half_color"], half, atol=1e-6)


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


@pytest.mark.parametrize("promise", PROMISES.values(), ids=PROMISES.keys())
def test_the_filter_promises(ctx, rng, promise):
    promise(ctx, rng, METHOD)


def test_timings_name_every_pass(ctx, rng):
    passes = ["velocity_flatten", "tile_minmax", "neighbor_dilate", "half_color", "reconstruct"]
    assert_timings_name(ctx, rng, METHOD, passes)
    assert_timings_name(ctx, rng, METHOD, passes[:3] + passes[4:], half_res_gather=0)
