"""Per-object and camera motion-blur scales (docs/spec.md §12.1): an object with scale s is
evaluated at t_c + s·(t − t_c) in every sub-frame of the reference and in the G-buffer's motion;
the camera likewise. At s = 0 its pixels are the sharp render at t_c, in the reference and in
every method."""

from __future__ import annotations

import math

import numpy as np
import pytest
from method_picks import EXAMPLE

import blurlab as bl
from blurlab.scene import mesh
from blurlab.scene.blur_scales import check_blur_scale, scaled_scene

SIZE = (96, 54)
SHUTTER = (0.0, 0.1)
CENTRE = 0.05
TOLERANCE = 1e-6


def lit_flat(camera) -> bl.Scene:
    light = bl.DirectionalLight(color=(0.3, 0.3, 0.3), ambient=(0.7, 0.7, 0.7))
    scene = bl.Scene(camera, light=light, shutter=SHUTTER)
    checker = np.indices((64, 64)).sum(axis=0)[..., None] // 8 % 2 * np.ones(3) * 0.5 + 0.2
    wall = mesh.plane(40, 40).transformed(mesh.rotation_x(math.pi / 2))
    scene.add(wall, bl.Material(texture=checker.astype(np.float32)), name="wall")
    return scene


def two_movers(sharp_scale=0.0, free_scale=1.0) -> bl.Scene:
    """A still camera and wall; on the left a box crossing fast with `sharp_scale`, on the
    right a sphere crossing with its full blur."""
    scene = lit_flat(bl.Camera((0, 0, 6), (0, 0, 0), fov_y=50))
    crossing = bl.Motion.linear((-3.2, 0, 1), (20, 6, 0), (0, 0, 1), 9.0)
    scene.add(
        mesh.box((1.2, 1.2, 1.2)),
        bl.Material((0.9, 0.2, 0.1)),
        crossing,
        name="held",
        motion_blur=sharp_scale,
    )
    far = bl.Motion.linear((2.8, 0, 1), (0, 8, 0))
    scene.add(
        mesh.sphere(0.7, 16, 8),
        bl.Material((0.1, 0.5, 0.9)),
        far,
        name="free",
        motion_blur=free_scale,
    )
    return scene


def panning(camera_scale=0.0) -> bl.Scene:
    """A camera turning fast over a still wall, `camera_scale` of its motion blurred; a sphere
    crossing in the right third."""
    pan = bl.Motion.linear(spin_axis=(0, 1, 0), spin_rate=4.0)
    scene = lit_flat(bl.Camera((0, 0, 6), (0, 0, 0), fov_y=50, motion=pan))
    scene.camera_motion_blur = camera_scale
    scene.add(
        mesh.sphere(0.6, 16, 8),
        bl.Material((0.1, 0.5, 0.9)),
        bl.Motion.linear((2.9, 0, 1), (0, 9, 0)),
        name="free",
    )
    return scene


def inner(mask: np.ndarray) -> np.ndarray:
    """The mask one pixel in from its outline (edge pixels differ under sub-pixel jitter)."""
    m = mask.copy()
    m[1:] &= mask[:-1]
    m[:-1] &= mask[1:]
    m[:, 1:] &= mask[:, :-1]
    m[:, :-1] &= mask[:, 1:]
    return m


# Motion this small is float rounding of two equal projections, not motion (see below).
STILL_PX = 1e-5


def far_from_motion(frame, tile=20, reach=2) -> np.ndarray:
    """Pixels more than `reach` tiles of `tile` px from any tile with motion: what the filters'
    tile neighbourhoods (k = 20 px by default) never mix into a moving pixel's blur."""
    height, width = frame.motion.shape[:2]
    moving = np.abs(frame.motion).max(axis=-1) > STILL_PX
    ty, tx = np.nonzero(moving)
    ty, tx = ty // tile, tx // tile
    y, x = np.mgrid[:height, :width] // tile
    near = np.zeros((height, width), bool)
    for a, b in set(zip(ty.tolist(), tx.tolist(), strict=True)):
        near |= (np.abs(y - a) <= reach) & (np.abs(x - b) <= reach)
    return ~near


def sharp(ctx, scene):
    return ctx.render(scene, SIZE, (CENTRE, CENTRE))


def check_sharp_everywhere(ctx, scene, mask, what):
    expected = sharp(ctx, scene).color
    reference = ctx.reference(scene, SIZE, samples=16).color
    assert np.abs(reference[mask] - expected[mask]).max() <= TOLERANCE, f"reference, {what}"
    failures, antialiased = {}, set()
    for name in bl.methods():
        _, result = bl.render_and_blur(ctx, scene, name, SIZE)
        own = expected
        _, still = bl.render_and_blur(ctx, scene, name, SIZE, (CENTRE, CENTRE))
        if np.abs(still.color[mask] - expected[mask]).max() > TOLERANCE:
            # A method that samples sub-pixel positions antialiases even a still image: its
            # own render of the sharp instant is what the object must match.
            own = still.color
            antialiased.add(name)
        error = float(np.abs(result.color[mask] - own[mask]).max())
        if error > TOLERANCE:
            failures[name] = error
    assert not failures, f"{what}: pixels off the sharp render by {failures}"
    # Only a method that renders sub-frames may sample sub-pixel positions (accumulation's
    # folder holds it to the pixel centres).
    assert all(bl.method(name).kind == "render" for name in antialiased), antialiased


