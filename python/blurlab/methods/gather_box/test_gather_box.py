"""gather_box (docs/spec.md §4, "Blurry things"; spec.md here) against its NumPy twin."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import random_frame

import blurlab as bl
from blurlab.methods.gather_box import twin


@pytest.mark.parametrize("backend", ["compute", "fragment"])
@pytest.mark.parametrize(
    ("taps", "intensity", "direction", "edge"),
    [
        (10, 1.0, "backward", "clamp"),
        (2, 0.5, "centered", "ignore"),
        (7, 1.5, "centered", "clamp"),
        (16, 1.0, "backward", "ignore"),
    ],
)
def test_matches_reference(ctx, rng, backend, taps, intensity, direction, edge):
    frame = random_frame(rng, 97, 61)
    params = {"taps": taps, "intensity": intensity, "direction": direction, "edge": edge}
    result = bl.blur(ctx, frame, "gather_box", backend=backend, **params)
    expected = twin.gather_box(frame.color, frame.motion, **params)
    error = np.abs(result.color - expected).max(axis=-1)
    assert (error <= 1e-3).mean() >= 0.999


@pytest.mark.parametrize("direction", ["backward", "centered"])
def test_zero_motion_is_the_identity(ctx, rng, direction):
    frame = random_frame(rng, 40, 30)
    frame.motion[:] = 0
    result = bl.blur(ctx, frame, "gather_box", direction=direction)
    np.testing.assert_allclose(result.color, frame.color, atol=1e-6)


def test_instant_follows_the_direction():
    assert bl.method_instant("gather_box") == "close"
    assert bl.method_instant("gather_box", {"direction": "centered"}) == "center"


def test_guard_needs_a_rendered_frame_and_removes_edge_error(ctx, rng):
    with pytest.raises(ValueError, match="guard"):
        bl.blur(ctx, random_frame(rng, 16, 16), "gather_box", edge="guard")
    # A camera panning across a finely checkered wall: clamped taps near the edge smear the
    # edge pixel; the guard band shows what lies beyond it.
    scene = bl.Scene(
        bl.Camera(
            (0.0, 0.0, 3.0),
            (0.0, 0.0, 0.0),
            fov_y=45,
            motion=bl.Motion.linear(velocity=(-24.0, 0.0, 0.0)),
        )
    )
    wall = bl.mesh.plane(8, 8).transformed(
        np.array([[1, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1.0]])
    )
    scene.add(wall, bl.Material(texture=bl.scenes.checker(512, 96)))
    frame = ctx.render(scene, (160, 90), instant="close")
    reference = ctx.reference(scene, (160, 90), samples=64, progress=False).color
    clamp = bl.blur(ctx, frame, "gather_box", taps=32, edge="clamp").color
    guard = bl.blur(ctx, frame, "gather_box", taps=32, edge="guard").color
    border = np.zeros((90, 160), bool)
    border[:, :12] = True  # the motion points left; backward taps leave on the left edge
    clamp_error = np.abs(clamp - reference)[border].mean()
    guard_error = np.abs(guard - reference)[border].mean()
    assert guard_error < 0.5 * clamp_error


def test_render_and_blur_uses_the_declared_instant_and_blur_warns_otherwise(ctx):
    scene = bl.scenes.fan()
    frame, result = bl.render_and_blur(ctx, scene, "gather_box", (32, 32), direction="centered")
    assert frame.time == pytest.approx(scene.shutter[1] / 2)
    assert result.color.shape == (32, 32, 4)
    wrong = ctx.render(scene, (32, 32), instant="center")
    with pytest.warns(UserWarning, match="expects the G-buffer at the shutter's close"):
        bl.blur(ctx, wrong, "gather_box")
