"""The two-sided motion of docs/spec.md §17.1 (frame.motion_prev, frame.motion_next) against
NumPy projections, and its constant-velocity derivation for frames made from arrays."""

from __future__ import annotations

import numpy as np
import pytest
from test_gbuffer import SHUTTER, SIZE, _apply, one_object_scene, sky_positions

import blurlab as bl
from blurlab.twins import projection


def expected_sides(frame: bl.Frame, scene: bl.Scene, object_id: int):
    """(mask, M_prev, M_next) at one object's pixels: each pixel center is where its surface
    point is at the instant; carried to t0 and t1 through the object's transforms."""
    mask = frame.object_id == object_id
    centers = projection.pixel_centers(*frame.size)[mask]
    world = projection.unproject(centers, frame.depth[mask], scene.camera, frame.time, frame.size)
    obj = scene.objects[object_id]
    local = _apply(np.linalg.inv(obj.model(frame.time)), world)
    t0, t1 = frame.shutter
    p0, _ = projection.project(_apply(obj.model(t0), local), scene.camera, t0, frame.size)
    p1, _ = projection.project(_apply(obj.model(t1), local), scene.camera, t1, frame.size)
    return mask, centers - p0, p1 - centers


@pytest.mark.parametrize("instant", ["center", "close", "open"])
def test_two_sided_motion_matches_the_projection(ctx, instant):
    motion = bl.Motion.linear((0, 0, 0), (6, 0, 0), spin_axis=(0.3, 1, 0.2), spin_rate=25.0)
    camera = bl.Camera(
        (0.0, 0.3, 4.0), (0.0, 0.0, 0.0), fov_y=50, motion=bl.Motion.linear(velocity=(8, 0, -6))
    )
    scene = one_object_scene(bl.mesh.torus(0.8, 0.3), motion, camera)
    frame = ctx.render(scene, SIZE, SHUTTER, instant=instant)
    mask, prev, next_ = expected_sides(frame, scene, 0)
    assert mask.sum() > 200
    assert np.abs(frame.motion_prev[mask] - prev).max() <= 0.01
    assert np.abs(frame.motion_next[mask] - next_).max() <= 0.01
    # The test means something: at the center the halves differ (the spin is not a straight
    # screen-space motion), at the ends one half is zero.
    if instant == "center":
        assert np.abs(prev - next_).max() > 0.5
    moving = np.abs(frame.motion[mask]).max()
    assert moving > 5
    if instant == "open":
        assert np.abs(frame.motion_prev[mask]).max() <= 0.01
    if instant == "close":
        assert np.abs(frame.motion_next[mask]).max() <= 0.01


def test_the_halves_add_up_to_the_motion(ctx):
    frame = ctx.render(bl.scenes.teapot_pass(), SIZE)
    total = frame.motion_prev + frame.motion_next
    assert np.abs(total - frame.motion).max() <= 1e-3
    assert np.abs(frame.motion).max() > 5


def test_background_halves_follow_the_camera_rotation(ctx):
    camera = bl.Camera(
        (0.0, 0.5, 5.0),
        (0.0, 0.0, 0.0),
        fov_y=60,
        motion=bl.Motion.linear(velocity=(0, 0, 0), spin_axis=(0, 1, 0), spin_rate=6.0),
    )
    scene = one_object_scene(bl.mesh.sphere(0.5), None, camera)
    frame = ctx.render(scene, SIZE, SHUTTER)
    sky, centers, p0, p1 = sky_positions(frame, camera)
    assert np.abs(frame.motion_prev[sky] - (centers - p0)).max() <= 0.01
    assert np.abs(frame.motion_next[sky] - (p1 - centers)).max() <= 0.01
    assert np.abs(p1 - p0).max() > 1.0


@pytest.mark.parametrize(("time", "fraction"), [(None, 0.5), (0.0, 0.0), (1.0, 1.0), (0.25, 0.25)])
def test_frames_from_arrays_get_constant_velocity_halves(rng, time, fraction):
    motion = rng.normal(0, 10, (9, 12, 2)).astype(np.float32)
    frame = bl.Frame(np.ones((9, 12, 4)), np.ones((9, 12)), motion, shutter=(0.0, 1.0), time=time)
    assert frame.instant_fraction == fraction
    np.testing.assert_allclose(frame.motion_prev, fraction * motion, rtol=1e-6)
    np.testing.assert_allclose(frame.motion_next, (1 - fraction) * motion, rtol=1e-6)


def test_given_halves_are_kept_and_checked(rng):
    color, depth = np.ones((4, 5, 4)), np.ones((4, 5))
    motion = rng.normal(0, 3, (4, 5, 2))
    prev, next_ = rng.normal(0, 3, (4, 5, 2)), rng.normal(0, 3, (4, 5, 2))
    frame = bl.Frame(color, depth, motion, motion_prev=prev, motion_next=next_)
    assert frame.motion_prev.dtype == np.float32
    np.testing.assert_array_equal(frame.motion_next, next_.astype(np.float32))
    with pytest.raises(ValueError, match="both motion_prev and motion_next"):
        bl.Frame(color, depth, motion, motion_prev=prev)
    with pytest.raises(ValueError, match="motion_next has shape"):
        bl.Frame(color, depth, motion, motion_prev=prev, motion_next=next_[:3])


def test_non_finite_motion_derives_without_warnings():
    motion = np.array([[[np.inf, np.nan], [1e38, -1e38]]], np.float32)
    with np.errstate(all="raise"):
        frame = bl.Frame(np.ones((1, 2, 4)), np.ones((1, 2)), motion)
    assert frame.motion_prev.shape == (1, 2, 2)


def test_derived_halves_follow_later_changes_to_the_motion(rng):
    frame = bl.Frame(np.ones((3, 4, 4)), np.ones((3, 4)), np.zeros((3, 4, 2)))
    frame.motion[:] = 6.0  # as the suites that build a frame and then set its motion do
    assert (frame.motion_prev == 3.0).all() and (frame.motion_next == 3.0).all()