def test_an_object_at_scale_0_is_the_sharp_render_in_the_reference_and_every_method(ctx):
    scene = two_movers(0.0)
    frame = ctx.render(scene, SIZE)
    held = inner(sharp(ctx, scene).object_id == 1)
    assert held.sum() > 40
    # No motion of its own at scale 0: the two equal projections differ by float rounding
    # alone (exactly 0 on llvmpipe, up to 1e-6 px on an H200).
    assert np.abs(frame.motion[held]).max() <= STILL_PX
    blurred = ctx.render(two_movers(1.0), SIZE)
    assert np.abs(blurred.motion[held]).max() > 10  # the same object at scale 1 moves far
    check_sharp_everywhere(ctx, scene, held, "motion_blur=0")
    # Shutter steps pivot on the whole shutter's centre, not each step's.
    _, stepped = bl.render_and_blur(ctx, scene, EXAMPLE, SIZE, steps=4)
    expected = sharp(ctx, scene).color
    assert np.abs(stepped.color[held] - expected[held]).max() <= TOLERANCE


def test_a_still_background_stays_sharp_under_a_camera_at_scale_0(ctx):
    scene = panning(0.0)
    assert np.abs(ctx.render(panning(1.0), SIZE).motion[..., 0]).max() > 10
    background = inner(sharp(ctx, scene).object_id == 0) & far_from_motion(ctx.render(scene, SIZE))
    assert background.sum() > 1000
    check_sharp_everywhere(ctx, scene, background, "camera_motion_blur=0")


def test_half_scale_halves_the_motion_and_centres_it(ctx):
    full, half = ctx.render(two_movers(1.0), SIZE), ctx.render(two_movers(1.0, 0.5), SIZE)
    free = inner((full.object_id == 2) & (half.object_id == 2))
    assert free.sum() > 20
    # A translation in a plane facing the camera: half the scale, half the motion vector.
    assert np.allclose(half.motion[free], 0.5 * full.motion[free], atol=1e-3)
    obj = scaled_scene(two_movers(0.5), SHUTTER).objects[1]
    original = two_movers(1.0).objects[1]
    for t in (0.0, 0.03, 0.1):
        assert np.allclose(obj.model(t), original.model(CENTRE + 0.5 * (t - CENTRE)))


def test_a_camera_held_object_is_sharp_at_scale_0_while_the_camera_pans(ctx):
    scene = panning(1.0)
    sway = bl.Motion.linear((0.5, -0.4, -2.0), (3.0, 1.0, 0.0))  # in camera space
    held = scene.add(
        mesh.box((0.4, 0.3, 0.8)),
        bl.Material((0.3, 0.3, 0.3)),
        bl.CameraHeld(scene.camera, sway),
        name="weapon",
        motion_blur=0.0,
    )
    frame = ctx.render(scene, SIZE)
    mask = inner(frame.object_id == 2)
    assert mask.sum() > 20
    assert np.abs(frame.motion[mask]).max() < 1e-3  # carried by the camera, its sway frozen
    held.motion_blur = 1.0
    assert np.abs(ctx.render(scene, SIZE).motion[mask]).max() > 2


def test_identity_at_scale_1_and_bad_scales():
    scene = two_movers(1.0)
    assert scaled_scene(scene, SHUTTER) is scene  # nothing changes, not a bit
    for bad, message in (
        (1.5, r"in \[0, 1\]"),
        (-0.1, r"in \[0, 1\]"),
        (True, "number"),
        (math.nan, "number"),
        ("1", "number"),
    ):
        with pytest.raises(ValueError, match=message):
            check_blur_scale(bad, "motion_blur")
        with pytest.raises(ValueError, match="motion_blur of box"):
            bl.Scene().add(mesh.box(), motion_blur=bad, name="box")
        with pytest.raises(ValueError, match="camera_motion_blur"):
            bl.Scene(camera_motion_blur=bad)
    scene.objects[1].motion_blur = 2.0  # set after the fact: refused when rendered
    with pytest.raises(ValueError, match="motion_blur of held"):
        scaled_scene(scene, SHUTTER)


@pytest.mark.parametrize(("name", "subject"), [("fps_weapon", "weapon"), ("tracked_car", "car")])
def test_the_two_scenes_keep_their_subject_still_on_screen_while_the_rest_blurs(ctx, name, subject):
    scene = bl.scenes.get(name)
    frame = ctx.render(scene, (160, 90))
    ids = [i for i, obj in enumerate(scene.objects) if obj.name == subject]
    held = inner(np.isin(frame.object_id, ids))
    speed = np.linalg.norm(frame.motion, axis=-1)
    assert held.sum() > 50
    assert speed[held].max() < 0.01  # carried (weapon) or tracked (car): still on screen
    assert np.median(speed[~np.isin(frame.object_id, ids)]) > 3  # the world behind blurs


@pytest.mark.skipif(not bl.blender.available(), reason="bpy is not installed")
def test_blender_renders_the_scales_as_blurlab_evaluates_them(ctx):
    scene, size = two_movers(0.0), (48, 27)
    held = inner(ctx.render(scene, size, (CENTRE, CENTRE)).object_id == 1)
    blurred = bl.blender.render(scene, size, SHUTTER, samples=16, steps=3).color
    still = bl.blender.render(scene, size, SHUTTER, samples=16, instant=CENTRE).color
    assert held.sum() > 10
    assert np.abs(blurred[held] - still[held]).max() < 1e-3  # held: as sharp as the instant
