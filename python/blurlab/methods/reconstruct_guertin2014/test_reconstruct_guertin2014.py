"""reconstruct_guertin2014 (docs/guertin2014.md) on the GPU against its NumPy twin (twin.py),
its direction-keeping NeighborMax, and the 2012 filter's promises:
still images unchanged, output inside the input range, no NaN, same seed same bits."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import (
    assert_inside_input_range,
    assert_matches_twin,
    assert_timings_name,
    random_frame,
)
from method_picks import EXAMPLE

import blurlab as bl
from blurlab.methods.reconstruct_guertin2014 import twin as ref
from blurlab.twins import mcguire2012

METHOD = "reconstruct_guertin2014"


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize(
    ("k", "samples", "size", "gamma", "kappa"),
    [
        (20, 15, (160, 90), 1.5, 40.0),
        (8, 8, (97, 61), 1.5, 40.0),
        (1, 5, (40, 30), 0.5, 10.0),
        (33, 16, (150, 77), 4.0, 40.0),
        (64, 1, (130, 70), 1.5, 40.0),
    ],
)
def test_random_frames_match_reference(ctx, rng, backend, k, samples, size, gamma, kappa):
    frame = random_frame(rng, *size, k=k)
    params = {"k": k, "samples": samples, "soft_z": 0.5, "seed": 7, "gamma": gamma, "kappa": kappa}
    result = bl.blur(ctx, frame, METHOD, backend=backend, **params)
    assert params.items() <= result.params.items()
    assert_matches_twin(result, frame)


@pytest.mark.parametrize("scene", ["teapot_pass", "fan", "skinned_arm", "crossing"])
def test_rendered_frames_match_reference(ctx, scene):
    frame = ctx.render(bl.scenes.get(scene), (160, 90))
    result = bl.blur(ctx, frame, METHOD, k=12, samples=11)
    assert_matches_twin(result, frame)
    assert np.abs(result.color - frame.color).max() > 0.05  # it really blurred


@pytest.mark.parametrize("backend", ["compute", "fragment"])
def test_direction_keeping_neighbor_max_equals_reference(ctx, rng, backend):
    frame = random_frame(rng, 150, 90, k=10)
    result = bl.blur(ctx, frame, METHOD, backend=backend, k=10)
    tiles = result.buffers["tile_max"].astype(np.float64)
    expected = mcguire2012.neighbor_max(tiles, diagonal_reach=True)
    np.testing.assert_array_equal(result.buffers["neighbor_max"], expected.astype(np.float32))
    assert not np.array_equal(expected, mcguire2012.neighbor_max(tiles))  # it is another rule


def test_diagonal_tiles_count_only_where_their_motion_reaches_the_center():
    tiles = np.zeros((5, 5, 2))
    tiles[2, 2] = (3.0, 0.0)  # horizontal: reaches its row only
    spread = np.linalg.norm(mcguire2012.neighbor_max(tiles, diagonal_reach=True), axis=-1) > 0
    assert spread[2, 1:4].all() and spread[1:4, 2].all()
    assert not spread[1, 1] and not spread[1, 3] and not spread[3, 1] and not spread[3, 3]
    tiles[2, 2] = (2.0, 2.0)  # along the main diagonal (+y down): the two tiles on that line
    spread = np.linalg.norm(mcguire2012.neighbor_max(tiles, diagonal_reach=True), axis=-1) > 0
    assert spread[1, 1] and spread[3, 3] and not spread[1, 3] and not spread[3, 1]
    assert spread.sum() == 7


def test_center_direction_follows_equation_1():
    vn = np.array([[10.0, 0.0]] * 3)
    vx = np.array([[0.0, 0.0], [0.0, -0.5], [3.0, 3.0]])
    wc = ref.center_direction(vn, vx, gamma=1.5)
    np.testing.assert_allclose(wc[0], (0.0, 1.0))  # still: vN's perpendicular
    np.testing.assert_allclose(wc[1], (0.0, -1.0))  # slow: the perpendicular on V[X]'s side
    np.testing.assert_allclose(wc[2], np.array([1.0, 1.0]) / np.sqrt(2))  # fast: V[X]'s own


def test_still_image_comes_back_unchanged(ctx, rng):
    frame = random_frame(rng, 64, 48)
    frame.motion[:] = 0
    result = bl.blur(ctx, frame, METHOD)
    assert result.color.tobytes() == frame.color.tobytes()


def test_output_stays_inside_the_input_range(ctx, rng):
    frame = random_frame(rng, 120, 80)
    frame.color[..., :3] = frame.color[..., :3] * 0.5 + 0.25  # inputs in [0.25, 0.75]
    out = bl.blur(ctx, frame, METHOD, k=10).color
    assert_inside_input_range(out, frame.color)


@pytest.mark.parametrize("scale", [0.0, 1e-3, 1e30])
def test_zero_tiny_and_huge_motion_give_no_nan(ctx, rng, scale):
    frame = random_frame(rng, 80, 60)
    frame.motion[:] = np.float32(scale) * np.sign(frame.motion)
    result = bl.blur(ctx, frame, METHOD, k=8)
    assert np.isfinite(result.color).all()


def test_same_seed_same_bits_other_seed_other_noise(ctx, rng):
    frame = random_frame(rng, 80, 60)
    a = bl.blur(ctx, frame, METHOD, seed=3).color
    b = bl.blur(ctx, frame, METHOD, seed=3).color
    c = bl.blur(ctx, frame, METHOD, seed=4).color
    assert a.tobytes() == b.tobytes()
    assert a.tobytes() != c.tobytes()


def test_nearer_the_reference_than_2012_on_the_fan(ctx):
    """docs/guertin2014.md's claim at test size: overlapping rotating blades, where 2012's
    single direction vN smears the blades across each other. The 2012 filter is the example
    method (EXAMPLE, reconstruct_mcguire2012), the filter this one changes."""
    scene = bl.scenes.get("fan")
    size = (128, 72)
    reference = ctx.reference(scene, size, samples=64, progress=False).color
    frame = ctx.render(scene, size)
    psnr = {m: bl.metrics.psnr(reference, bl.blur(ctx, frame, m).color) for m in (EXAMPLE, METHOD)}
    assert psnr[METHOD] > psnr[EXAMPLE] + 1.0, psnr


def test_timings_name_every_pass(ctx, rng):
    assert_timings_name(ctx, rng, METHOD, ["tile_max", "neighbor_max", "reconstruct"])
