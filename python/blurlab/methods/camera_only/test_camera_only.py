"""camera_only (docs/spec.md §4, Urho3D thesis §2.3.2; spec.md here): motion from depth and the
camera alone, then the box gather along it."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import assert_matches_twin

import blurlab as bl
from blurlab.methods.camera_only import twin
from blurlab.twins import gathers


def panning_scene():
    scene = bl.scenes.teapot_pass()
    for obj in scene.objects:
        obj.motion = obj.motion and bl.Motion.static(obj.model(0.0)[:3, 3])
    scene.objects[-1].motion = None  # nothing moves but the camera
    scene.camera.motion = bl.Motion.linear(velocity=(6, 2, -4), spin_axis=(0, 1, 0), spin_rate=4)
    return scene


def test_camera_motion_equals_the_gbuffer_motion_of_a_still_world(ctx):
    frame = ctx.render(panning_scene(), (160, 90), instant="close")
    motion = gathers.camera_motion(frame.depth, frame.camera, frame.size)
    assert np.abs(motion - frame.motion).max() <= 0.01
    assert np.abs(frame.motion).max() > 3


def test_gpu_matches_reference(ctx):
    frame = ctx.render(panning_scene(), (160, 90), instant="close")
    result = bl.blur(ctx, frame, "camera_only", taps=8)
    expected = twin.camera_only(frame.color, frame.depth, frame.camera, frame.size, **result.params)
    assert_matches_twin(result, frame, expected=expected)


def test_a_moving_object_under_a_still_camera_stays_sharp(ctx):
    frame = ctx.render(bl.scenes.teapot_pass(), (160, 90), instant="close")
    assert np.abs(frame.motion).max() > 5  # the teapot moves
    result = bl.blur(ctx, frame, "camera_only")
    np.testing.assert_allclose(result.color, frame.color, atol=1e-6)


def test_needs_a_rendered_frame(ctx, rng):
    frame = bl.Frame(color=rng.random((8, 8, 4)), depth=np.ones((8, 8)), motion=np.zeros((8, 8, 2)))
    with pytest.raises(ValueError, match="ctx.render"):
        bl.blur(ctx, frame, "camera_only")
