"""A reference's still objects drawn once (docs/spec.md §11): where the camera stands still,
the first opaque objects that stand still too make a base every sub-frame starts from. These
tests hold it to the same bits as drawing every object in every sub-frame."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import CLI_DEVICE

import blurlab as bl
from blurlab.core.references import sample_times
from blurlab.core.render import render_base, render_targets, still_draws
from blurlab.scene.blur_scales import scaled_scene

SIZE = (64, 36)


def _scene(name):
    scene = bl.scenes.get(name)
    return scaled_scene(scene, scene.shutter)  # as the reference renders it


@pytest.mark.parametrize(
    ("name", "still"),
    [
        ("teapot_pass", 3),  # floor, box and sphere; the teapot moves
        ("fan", 1),  # the wall
        ("occluder", 1),  # the second still object follows a moving one: not in the base
        ("vehicle", 0),  # the camera moves
        ("textured_spin", 0),  # every sphere turns
        ("skinned_arm", 0),  # skinned
        ("moving_glass", 1),  # translucent objects are never in it
    ],
)
def test_still_draws_counts_the_still_opaque_objects_before_the_first_that_moves(name, still):
    scene = _scene(name)
    assert still_draws(scene, SIZE, sample_times(scene.shutter, 16, True, 0)) == still


def test_still_draws_is_zero_for_one_time_and_when_any_time_moves_the_camera():
    scene = _scene("teapot_pass")
    assert still_draws(scene, SIZE, [0.0]) == 0
    camera_moves = _scene("camera_yaw")
    times = sample_times(camera_moves.shutter, 8, True, 0)
    assert still_draws(camera_moves, SIZE, times) == 0


@pytest.mark.parametrize("name", ["teapot_pass", "fan", "occluder", "foliage_spin", "moving_glass"])
def test_sub_frames_over_a_base_are_the_sub_frames_drawn_whole(ctx, name):
    scene = _scene(name)
    times = sample_times(scene.shutter, 6, True, 3)
    still = still_draws(scene, SIZE, times)
    assert still > 0
    base, _ = render_base(ctx, scene, SIZE, scene.shutter, float(times[0]), still, timers=False)
    for t in times:
        args = (ctx, scene, SIZE, scene.shutter, float(t))
        over, _, _ = render_targets(*args, timers=False, color_only=True, base=base)
        whole, _, _ = render_targets(*args, timers=False, color_only=True)
        assert np.array_equal(over["color"].download(), whole["color"].download())
        for targets in (over, whole):
            ctx.recycle(*(t for t in targets.values() if hasattr(t, "native")))
    ctx.recycle(*base.textures.values())


def test_a_reference_with_a_base_equals_one_drawn_whole(ctx, monkeypatch):
    scene = bl.scenes.get("teapot_pass")
    with_base = ctx.reference(scene, SIZE, samples=12, progress=False).color
    monkeypatch.setattr("blurlab.core.references.still_draws", lambda *args: 0)
    whole = ctx.reference(scene, SIZE, samples=12, progress=False).color
    assert np.array_equal(with_base, whole)


def test_a_base_is_refused_where_it_does_not_fit(ctx):
    scene = _scene("teapot_pass")
    times = sample_times(scene.shutter, 4, True, 0)
    first, _ = render_base(ctx, scene, SIZE, scene.shutter, float(times[0]), 3, timers=False)
    second, _ = render_base(ctx, scene, SIZE, scene.shutter, float(times[0]), 3, timers=False)
    args = (ctx, scene, SIZE, scene.shutter, float(times[1]))
    with pytest.raises(ValueError, match="not the G-buffer pass's kept one"):
        render_targets(*args, timers=False, color_only=True, base=first)
    with pytest.raises(ValueError, match="keeps the colour alone"):
        render_targets(*args, timers=False, base=second)
    with pytest.raises(ValueError, match="differs in size"):
        render_targets(
            ctx, scene, (32, 18), scene.shutter, 0.0, timers=False, color_only=True, base=second
        )
    ctx.recycle(*first.textures.values(), *second.textures.values())
    # nothing was left half-done: a render over the kept base still works
    third, _ = render_base(ctx, scene, SIZE, scene.shutter, float(times[0]), 3, timers=False)
    over, _, _ = render_targets(*args, timers=False, color_only=True, base=third)
    assert np.isfinite(over["color"].download()).all()
    ctx.recycle(*over.values(), *third.textures.values())


def test_a_base_of_another_context_is_refused(ctx):
    scene = _scene("fan")
    other = bl.Context(CLI_DEVICE)
    base, _ = render_base(other, scene, SIZE, scene.shutter, 0.0, 1, timers=False)
    with pytest.raises(ValueError, match="made by another context"):
        render_targets(
            ctx, scene, SIZE, scene.shutter, 0.0, timers=False, color_only=True, base=base
        )


def test_a_pass_keeps_no_base_before_it_has_rendered(ctx):
    from blurlab import _core

    fresh = _core.GBufferPass(ctx.native)
    with pytest.raises(RuntimeError, match="keep_base needs a G-buffer render first"):
        fresh.keep_base()
