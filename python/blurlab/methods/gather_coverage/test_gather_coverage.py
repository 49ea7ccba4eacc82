"""gather_coverage (spec.md, docs/spec.md §17.6) on the GPU against its twin (twin.py, and
blurlab.twins.coverage part by part): the whole filter on random and rendered frames, its parts
on hand values (trail reach, family overlap, tap layout, sizes relative to the height, coverage
of a bar over a still background), and the filter's promises: still images unchanged, output
inside the input range, no NaN, same seed same bits."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import assert_matches_twin, assert_timings_name, random_frame
from filter_promises import (
    assert_finite_for_motion_scale,
    assert_inside_the_input_range,
    two_sided_frame,
)

import blurlab as bl
from blurlab.methods.coverage import (
    FILM_LAYOUT,
    FILM_VARIANTS,
    GATHER_LAYOUT,
    GATHER_VARIANTS,
    tap_plan,
)
from blurlab.methods.coverage import tile_lines as coverage_tile_lines
from blurlab.methods.gather_coverage import method as declared
from blurlab.methods.passes import frame_textures
from blurlab.twins import coverage as ref
from blurlab.twins import eevee as eevee_twin
from blurlab.twins import film
from blurlab.twins.eevee import resolve_reach_keys
from blurlab_bench.taps import tap_counts

METHOD = "gather_coverage"
# The tile passes of the default dilation, by scatter with the keys resolved in the gather
# (tests/test_scatter_dilation.py).
TILE_PASSES = ["reach_keys_clear", "tile_flatten"]
# the gather over the lists of still and moving blocks (§17.6.2)
GATHER_PASSES = ["block_classify", "gather[still]", "gather[moving]"]


# Each lever of "just enough taps" (§17.6) alone and all together, the film through the taps
# with them.
LEVERS = [
    {"tap_spacing": 4.0},
    {"early_exit": 3.0},
    {"uniform_tolerance": 1.0},
    {"half_res_above": 3.0},
    {"tap_spacing": 2.0, "early_exit": 2.0, "uniform_tolerance": 1.0, "half_res_above": 3.0},
    {"tap_spacing": 2.0, "uniform_tolerance": 1.0, "film_filter": 0.5, "film_through_taps": True},
    {"half_res_above": 2.0, "film_filter": 0.5},
]


@pytest.mark.parametrize("params", LEVERS)
@pytest.mark.parametrize("scene", ["teapot_pass", "camera_yaw", "crossing"])
def test_just_enough_taps_match_reference(ctx, scene, params):
    frame = ctx.render(bl.scenes.get(scene), (160, 90))
    result = bl.blur(ctx, frame, METHOD, **params)
    assert_matches_twin(result, frame)


def test_per_tile_samples_follow_the_tiles_longer_line():
    assert ref.tile_samples([0.5, 3.0, 3.1, 40.0, 1e4], 16, 3.0).tolist() == [2, 2, 2, 14, 16]
    assert ref.tile_samples([0.5, 40.0], 8, 0.0).tolist() == [8, 8]


def test_the_levers_choose_fewer_taps_and_the_fast_path(ctx):
    frame = ctx.render(bl.scenes.get("camera_yaw"), (160, 90))
    full = tap_plan(frame).taps_per_pixel()
    assert set(np.unique(full)) <= {0, 2 * bl.method(METHOD).params["samples"].default}
    fewer = tap_plan(frame, tap_spacing=6.0).taps_per_pixel()
    assert (fewer <= full).all() and fewer.mean() < full.mean()
    assert ((fewer == 0) == (full == 0)).all()  # the same pixels exit early
    later = tap_plan(frame, early_exit=20.0).taps_per_pixel()
    assert (later == 0).mean() > (full == 0).mean()
    assert not tap_plan(frame).fast.any()
    assert tap_plan(frame, uniform_tolerance=1.0).fast.mean() > 0.2  # the camera turns: uniform


def test_a_long_quad_takes_its_top_left_pixels_gather(ctx):
    frame = ctx.render(bl.scenes.get("camera_yaw"), (97, 61))  # odd: the last quads are cut
    result = bl.blur(ctx, frame, METHOD, half_res_above=2.0)
    assert list(result.timings) == [*TILE_PASSES, "gather_half", "gather"]
    plan = tap_plan(frame, result, half_res_above=2.0)
    assert 0.2 < plan.half.mean() < 1
    out = result.color
    y, x = np.nonzero(plan.half)
    np.testing.assert_array_equal(out[y, x], out[ref.quad_corner(y), ref.quad_corner(x)])
    # a quad's taps are shared by its four pixels
    taps, full = plan.taps_per_pixel(), tap_plan(frame).taps_per_pixel()
    assert taps[plan.half].sum() < 0.3 * full[plan.half].sum()
    assert (taps[~plan.half] == full[~plan.half]).all()


def test_the_benchmark_counts_taps_per_pixel_on_hand_values():
    counts = tap_counts(np.array([[0, 0, 0, 4], [16, 16, 16, 16], [0, 2, 2, 8]]))
    expected = {"mean": 80 / 12, "p50": 3.0, "p90": 16.0, "max": 16.0, "none": 4 / 12}
    assert counts == pytest.approx(expected)


def test_an_early_exit_keeps_the_pixels_colour(ctx):
    frame = ctx.render(bl.scenes.get("teapot_pass"), (160, 90))
    out = bl.blur(ctx, frame, METHOD, early_exit=12.0).color
    still = tap_plan(frame, early_exit=12.0).taps == 0
    assert still.mean() > 0.1
    assert (out[still] == frame.color[still]).all()


def test_uniform_motion_takes_the_fast_path_and_stays_close_to_the_coverage_weights(ctx, rng):
    # Everything moves by the same 6 px: the plain gather of the fast path sees the same trails
    # as the coverage weights.
    color = np.repeat(np.linspace(0, 1, 96, dtype=np.float32)[None, :, None], 48, 0)
    color = np.concatenate([np.repeat(color, 3, -1), np.ones((48, 96, 1), np.float32)], -1)
    motion = np.zeros((48, 96, 2), np.float32)
    motion[..., 0] = 6.0
    frame = bl.Frame(color, np.full((48, 96), 5.0, np.float32), motion)
    assert tap_plan(frame, uniform_tolerance=0.5).fast.all()
    fast = bl.blur(ctx, frame, METHOD, uniform_tolerance=0.5).color
    full = bl.blur(ctx, frame, METHOD).color
    inside = np.s_[:, 12:-12]
    assert np.abs(fast[inside] - full[inside]).max() < 0.01
    # a ramp's mean is its middle, within a quarter of a pixel's step (taps land on whole pixels)
    assert np.abs(fast[inside] - frame.color[inside]).max() < 0.25 / 95


def test_tile_passes_are_engine_eevees_at_this_methods_sizes_and_reach(ctx, rng):
    frame = two_sided_frame(rng, 150, 90, reach=60.0)
    result = bl.blur(ctx, frame, METHOD, tile_percent=10.0, max_blur=40.0, exposure=0.8)
    s, limit = ref.tile_size(90, 10.0), ref.max_blur_px(90, 40.0)
    assert (s, limit) == (9, 36.0)
    prev = eevee_twin.scaled_motion(frame.motion_prev, 0.8)
    next_ = eevee_twin.scaled_motion(frame.motion_next, 0.8)
    steps = ref.TILE_LENGTH_STEPS
    np.testing.assert_allclose(
        result.buffers["tiles"],
        eevee_twin.tile_flatten(prev, next_, s, steps),
        rtol=1e-6,
        atol=1e-5,
    )
    tiles = result.buffers["tiles"].astype(np.float64)
    dilated = eevee_twin.tile_dilate(tiles, s, limit, steps, ref.JITTER_REACH)
    # the jitter's quarter tile widens some reaches: the grid is not engine_eevee's
    assert (np.abs(dilated - eevee_twin.tile_dilate(tiles, s, limit, steps)) > 1e-3).any()
    # The gather resolves the scatter dilation's keys itself (the default): decode them as it does
    keys = result.buffers["reach_keys"]
    resolved = eevee_twin.resolve_reach_keys(keys, result.buffers["tiles"])
    np.testing.assert_allclose(resolved, dilated, rtol=1e-6, atol=1e-5)


def test_near_equal_lengths_tie_and_go_to_the_first_tile(ctx):
    # The moire gap's cause (docs/engines.md): a turning disc moves many pixels and tiles
    # almost equally fast, and exact lengths that float rounding orders differently on the GPU
    # and in the twin picked other tiles, so whole tiles differed. Lengths compare in steps of
    # 1/16 px: here the later pixel is longer by 1e-5 px (exactly, not only by rounding), and
    # the first still wins, on the GPU and in the twin.
    height, width = 16, 16  # 8 px tiles (tile_percent 50), a 2 x 2 grid
    prev = np.zeros((height, width, 2), np.float32)
    prev[0, 0] = (3.0, 4.0)  # length 5, first in row order
    prev[3, 5] = (0.0, 5.00001)  # length 5.00001, later
    frame = bl.Frame(
        np.zeros((height, width, 4), np.float32),
        np.ones((height, width), np.float32),
        2 * prev,
        motion_prev=prev,
        motion_next=prev.copy(),
    )
    tiles = bl.blur(ctx, frame, METHOD, tile_percent=50.0).buffers["tiles"]
    assert tiles[0, 0].tolist() == [3.0, 4.0, 3.0, 4.0]
    twin_tiles = eevee_twin.tile_flatten(prev, prev, 8, ref.TILE_LENGTH_STEPS)
    assert twin_tiles[0, 0].tolist() == [3.0, 4.0, 3.0, 4.0]
    # engine_eevee keeps EEVEE's exact comparison: the longer one wins
    exact = eevee_twin.tile_flatten(prev, prev, 8)
    assert exact[0, 0, 1] == np.float32(5.00001)
    # A length a full step longer still wins
    assert eevee_twin.pick_key(np.float32(5.0625), 16) > eevee_twin.pick_key(np.float32(5.0), 16)


def test_sizes_follow_the_image_height():
    assert ref.tile_size(1080, 3.0) == 32  # 32.4 px: EEVEE's 32 px tile at 1080p
    assert ref.tile_size(360, 3.0) == 11
    assert ref.tile_size(90, 3.0) == 8  # 2.7 px, raised to the smallest tile
    assert ref.max_blur_px(1080, 30.0) == 324.0
    assert ref.max_blur_px(90, 30.0) == 27.0


def test_trail_reach_on_hand_values():
    v = np.array([10.0, 0.0])  # moving 10 px towards X from +x
    straight = np.zeros(2)
    cases = {
        (4.0, 0.0): 1.0,  # on the trail
        (10.5, 0.0): 0.5,  # half a pixel past its end: 10 + 1 - 10.5
        (12.0, 0.0): 0.0,  # beyond it
        (4.0, 1.5): 1.0,  # 1.5 px across: still over X (ACROSS + 0.05 * 10 = 2.5 px wide)
        (4.0, 2.0): 0.5,  # 2 px across: half
        (4.0, 2.5): 0.0,  # beyond it
        (-1.0, 0.0): 0.0,  # behind the trail's start
    }
    for d, expected in cases.items():
        assert ref.trail_reaches(np.array(d), v, straight) == pytest.approx(expected)
    long_trail = np.array([40.0, 0.0])  # 4 px wide
    assert ref.trail_reaches(np.array([20.0, 3.0]), long_trail, straight) == pytest.approx(1.0)
    assert ref.trail_reaches(np.array([20.0, 4.5]), long_trail, straight) == pytest.approx(0.0)
    still = np.zeros(2)
    assert ref.trail_reaches(np.array([0.0, 0.0]), still, straight) == pytest.approx(1.0)
    assert ref.trail_reaches(np.array([2.0, 0.0]), still, straight) == 0.0


def test_a_bent_trail_is_the_parabola_through_its_three_positions():
    v, bend = np.array([10.0, 0.0]), np.array([0.0, 4.0])
    # halfway along, the parabola lies τ(1 - τ)·bend = 1 px off the chord
    assert ref.trail_reaches(np.array([5.0, 1.0]), v, bend) == pytest.approx(1.0)
    assert ref.trail_reaches(np.array([5.0, 3.0]), v, bend) == pytest.approx(0.5)
    assert ref.trail_reaches(np.array([5.0, -2.0]), v, bend) == 0.0
    assert ref.trail_reaches(np.array([5.0, -2.0]), v, np.zeros(2)) == pytest.approx(0.5)
    # at its ends it meets the chord
    assert ref.trail_reaches(np.array([10.0, 0.0]), v, bend) == pytest.approx(1.0)


def test_own_taps_follow_the_arc_of_a_turning_pixel():
    # X at radius 10 turning 0.3 rad each half-shutter about the origin
    def at(angle):
        return 10 * np.array([np.cos(angle), np.sin(angle)])

    x = at(0.0)
    prev, next_ = x - at(-0.3), at(0.3) - x
    bend = (next_ - prev) / 2
    ts = np.linspace(0.0, 1.0, 11)
    bent = x + ref.tap_offset_along(prev, bend, ts)
    straight = x + ref.tap_offset_along(prev, np.zeros(2), ts)
    assert bent[-1] == pytest.approx(at(0.3))  # where X is at the shutter's close
    assert np.abs(np.linalg.norm(bent, axis=-1) - 10).max() < 0.05  # on the circle
    assert np.abs(np.linalg.norm(straight, axis=-1) - 10).max() > 0.4  # the chord is not


def test_family_overlap_on_hand_values():
    assert ref.family_overlap(np.array([10.0, 0.0]), np.array([3.0, 0.0])) == pytest.approx(1)
    # opposite lines sample opposite sides of X: no trail twice
    assert ref.family_overlap(np.array([10.0, 0.0]), np.array([-3.0, 0.0])) == 0.0
    assert ref.family_overlap(np.array([10.0, 0.0]), np.array([0.0, 4.0])) == pytest.approx(0)
    assert ref.family_overlap(np.array([3.0, 3.0]), np.array([2.0, 0.0])) == pytest.approx(
        np.sqrt(0.5)
    )
    # X still: both families sample the tile's line
    assert ref.family_overlap(np.array([10.0, 0.0]), np.array([0.5, 0.0])) == 1.0


def test_tap_offsets_interleave_families_and_sides():
    offsets = [ref.tap_offset(0.1, family, side) for side in (0, 1) for family in (0, 1)]
    assert offsets == pytest.approx([0.1, 0.6, 0.35, 0.85])


def test_tap_layout_alternates_families():
    assert ref.tap_layout(5) == [(0, 0, 3), (1, 0, 2), (0, 1, 3), (1, 1, 2), (0, 2, 3)]


def bar_frame(width=96, bar=(40, 48), speed=32.0):
    """A white bar `speed` px/shutter to the right over a still grey wall, 48 rows alike."""
    color = np.full((48, width, 4), 0.2, np.float32)
    color[..., 3] = 1
    depth = np.full((48, width), 10.0, np.float32)
    motion = np.zeros((48, width, 2), np.float32)
    color[:, bar[0] : bar[1], :3] = 1.0
    depth[:, bar[0] : bar[1]] = 5.0
    motion[:, bar[0] : bar[1], 0] = speed
    return bl.Frame(color, depth, motion)


def test_a_still_post_in_front_does_not_thin_the_object_moving_behind_it(ctx):
    # A wide box (32 px) moving 16 px behind a still post (4 px): beside the post the box
    # covers its pixels all the shutter, so they keep the box's color; the taps that land on
    # the post are left out of the coverage estimate instead of counting as uncovered.
    color = np.full((48, 96, 4), 0.2, np.float32)
    color[..., 3] = 1
    depth = np.full((48, 96), 10.0, np.float32)
    motion = np.zeros((48, 96, 2), np.float32)
    color[:, 24:56, :3], depth[:, 24:56], motion[:, 24:56, 0] = 0.6, 5.0, 16.0
    color[:, 44:48, :3], depth[:, 44:48], motion[:, 44:48] = 1.0, 2.0, 0.0
    out = bl.blur(ctx, bl.Frame(color, depth, motion), METHOD, samples=16, max_blur=100.0)
    beside = out.color[:, [38, 39, 40, 41, 50, 51], 0]
    assert beside.mean() == pytest.approx(0.6, abs=0.03)
    assert out.color[:, 44:48, 0].min() == pytest.approx(1.0)  # the post stays sharp


def test_a_bar_covers_its_trail_by_its_width_over_its_motion(ctx):
    # A bar 8 px wide moving 32 px: a pixel its trail crosses is covered 8/32 of the shutter,
    # its own pixels too (the wall behind shows the rest). The box-shutter truth is 0.2 +
    # 0.8 * 1/4 = 0.4 in the middle of the trail.
    frame = bar_frame()
    out = bl.blur(ctx, frame, METHOD, samples=32, max_blur=100.0).color[..., 0]
    middle = out[:, 36:52].mean()  # within 12 px of the bar's center at mid-shutter
    assert middle == pytest.approx(0.4, abs=0.05)
    assert out[:, 44].mean() < 0.55  # the bar's own pixels: not left sharp (1.0)
    assert out[:, :10].max() == pytest.approx(0.2)  # beyond the trail: the wall untouched


def test_colour_past_display_white_matches_reference(ctx, rng):
    # most colours far above 1: the hot share (§17.6) weighs on nearly every tap
    frame = two_sided_frame(rng, 97, 61)
    frame.color[..., :3] *= 40.0
    assert_matches_twin(bl.blur(ctx, frame, METHOD, samples=9, seed=3), frame)


def test_an_emitter_saturates_only_the_rows_its_pixels_cross(ctx):
    # An emitter of radiance 200, 4 rows tall, moving 12 px a half-shutter to the right over a
    # still wall. The rows beside it are never crossed (its pixels pass them edge to edge), so
    # they stay under display white; its own rows are saturated along the trail.
    color = np.full((48, 96, 4), 0.2, np.float32)
    color[..., 3] = 1
    depth = np.full((48, 96), 10.0, np.float32)
    motion = np.zeros((48, 96, 2), np.float32)
    color[20:24, 40:48, :3], depth[20:24, 40:48], motion[20:24, 40:48, 0] = 200.0, 5.0, 24.0
    frame = bl.Frame(color, depth, motion)
    result = bl.blur(ctx, frame, METHOD, samples=16, max_blur=100.0)
    out = result.color[..., 0]
    assert out[20:24, 36:52].min() > 1.0
    assert out[[19, 24], :].max() < 1.0
    assert_matches_twin(result, frame)


def test_a_pixel_at_a_tiles_edge_reads_the_streak_beside_it(ctx):
    # A block moving 9 px a half-shutter down the first column of an 8 px tile. The jittered
    # lookup sends some pixels of that column to the tile on their left, whose reach holds the
    # streak's motion only because it is widened by the jitter's quarter tile.
    motion = np.zeros((64, 64, 2), np.float32)
    motion[28:32, 16:20, 1] = 18.0
    color = np.full((64, 64, 4), 0.5, np.float32)
    frame = bl.Frame(color, np.full((64, 64), 10.0, np.float32), motion)
    params = {"tile_percent": 12.5, "max_blur": 50.0}
    result = bl.blur(ctx, frame, METHOD, **params)
    lines = coverage_tile_lines(frame, result, **params)
    crossed = (slice(21, 39), 16)  # rows the block's pixels cross in column 16
    for line in lines.lines:
        assert np.linalg.norm(line[crossed], axis=-1).min() > 8.0
    y, x = np.mgrid[0:64, 0:64]
    ty, tx = eevee_twin.lookup_tile(x, y, 8, result.params["seed"], (8, 8), ref.JITTER_SALTS)
    assert (tx[crossed] == 1).any()  # some of them read the tile on the left
    narrow = eevee_twin.tile_dilate(result.buffers["tiles"].astype(np.float64), 8, 32.0, 16.0)
    assert (np.linalg.norm(narrow[ty, tx][crossed][..., :2], axis=-1) == 0).any()


def test_timings_name_every_pass(ctx, rng):
    assert_timings_name(ctx, rng, METHOD, [*TILE_PASSES, *GATHER_PASSES])
    filtered = bl.blur(ctx, random_frame(rng, 64, 36), METHOD, film_filter=0.5)
    two_passes = FILM_LAYOUT.chosen() == "separable"
    passes = ["film_rows", "film_columns"] if two_passes else ["film"]
    assert list(filtered.timings) == [*TILE_PASSES, *GATHER_PASSES, *passes]


def test_the_film_filter_spreads_a_point_by_its_gaussian(ctx):
    # A still frame (every tile exits early) with one bright pixel: the film filter alone acts,
    # and each neighbour gets the normalised Gaussian weight of its distance.
    color = np.zeros((21, 21, 4), np.float32)
    color[10, 10] = 1.0
    frame = bl.Frame(color, np.ones((21, 21), np.float32), np.zeros((21, 21, 2), np.float32))
    out = bl.blur(ctx, frame, METHOD, film_filter=0.5).color[..., 0]
    offsets = np.arange(-2, 3)  # ceil(3 * 0.5) = 2 px each way
    weights = np.exp(-(offsets[:, None] ** 2 + offsets[None, :] ** 2) / (2 * 0.5**2))
    assert out[8:13, 8:13] == pytest.approx(weights / weights.sum(), abs=1e-6)
    assert out.sum() == pytest.approx(1.0, abs=1e-5)  # nothing lost, nothing beyond 2 px
    assert out[10, 10] == pytest.approx(0.6187, abs=1e-3)
    unfiltered = bl.blur(ctx, frame, METHOD).color
    assert unfiltered.tobytes() == color.tobytes()  # 0: no film filter


def test_the_film_filter_keeps_a_flat_image_and_the_input_range(ctx, rng):
    frame = two_sided_frame(rng, 80, 60)
    frame.color[..., :3] = frame.color[..., :3] * 0.5 + 0.25
    out = bl.blur(ctx, frame, METHOD, film_filter=2.0, max_blur=40.0).color
    assert out[..., :3].min() >= 0.25 - 1e-6 and out[..., :3].max() <= 0.75 + 1e-6
    flat = bl.Frame(
        np.full((30, 40, 4), 0.3, np.float32), frame.depth[:30, :40], frame.motion[:30, :40]
    )
    assert bl.blur(ctx, flat, METHOD, film_filter=1.0).color == pytest.approx(0.3, abs=1e-6)


@pytest.mark.parametrize("variant", list(FILM_VARIANTS))
@pytest.mark.parametrize("sigma", [0.3, 1.3, 4.0])
def test_the_film_pass_equals_its_twin_across_group_edges(ctx, rng, variant, sigma):
    # A still frame: every tile exits early, so the film filter alone acts. 37 x 23 cuts the
    # 16 x 16 groups (separable_shared's aprons reach past the image on every side); σ = 4
    # reaches 12 px, wider than the image's 23 rows, so every clamp is taken. NaN reads as 0.
    color = rng.random((23, 37, 4), dtype=np.float32)
    color[5, 7, 1] = np.nan
    frame = bl.Frame(color, np.ones((23, 37), np.float32), np.zeros((23, 37, 2), np.float32))
    with FILM_LAYOUT.use(variant):
        out = bl.blur(ctx, frame, METHOD, film_filter=sigma)
    passes = ["film_rows", "film_columns"] if variant == "separable" else ["film"]
    assert list(out.timings) == [*TILE_PASSES, *GATHER_PASSES, *passes]
    np.testing.assert_allclose(out.color, film.film_filter(color, sigma), atol=2e-6)


@pytest.mark.parametrize("variant", list(FILM_VARIANTS))
def test_every_film_layout_matches_the_twin_after_the_gather(ctx, rng, variant):
    frame = two_sided_frame(rng, 160, 90)
    with FILM_LAYOUT.use(variant):
        result = bl.blur(ctx, frame, METHOD, film_filter=0.5)
    assert_matches_twin(result, frame)


@pytest.mark.parametrize("scene", ["teapot_pass", "occluder", None])
def test_every_gather_variant_gives_the_same_bits(ctx, rng, scene):
    if scene is None:
        frame = two_sided_frame(rng, 97, 61, reach=40.0)
    else:
        frame = ctx.render(bl.scenes.get(scene), (160, 90))
    outputs = {}
    for variant in GATHER_VARIANTS:
        with GATHER_LAYOUT.use(variant):
            outputs[variant] = bl.blur(ctx, frame, METHOD, samples=6).color
    first, *others = outputs.values()
    assert all(other.tobytes() == first.tobytes() for other in others)


@pytest.mark.parametrize("scene", ["moire", "edge_exit", "fan"])
def test_the_film_read_through_the_taps_matches_its_twin_without_a_film_pass(ctx, scene):
    frame = ctx.render(bl.scenes.get(scene), (160, 90))
    result = bl.blur(ctx, frame, METHOD, film_filter=0.5, film_through_taps=True)
    assert_matches_twin(result, frame)
    assert list(result.timings) == [*TILE_PASSES, *GATHER_PASSES]
    after = bl.blur(ctx, frame, METHOD, film_filter=0.5).color
    assert np.abs(result.color - after).max() > 1e-3  # another filter, not the same pass


def test_the_film_through_the_taps_on_a_still_frame_is_its_three_tap_kernel(ctx, rng):
    # A still frame: every tile exits early, and X reads itself through the film filter.
    frame = random_frame(rng, 37, 23)
    frame.motion[:] = 0
    out = bl.blur(ctx, frame, METHOD, film_filter=0.5, film_through_taps=True).color
    spread = film.film_spread(0.5)
    np.testing.assert_allclose(out, film.own_color(frame.color, spread), atol=2e-6)
    # [d/2, 1 - d, d/2] has the Gaussian kernel's variance: a point spreads as far.
    point = np.zeros((9, 9, 4))
    point[4, 4] = 1.0
    spread_out = film.own_color(point, spread)[4, :, 0]
    gaussian = film.film_filter(point, 0.5)[4, :, 0]
    offsets = np.arange(9) - 4
    variance = lambda row: (row * offsets**2).sum() / row.sum()  # noqa: E731
    assert variance(spread_out) == pytest.approx(variance(gaussian), rel=1e-9)
    assert spread == pytest.approx(0.2150, abs=1e-4)


def test_the_film_through_the_taps_is_off_without_a_film_filter_and_bounded(ctx, rng):
    frame = two_sided_frame(rng, 48, 27)
    plain = bl.blur(ctx, frame, METHOD).color
    assert bl.blur(ctx, frame, METHOD, film_through_taps=True).color.tobytes() == plain.tobytes()
    assert film.MAX_TAP_SIGMA == pytest.approx(0.708, abs=1e-3)
    with pytest.raises(ValueError, match=r"holds film_filter up to 0\.71 px, not 0\.8"):
        bl.blur(ctx, frame, METHOD, film_filter=0.8, film_through_taps=True)


THROUGH_TAPS = {"film_filter": 0.5, "film_through_taps": True}


def test_the_film_through_the_taps_keeps_the_filters_promises(ctx, rng):
    # Its weights (1 - d)², d(1 - d) and d² are a convex combination: inside the input range.
    assert_inside_the_input_range(
        ctx, random_frame(rng, 120, 80), METHOD, max_blur=40.0, **THROUGH_TAPS
    )
    for scale in (0.0, 1e30):
        assert_finite_for_motion_scale(ctx, rng, METHOD, scale, max_blur=50.0, **THROUGH_TAPS)
    frame = random_frame(rng, 64, 36)
    frame.color[5, 7] = np.nan  # a NaN texel stays where it is: each read is sanitised
    result = bl.blur(ctx, frame, METHOD, **THROUGH_TAPS)
    assert np.isfinite(result.color).all()
    assert_matches_twin(result, frame)


@pytest.mark.parametrize("film_through_taps", [False, True])
def test_still_and_moving_block_lists_give_the_bits_of_one_pass(ctx, film_through_taps):
    """§17.6.2: the gather over the still blocks' list and the moving blocks' list (indirect
    dispatch) against one pass over every pixel; the classes are the twin's, and a still
    block's pixels keep their colour."""
    frame = ctx.render(bl.scenes.get("thin_bar"), (160, 96))
    params = {"film_filter": 0.3, "film_through_taps": film_through_taps}
    values = bl.method(METHOD).defaults(frame, **params)
    inputs = frame_textures(ctx, frame)
    listed, timings = declared.run(ctx, frame, inputs, values, "compute")
    one = {**values, "tile_dispatch": "one"}
    full, _ = declared.run(ctx, frame, inputs, one, "compute")
    assert listed["color"].download().tobytes() == full["color"].download().tobytes()
    result = bl.blur(ctx, frame, METHOD, **params)
    dilated = resolve_reach_keys(result.buffers["reach_keys"], result.buffers["tiles"])
    height = frame.color.shape[0]
    s = ref.tile_size(height, values["tile_percent"])
    reach_limit = ref.max_blur_px(height, values["max_blur"])
    expected = ref.still_blocks(dilated, (96, 160), s, reach_limit, values["early_exit"])
    np.testing.assert_array_equal(result.buffers["block_class"][..., 0], expected)
    counts = result.buffers["tile_counts"][0, ::4, 0]
    np.testing.assert_array_equal(counts, np.bincount(expected.ravel(), minlength=2))
    assert counts.min() > 0
    still = np.kron(expected == 0, np.ones((16, 16), bool))[:96, :160]
    if not film_through_taps:
        gathered = result.buffers["unfiltered"]
        np.testing.assert_array_equal(gathered[still], frame.color[still])
    assert ctx.gl_errors() == []
