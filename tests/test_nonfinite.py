"""NaN and infinity inside input buffers (docs/reliability.md "Non-finite input"): NaN color is
0, infinite color clamps to +-2^64, NaN/zero/negative depth is far, NaN or infinite motion is
no motion. The GPU (shaders/common/inputs.glsl) and the NumPy references
(bl.twins.inputs) read them alike, and no NaN spreads through any blur."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import blurlab as bl
from blurlab.twins import gathers, inputs

W, H = 48, 32


def poisoned(rng, frame: bl.Frame, fraction: float = 0.1, both_signs: bool = True) -> bl.Frame:
    """`frame` with NaN, +-inf, zero and negative values scattered through color, depth and
    motion; a rendered frame keeps its scene and camera (methods that re-render still can).
    `both_signs=False` poisons color with NaN and +inf only: sums of +2^64 and -2^64 cancel
    differently in float32 and float64, so the GPU-vs-reference comparisons avoid them."""
    color, depth, motion = frame.color.copy(), frame.depth.copy(), frame.motion.copy()
    for array, values in (
        (color, [np.nan, np.inf, -np.inf, 3e38] if both_signs else [np.nan, np.inf, 3e38]),
        (depth, [np.nan, -np.inf, 0.0, -2.0]),
        # 3e38 clamps to 2^20 px, every such vector to length k: TileMax ties ("any" may win).
        (motion, [np.nan, np.inf, -np.inf, 3e38] if both_signs else [np.nan, np.inf]),
    ):
        mask = rng.random(array.shape) < fraction
        array[mask] = rng.choice(values, int(mask.sum()))
    return dataclasses.replace(frame, color=color, depth=depth, motion=motion, textures={})


@pytest.fixture(scope="module")
def rendered(ctx):
    scene = bl.scenes.fan()
    return {i: ctx.render(scene, (W, H), instant=i) for i in ("center", "close")}


def test_all_nan_frame_is_still_finite(ctx):
    nan = np.full((H, W, 4), np.nan, np.float32)
    frame = bl.Frame(color=nan, depth=nan[..., 0], motion=nan[..., :2])
    for name in ("reconstruct_mcguire2012", "reconstruct_urho3d", "gather_box", "trail"):
        out = bl.blur(ctx, frame, name).color
        np.testing.assert_array_equal(out, 0.0)  # NaN color is 0, NaN motion is none


def assert_close(gpu, ref):
    """float32 against float64 where colors of 2^64 take part: a pixel that mixes in such a
    color carries float32's rounding of weights times 2^64."""
    tolerance = 2e-4 + 2e-4 * np.abs(ref) + np.where(np.abs(ref) > 1e6, 2e-6 * 2.0**64, 0.0)
    bad = np.abs(gpu - ref) > tolerance
    assert not bad.any(), f"{bad.sum()} values differ, e.g. {gpu[bad][:3]} vs {ref[bad][:3]}"


def array_frame(rng, nan_color_only: bool = False):
    from conftest import random_frame

    frame = random_frame(rng, W, H, k=8)
    frame = poisoned(rng, frame, 0.15, both_signs=False)
    if nan_color_only:  # bilinear weights of exactly 0 are ~1e-8 in float32: times 2^64 ...
        frame.color[np.abs(frame.color) > 1e6] = np.nan
    return frame


def test_reconstruct_matches_reference_on_poisoned_input(ctx, rng):
    frame = array_frame(rng)
    params = dict(k=8, samples=9, soft_z=0.5, exposure=1.0, seed=3)
    gpu = bl.blur(ctx, frame, "reconstruct_mcguire2012", **params).color
    ref = bl.method("reconstruct_mcguire2012").twin_output(frame, **params)
    assert np.isfinite(gpu).all() and np.isfinite(ref).all()
    assert_close(gpu, ref)


def test_urho3d_matches_reference_on_poisoned_input(ctx, rng):
    frame = array_frame(rng, nan_color_only=True)
    params = dict(k=8, samples=9, soft_z=0.5, exposure=1.0, seed=3, far=20.0)
    gpu = bl.blur(ctx, frame, "reconstruct_urho3d", **params).color
    ref = bl.method("reconstruct_urho3d").twin_output(frame, **params)
    assert np.isfinite(gpu).all()
    assert_close(gpu, ref)


@pytest.mark.parametrize("edge", ["clamp", "ignore"])
def test_gathers_match_reference_on_poisoned_input(ctx, rng, edge):
    frame = array_frame(rng)
    box = bl.blur(ctx, frame, "gather_box", taps=6, edge=edge).color
    assert_close(box, bl.method("gather_box").twin_output(frame, taps=6, edge=edge))
    weighted = bl.blur(ctx, frame, "gather_weighted", edge=edge).color
    assert_close(weighted, gathers.gather_weighted(frame.color, frame.motion, edge=edge))


def test_sanitize_rules():
    np.testing.assert_array_equal(
        inputs.sanitize_color([np.nan, np.inf, -np.inf, 1.5, 1e30]),
        [0.0, 2.0**64, -(2.0**64), 1.5, 2.0**64],
    )
    np.testing.assert_array_equal(
        inputs.sanitize_depth([np.nan, 0.0, -1.0, -np.inf, np.inf, 2.0]),
        [np.inf, np.inf, np.inf, np.inf, np.inf, 2.0],
    )
    np.testing.assert_array_equal(
        inputs.sanitize_motion([[np.nan, 1.0], [np.inf, 0.0], [3.0, -4.0], [1e9, -1e9]]),
        [[0.0, 0.0], [0.0, 0.0], [3.0, -4.0], [2.0**20, -(2.0**20)]],
    )


def test_gpu_reads_inputs_as_the_reference_does(ctx):
    """A gather of one tap per pixel (motion 0) is the sanitized color itself."""
    values = np.array([np.nan, np.inf, -np.inf, 3e38, -3e38, 1.0, -0.0, 1e-45], np.float32)
    color = np.resize(values, (2, 4, 4)).astype(np.float32)
    frame = bl.Frame(color=color, depth=np.ones((2, 4), np.float32), motion=np.zeros((2, 4, 2)))
    out = bl.blur(ctx, frame, "gather_box", taps=2).color
    expected = inputs.sanitize_color(color).astype(np.float32)
    # GPUs may flush denormals (1e-45) to zero in shader arithmetic (the H100 does); GL allows
    # it, so a denormal input reads as itself or as zero, and everything else exactly.
    denormal = (expected != 0) & (np.abs(expected) < np.finfo(np.float32).tiny)
    assert ((out == expected) | (denormal & (out == 0))).all()
    assert (out[~denormal] == expected[~denormal]).all()
