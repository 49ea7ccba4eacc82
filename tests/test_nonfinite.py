"""NaN and infinity inside input buffers (docs/reliability.md "Non-finite input"): NaN color is
0, infinite color clamps to +-2^64, NaN/zero/negative depth is far, NaN or infinite motion is
no motion. The GPU (shaders/common/inputs.glsl) and the NumPy references
(bl.twins.inputs) read them alike, and no NaN spreads through any blur."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from method_picks import EXAMPLE, builtin, pick, picks
from poisoned_frames import H, W, array_frame, assert_close

import blurlab as bl
from blurlab.twins import inputs


@pytest.fixture(scope="module")
def rendered(ctx):
    scene = bl.scenes.fan()
    return {i: ctx.render(scene, (W, H), instant=i) for i in ("center", "close")}


def test_all_nan_frame_is_still_finite(ctx, rendered):
    nan = np.full((H, W, 4), np.nan, np.float32)
    # every method that blurs the frame it is given (those that render read the scene); a
    # rendered frame's camera stays, for the methods that read the camera's motion
    for name in (n for n in builtin() if not bl.method(n).renders):
        given = rendered[bl.method_instant(name)]
        frame = dataclasses.replace(
            given, color=nan, depth=nan[..., 0], motion=nan[..., :2], textures={}
        )
        out = bl.blur(ctx, frame, name).color
        np.testing.assert_array_equal(out, 0.0)  # NaN color is 0, NaN motion is none


def test_reconstruct_matches_reference_on_poisoned_input(ctx, rng):
    frame = array_frame(rng)
    params = dict(k=8, samples=9, soft_z=0.5, exposure=1.0, seed=3)
    gpu = bl.blur(ctx, frame, EXAMPLE, **params).color
    ref = bl.method(EXAMPLE).twin_output(frame, **params)
    assert np.isfinite(gpu).all() and np.isfinite(ref).all()
    assert_close(gpu, ref)


@pytest.mark.parametrize("edge", ["clamp", "ignore"])
@pytest.mark.parametrize("name", picks(kind="gather", params=("edge",), twin=True))
def test_gathers_match_reference_on_poisoned_input(ctx, rng, edge, name):
    frame = array_frame(rng)
    params = {"edge": edge, **({"taps": 6} if "taps" in bl.method(name).params else {})}
    gpu = bl.blur(ctx, frame, name, **params).color
    assert_close(gpu, bl.method(name).twin_output(frame, **params))


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
    out = bl.blur(ctx, frame, pick(kind="gather", params=("taps",)), taps=2).color
    expected = inputs.sanitize_color(color).astype(np.float32)
    # GPUs may flush denormals (1e-45) to zero in shader arithmetic (the H100 does); GL allows
    # it, so a denormal input reads as itself or as zero, and everything else exactly.
    denormal = (expected != 0) & (np.abs(expected) < np.finfo(np.float32).tiny)
    assert ((out == expected) | (denormal & (out == 0))).all()
    assert (out[~denormal] == expected[~denormal]).all()
