"""Packed filter inputs (docs/spec.md §19): colour and motion + depth as half floats,
packed once per frame by shaders/passes/pack_inputs.comp, read by reconstruct_mcguire2012 and
reconstruct_guertin2014 with packed_inputs=True; NumPy twin blurlab.twins.inputs.pack_half. And
their results as half floats (half_result=True), rounded as blurlab.twins.inputs.round_to_half."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_frame
from method_picks import picks

import blurlab as bl
from blurlab.methods.core import frame_textures
from blurlab.methods.tile_filter import packed_inputs
from blurlab.twins.inputs import HALF_MAX, pack_half, round_to_half

# The filters that take packed inputs and half results, on both backends (two or more: a frame
# is packed once for all of them).
FILTERS = picks(params=("packed_inputs", "half_result"), backends=("compute", "fragment"))


def extreme_frame() -> bl.Frame:
    """Every case of §10.1 and §19's clamps, one per pixel of a 4 x 4 frame."""
    color = np.full((4, 4, 4), 0.5, np.float32)
    color[0, 0] = (np.nan, np.inf, -np.inf, 1e30)
    color[0, 1] = (7e4, -7e4, 65519.0, 1e-8)  # 65519 rounds down to HALF_MAX, 65520 would not
    color[0, 2] = (0.1, 1 / 3, 2049.0, 2051.0)  # ties to even: 2048 and 2052
    color[0, 3] = (3e-7, 2.5 * 2.0**-24, -1.5 * 2.0**-24, 6.1e-5)  # subnormal halves
    depth = np.full((4, 4), 2.0, np.float32)
    depth[1, :] = (np.nan, 0.0, -1.0, np.inf)
    depth[2, :] = (1e-9, 3e-8, 1e5, 65519.0)
    motion = np.full((4, 4, 2), 0.25, np.float32)
    motion[3, 0] = (np.nan, 1.0)
    motion[3, 1] = (np.inf, 1.0)
    motion[3, 2] = (1e7, -1e9)
    motion[3, 3] = (1 / 3, -12345.678)
    return bl.Frame(color=color, depth=depth, motion=motion)


def test_packed_textures_equal_the_twin_bit_for_bit(ctx):
    frame = extreme_frame()
    packed = packed_inputs(ctx, frame, frame_textures(ctx, frame))
    color, depth, motion = pack_half(frame.color, frame.depth, frame.motion)
    got_color = packed["color"].download()
    got = packed["motion_depth"].download()
    assert got_color.dtype == np.float16 and got.dtype == np.float16
    np.testing.assert_array_equal(got_color.astype(np.float64), color)
    np.testing.assert_array_equal(got[..., 2].astype(np.float64), depth)
    np.testing.assert_array_equal(got[..., :2].astype(np.float64), motion)
    assert not got[..., 3].any()
    # The clamps of §19: finite depths stay finite and positive, the rest as §10.1 reads it.
    assert depth[2, 0] == depth[2, 1] == 2.0**-14 and depth[2, 2] == HALF_MAX
    assert depth[1, 0] == np.inf
    assert color[0, 1, 2] == HALF_MAX and np.isfinite(color).all()
    assert (motion[3, 2] == (HALF_MAX, -HALF_MAX)).all() and not motion[3, :2].any()


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize("name", FILTERS)
@pytest.mark.parametrize(("k", "samples"), [(20, 15), (7, 8)])
def test_packed_filters_match_their_twins(ctx, rng, backend, name, k, samples):
    frame = random_frame(rng, 160, 90, k=k)
    params = {"k": k, "samples": samples, "soft_z": 0.5, "seed": 5, "packed_inputs": True}
    result = bl.blur(ctx, frame, name, backend=backend, **params)
    expected = bl.method(name).twin_output(frame, **params)
    error = np.abs(result.color - expected)
    assert (error.max(axis=-1) <= 1e-3).mean() >= 0.999
    assert error.mean() <= 1e-4
    unpacked = bl.method(name).twin_output(frame, **{**params, "packed_inputs": False})
    assert np.abs(expected - unpacked).max() > 0  # the twin does read half floats


