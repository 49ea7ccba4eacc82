"""The failure-case suite (docs/failure_cases.md): where post-process blur breaks, guarded."""

from __future__ import annotations

import numpy as np
import pytest
from method_picks import EXAMPLE, picks

import blurlab as bl
from blurlab import failures
from blurlab.studies.sweep import default_grids

SIZE = (64, 36)
POST_PROCESS = [m for m in default_grids() if not bl.method(m).renders]
# A method's own failures on a scene (the box gather's lag on a turning camera, ...) are tested
# in its folder (python/blurlab/methods/<name>/test_<name>_failures.py).


@pytest.fixture(scope="module")
def frames(ctx):
    """Each failure scene rendered at both instants, once for the module."""
    return {
        name: {i: ctx.render(bl.scenes.get(name), SIZE, instant=i) for i in ("center", "close")}
        for name in bl.scenes.names("failure")
    }


def test_the_suite_lists_fourteen_tagged_scenes():
    names = bl.scenes.names("failure")
    assert len(names) == 14 and not set(names) & set(bl.scenes.names())
    with pytest.raises(ValueError, match="tag"):
        bl.scenes.names("broken")


@pytest.mark.parametrize("scene", bl.scenes.names("failure"))
def test_no_nan_inf_or_colors_outside_the_input_range(ctx, frames, scene):
    for name in POST_PROCESS:
        frame = frames[scene][bl.method_instant(name)]
        out = bl.blur(ctx, frame, name).color
        assert np.isfinite(out).all(), name
        lo, hi = frame.color.min(axis=(0, 1)), frame.color.max(axis=(0, 1))
        assert (out >= lo - 1e-5).all() and (out <= hi + 1e-5).all(), name
    for name in [
        m for m in bl.methods() if bl.method(m).renders
    ]:  # their inputs are other renders: finite is asked
        assert np.isfinite(bl.blur(ctx, frames[scene]["center"], name).color).all(), name


@pytest.mark.parametrize("name", list(default_grids()))
def test_every_method_is_deterministic(ctx, frames, name):
    frame = frames["crossing"][bl.method_instant(name)]
    first = bl.blur(ctx, frame, name).color
    assert bl.blur(ctx, frame, name).color.tobytes() == first.tobytes()


def test_still_pixels_stay_still_with_8_bit_offset_motion(ctx):
    scene = bl.scenes.long_motion()
    size = (256, 144)
    for instant in ("center", "close"):
        exact = ctx.render(scene, size, instant=instant)
        stored = ctx.render(scene, size, instant=instant, motion_format="rgba8_offset")
        assert not stored.motion[exact.motion == 0].any()  # zero decodes to zero
        # Rows far from anything that moves: beyond the reach of NeighborMax (two tiles of 20).
        # Moving: over 0.01 px, the G-buffer's accuracy (tests/test_gbuffer.py); the H100
        # leaves rounding-sized motion on still surfaces that this test is not about.
        moving = np.abs(exact.motion).max(axis=-1) > 0.01
        ys, _ = np.nonzero(moving)
        far = np.ones(moving.shape, bool)
        far[max(ys.min() - 45, 0) : ys.max() + 45] = False
        assert far.sum() > 500
        for name in POST_PROCESS:
            if bl.method_instant(name) != instant:
                continue
            out = bl.blur(ctx, stored, name).color
            assert np.abs(out - stored.color)[far].max() <= 1e-6, name  # weights: rounding only


def test_guard_band_removes_the_edge_error_clamping_leaves(ctx):
    scene = bl.scenes.camera_yaw()
    size = (96, 54)
    reference = ctx.reference(scene, size, samples=128, progress=False).color
    frame = ctx.render(scene, size, instant="close")
    assert frame.motion[..., 0].mean() > 0  # the world moves right: backward taps leave left
    border = np.zeros(size[::-1], bool)
    border[:, :10] = True
    # every gather with the edge option that blurs the closing frame (backward taps)
    edged = [n for n in picks(kind="gather", params=("edge",)) if bl.method_instant(n) == "close"]
    assert edged
    for name in edged:
        clamp = bl.blur(ctx, frame, name, edge="clamp").color
        guard = bl.blur(ctx, frame, name, edge="guard").color
        clamped, guarded = (np.abs(out - reference)[border].mean() for out in (clamp, guard))
        assert guarded < clamped, name


def test_failure_table_has_every_measure(ctx):
    # a method with a seed (jittered taps) and a gather without one
    unseeded = next(n for n in picks(kind="gather") if "seed" not in bl.method(n).params)
    assert "seed" in bl.method(EXAMPLE).params
    table = failures.evaluate(
        ctx,
        ["occluder"],
        [EXAMPLE, unseeded],
        SIZE,
        frames=3,
        reference_samples=16,
        progress=False,
    )
    assert len(table) == 2
    for column in (
        "psnr",
        "ssim",
        "nan",
        "inf",
        "outside_input_range",
        "flicker",
        "seed_noise",
        "k_spread_db",
        "psnr_soft_z_x100",
        "soft_z_spread_db",
    ):
        assert column in table.columns
    assert (table["nan"] == 0).all() and (table["inf"] == 0).all()
    by_method = table.set_index("method")
    assert by_method.loc[EXAMPLE, "seed_noise"] > 0  # jittered taps
    assert by_method.loc[unseeded, "seed_noise"] == 0  # no seed, no noise


def test_every_failure_scene_says_what_it_shows():
    for name in bl.scenes.names("failure") + bl.scenes.names():
        assert len(bl.scenes.describe(name)) > 20, name
    with pytest.raises(ValueError, match="no built-in scene"):
        bl.scenes.describe("nothing")


def test_the_depth_test_keeps_a_still_occluder_sharp(ctx):
    """soft_z matters: at the default the post in front of the moving box stays sharp; a
    soft_z spanning the whole scene turns the depth test off and the box smears over it."""
    scene = bl.scenes.occluder()
    size = (96, 54)
    frame = ctx.render(scene, size)
    post = frame.object_id == [o.name for o in scene.objects].index("post")
    soft_z = bl.blur(ctx, frame, EXAMPLE).params["soft_z"]
    default = bl.blur(ctx, frame, EXAMPLE).color
    no_depth_test = bl.blur(ctx, frame, EXAMPLE, soft_z=soft_z * 100).color
    sharp = frame.color
    assert np.abs(default - sharp)[post].mean() < 0.5 * np.abs(no_depth_test - sharp)[post].mean()
