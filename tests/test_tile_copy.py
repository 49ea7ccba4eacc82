"""The still class's pass (shaders/passes/tile_copy.glsl): the color, bit for bit, on the
listed tiles only."""

from __future__ import annotations

import numpy as np
from conftest import random_frame
from test_classify_tiles import gpu_classification, structured_motion

SHADER = "passes/tile_copy.glsl"


def test_whole_image_copy_is_the_identity(ctx, rng):
    frame = random_frame(rng, 67, 45)
    color, result = ctx.upload(frame.color), ctx.empty((45, 67, 4))
    ctx.shader_pass(SHADER).run({"color": color}, {"result": result})
    assert result.download().tobytes() == frame.color.tobytes()


def test_restricted_copy_writes_the_listed_tiles_only(ctx, rng):
    k = 10
    frame = structured_motion(rng, 130, 70, k)
    _, _, classes, lists = gpu_classification(ctx, frame, k, 0.25)
    color, result = ctx.upload(frame.color), ctx.empty((70, 130, 4))
    with ctx.shader_pass(SHADER).restricted_to(lists, 0) as copy:
        copy.run({"color": color}, {"result": result})
    still = np.kron(classes == 0, np.ones((k, k), bool))[:70, :130]
    out = result.download()
    assert still.any() and (~still).any()
    assert out[still].tobytes() == frame.color[still].tobytes()
    assert not out[~still].any()  # the other tiles keep what the target held (zeros)