@pytest.mark.parametrize("name", FILTERS)
def test_packed_filters_read_the_clamped_colour(ctx, name):
    color = np.full((30, 40, 4), 1e5, np.float32)  # beyond half range, and still
    frame = bl.Frame(color=color, depth=np.ones((30, 40)), motion=np.zeros((30, 40, 2)))
    stored = bl.blur(ctx, frame, name).color
    packed = bl.blur(ctx, frame, name, packed_inputs=True).color
    np.testing.assert_array_equal(stored, 1e5)
    np.testing.assert_array_equal(packed, HALF_MAX)


def test_a_frame_is_packed_once(ctx, rng):
    assert len(FILTERS) >= 2
    frame = random_frame(rng, 64, 48, k=8)
    first = bl.blur(ctx, frame, FILTERS[0], k=8, packed_inputs=True)
    timing, kept = frame.timings["pack_inputs"], frame.textures["packed_color"]
    for name, k in ((FILTERS[1], 8), (FILTERS[0], 16)):
        bl.blur(ctx, frame, name, k=k, packed_inputs=True)
    assert frame.timings["pack_inputs"] is timing and frame.textures["packed_color"] is kept
    assert "pack_inputs" not in first.timings  # the filter's passes only
    assert list(first.timings) == ["tile_max", "neighbor_max", "reconstruct"]


def test_replayed_packed_calls_give_the_same_bits(ctx, rng):
    frame = random_frame(rng, 64, 48, k=8)
    params = {"k": 8, "samples": 9, "packed_inputs": True}
    ordinary = bl.blur(ctx, frame, FILTERS[1], **params).color
    for _ in range(3):  # the second untimed call records, the third replays
        replayed = bl.blur(ctx, frame, FILTERS[1], timed=False, **params)
    assert frame.plans and any(plan is not None for plan in frame.plans.values())
    np.testing.assert_array_equal(replayed.color, ordinary)


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize("name", FILTERS)
@pytest.mark.parametrize("packed", [False, True])
def test_half_results_match_their_twins(ctx, rng, backend, name, packed):
    frame = random_frame(rng, 160, 90)
    params = {"soft_z": 0.5, "seed": 5, "packed_inputs": packed, "half_result": True}
    result = bl.blur(ctx, frame, name, backend=backend, **params)
    assert result.color.dtype == np.float16
    expected = bl.method(name).twin_output(frame, **params)
    # Both round the same float32 to half: they differ only where the unrounded values lie on
    # either side of a rounding boundary, by one half step (under 1e-3 for values under 2).
    error = np.abs(result.color.astype(np.float64) - expected)
    assert (error.max(axis=-1) <= 1e-3).mean() >= 0.999
    assert (error == 0).mean() >= 0.99
    full = bl.method(name).twin_output(frame, **{**params, "half_result": False})
    assert np.abs(expected - full).max() > 0  # the twin does round


@pytest.mark.parametrize("name", FILTERS)
def test_half_results_round_ties_to_even_and_clamp(ctx, name):
    # Still pixels keep their colour: the stored half is round_to_half of it, on every driver.
    color = np.full((30, 40, 4), 0.5, np.float32)
    color[0, 0] = (2049.0, 2051.0, 1e5, -7e4)  # 2048, 2052 (ties to even), ±HALF_MAX
    frame = bl.Frame(color=color, depth=np.ones((30, 40)), motion=np.zeros((30, 40, 2)))
    for backend in ("compute", "fragment"):
        got = bl.blur(ctx, frame, name, backend=backend, half_result=True).color
        np.testing.assert_array_equal(got[0, 0], [2048.0, 2052.0, HALF_MAX, -HALF_MAX])
        np.testing.assert_array_equal(got.astype(np.float64), round_to_half(color))
