"""engine_godot (spec.md, docs/spec.md §17.10) on the GPU against its twin (twin.py): the velocity
pass (the three parts and their multipliers, the clamp to the largest multiplier, the near-plane
correction, the depth velocity, the frame-rate modes), the quality presets, and the whole
method on random and rendered frames."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import assert_timings_name, random_frame
from filter_promises import assert_blurs_a_rendered_scene_as_its_twin, assert_matches_twin

import blurlab as bl
from blurlab.methods.engine_godot import method as godot
from blurlab.methods.engine_godot import twin as ref

METHOD = "engine_godot"
# The velocity pass's parameters, and the frame-rate mode's, which the twin's velocity takes.
VELOCITY_KEYS = (*godot.VELOCITY_PARAMS, "framerate_mode", "fps", "reference_fps")


def _velocity_twin(frame, params):
    return ref.velocity(
        frame.depth, frame.motion, frame.camera, **{key: params[key] for key in VELOCITY_KEYS}
    )


@pytest.mark.parametrize(
    ("size", "params"),
    [
        ((160, 90), {}),
        ((97, 61), {"quality": "low", "k": 12, "object_multiplier": 0.5, "seed": 3}),
        ((130, 70), {"quality": "high", "exposure": 0.7, "framerate_mode": "fixed"}),
    ],
)
def test_random_frames_match_reference(ctx, rng, size, params):
    frame = random_frame(rng, *size, k=params.get("k", 20))
    result = bl.blur(ctx, frame, METHOD, **params)
    assert_matches_twin(result, frame)


@pytest.mark.parametrize(
    ("scene", "params"),
    [
        ("teapot_pass", {}),
        ("camera_yaw", {"rotation_multiplier": 0.5, "translation_multiplier": 0.25}),
        ("reverse_near_plane", {"translation_multiplier": 0.5}),
        ("racing_road", {"translation_multiplier": 0.5, "quality": "high"}),
    ],
)
def test_rendered_frames_match_reference(ctx, scene, params):
    assert_blurs_a_rendered_scene_as_its_twin(ctx, METHOD, scene, **params)


@pytest.mark.parametrize(
    "params",
    [
        {},
        {"near_correction": False, "clamp_to_original": False},
        {"rotation_multiplier": 0.3, "translation_multiplier": 0.6, "object_multiplier": 0.9},
        {"framerate_mode": "capped", "fps": 20.0, "depth_velocity": False},
    ],
)
def test_velocity_pass_equals_its_twin(ctx, params):
    frame = ctx.render(bl.scenes.get("reverse_near_plane"), (96, 54))
    result = bl.blur(ctx, frame, METHOD, **params)
    gpu = result.buffers["velocity"].astype(np.float64)
    expected = _velocity_twin(frame, result.params)
    np.testing.assert_allclose(gpu[..., :2], expected[..., :2], atol=2e-3, rtol=1e-4)
    np.testing.assert_allclose(gpu[..., 3], expected[..., 3], atol=1e-4, rtol=1e-4)
    np.testing.assert_array_equal(gpu[..., 2], frame.depth)


def test_the_three_parts_at_full_multipliers_give_the_motion_back(ctx):
    # Where no point crosses the near plane, the camera's parts are the G-buffer's own: the sum
    # of the three parts is M.
    frame = ctx.render(bl.scenes.get("tracked_car"), (96, 54))
    params = bl.method(METHOD).defaults(frame)
    np.testing.assert_allclose(_velocity_twin(frame, params)[..., :2], frame.motion, atol=1e-4)


def test_the_clamp_keeps_a_tracked_object_sharp(ctx):
    # tracked_car: the camera turns with the car, whose motion on screen is nearly zero. Halving
    # the camera's rotation leaves the car half the rotation's motion the other way, unless
    # the clamp holds it to the largest multiplier times its own (near zero) motion.
    frame = ctx.render(bl.scenes.get("tracked_car"), (96, 54))
    car = frame.object_id == [o.name for o in frame.scene.objects].index("car")
    assert car.sum() > 50
    half = bl.method(METHOD).defaults(frame, rotation_multiplier=0.5)
    clamped = np.linalg.norm(_velocity_twin(frame, half)[..., :2], axis=-1)[car]
    loose = _velocity_twin(frame, {**half, "clamp_to_original": False})[..., :2]
    original = np.linalg.norm(frame.motion, axis=-1)[car]
    assert (clamped <= original + 1e-9).all()
    assert np.median(np.linalg.norm(loose, axis=-1)[car]) > 5 * np.median(original) + 1.0


def test_near_plane_correction_moves_the_open_end_to_the_crossing():
    instant = np.array([0.4, -0.2, 3.0, 3.0])
    behind = np.array([0.9, 0.3, -1.0, -1.0])  # w < near: closer than the near plane
    clipped = ref.near_clipped(behind, instant, 0.5)
    assert clipped[3] == pytest.approx(0.5)
    direction = (clipped - instant) / np.linalg.norm(clipped - instant)
    np.testing.assert_allclose(direction, (behind - instant) / np.linalg.norm(behind - instant))
    in_front = np.array([0.1, 0.1, 2.0, 2.0])
    np.testing.assert_array_equal(ref.near_clipped(in_front, instant, 0.5), in_front)


def test_framerate_modes_against_the_reference_rate():
    assert ref.framerate_scale("native", 120.0, 30.0) == 1.0
    assert ref.framerate_scale("fixed", 120.0, 30.0) == 4.0
    assert ref.framerate_scale("fixed", 15.0, 30.0) == 0.5
    assert ref.framerate_scale("capped", 120.0, 30.0) == 1.0
    assert ref.framerate_scale("capped", 15.0, 30.0) == 0.5


def test_fixed_mode_scales_the_velocity(ctx, rng):
    frame = random_frame(rng, 64, 36)
    native = bl.blur(ctx, frame, METHOD).buffers["velocity"]
    fixed = bl.blur(ctx, frame, METHOD, framerate_mode="fixed", fps=15.0).buffers["velocity"]
    np.testing.assert_allclose(fixed[..., :2], native[..., :2] * 0.5, rtol=1e-6)


def test_quality_presets_take_4_8_16_samples():
    assert ref.SAMPLES_BY_QUALITY == {"low": 4, "medium": 8, "high": 16}


def test_velocities_are_clamped_to_twice_the_tile(ctx):
    frame = bl.Frame(
        color=np.random.default_rng(1).random((32, 64, 4), dtype=np.float32),
        depth=np.ones((32, 64), np.float32),
        motion=np.full((32, 64, 2), [300.0, 0.0], np.float32),
    )
    result = bl.blur(ctx, frame, METHOD, k=8)
    np.testing.assert_allclose(np.linalg.norm(result.buffers["tile_max"], axis=-1), 8.0, rtol=1e-6)


def test_timings_name_every_pass(ctx, rng):
    # Its refusals of bad parameters are rows of tests/test_parameter_refusals.py.
    assert_timings_name(ctx, rng, METHOD, ["velocity", "tile_max", "neighbor_max", "reconstruct"])


def test_reverse_near_plane_has_ends_behind_the_near_plane(ctx):
    # The correction must have work to do on its scene: posts in front at the instant that
    # were closer than the near plane at the shutter's open.
    frame = ctx.render(bl.scenes.get("reverse_near_plane"), (96, 54))
    params = bl.method(METHOD).defaults(frame)
    corrected = _velocity_twin(frame, params)[..., :2]
    plain = _velocity_twin(frame, {**params, "near_correction": False})[..., :2]
    changed = np.linalg.norm(corrected - plain, axis=-1) > 1.0
    assert changed.mean() > 0.01
    # Uncorrected, some of them point the other way and run longer.
    flipped = ((corrected * plain).sum(-1) < 0) & (
        np.linalg.norm(plain, axis=-1) > np.linalg.norm(corrected, axis=-1)
    )
    assert flipped.sum() > 10
