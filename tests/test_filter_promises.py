"""The promises of the engine filters and gather_coverage (tests/filter_promises.py), one table
for all of them: a still frame comes back unchanged, the output stays inside the input range,
zero, tiny and huge motion give no NaN, the same seed gives the same bits. Each row names the
frame the method is tried on (engine_eevee reads two-sided motion) and the parameters that let
its blur reach far enough to be tested."""

from __future__ import annotations

import pytest
from conftest import random_frame
from filter_promises import (
    assert_finite_for_motion_scale,
    assert_inside_the_input_range,
    assert_seeded,
    assert_still_frame_unchanged,
    two_sided_frame,
)

# method: (frame maker, parameters for the input-range check, parameters for huge motion)
PROMISES = {
    "engine_eevee": (two_sided_frame, {"tile_size": 16}, {"max_blur": 1e6, "tile_size": 16}),
    "engine_unity": (random_frame, {"max_radius": 15.0}, {"max_radius": 50.0}),
    "engine_hdrp": (random_frame, {"fast_ratio": 0.2}, {"maximum_velocity": 65024.0}),
    "engine_unreal": (random_frame, {"max_blur": 15.0}, {"max_blur": 100.0}),
    "engine_godot": (random_frame, {"k": 15}, {"k": 256}),
    "gather_coverage": (random_frame, {"max_blur": 40.0}, {"max_blur": 50.0}),
}
METHODS = list(PROMISES)


@pytest.mark.parametrize("method", METHODS)
def test_still_image_comes_back_unchanged(ctx, rng, method):
    assert_still_frame_unchanged(ctx, rng, method)


@pytest.mark.parametrize("method", METHODS)
def test_output_stays_inside_the_input_range(ctx, rng, method):
    make, params, _ = PROMISES[method]
    assert_inside_the_input_range(ctx, make(rng, 120, 80), method, **params)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("scale", [0.0, 1e-3, 1e30])
def test_zero_tiny_and_huge_motion_give_no_nan(ctx, rng, method, scale):
    assert_finite_for_motion_scale(ctx, rng, method, scale, **PROMISES[method][2])


@pytest.mark.parametrize("method", METHODS)
def test_same_seed_same_bits_other_seed_other_noise(ctx, rng, method):
    make = PROMISES[method][0]
    assert_seeded(ctx, make(rng, 80, 60), method)
