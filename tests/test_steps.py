"""`steps` (docs/classify_and_steps.md): n sub-intervals of the shutter, each rendered and
blurred over its own sub-interval, then averaged — from pure post-process (n = 1) to the
reference (n = N, where no sub-interval moves far enough to blur)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from method_picks import EXAMPLE, picks

import blurlab as bl

FILTER = EXAMPLE  # a tile filter, which blurs the frame at the shutter's center
# A gather with taps that blurs the frame at the shutter's close (backward taps).
BOX = next(n for n in picks(kind="gather", params=("taps",)) if bl.method_instant(n) == "close")
RENDERS = picks(kind="render")  # methods that render their own sub-frames: no steps


def test_one_step_is_the_plain_render_and_blur_bit_for_bit(ctx):
    scene = bl.scenes.get("teapot_pass")
    frame = ctx.render(scene, (96, 54))
    plain = bl.blur(ctx, frame, FILTER, k=10)
    stepped_frame, stepped = bl.render_and_blur(ctx, scene, FILTER, (96, 54), steps=1, k=10)
    assert stepped.color.tobytes() == plain.color.tobytes()
    assert stepped_frame.time == frame.time and "steps" not in stepped.params
    again = bl.blur_steps(ctx, [frame], FILTER, k=10)
    assert again.color.tobytes() == plain.color.tobytes()


@pytest.mark.parametrize("scene", ["fan", "fast_fan"])
@pytest.mark.parametrize("name", [FILTER, BOX])
def test_steps_reduce_the_rotating_fan_error_monotonically(ctx, scene, name):
    size = (96, 54)
    s = bl.scenes.get(scene)
    reference = ctx.reference(s, size, samples=256, progress=False)
    psnr = [
        bl.metrics.psnr(reference.color, bl.render_and_blur(ctx, s, name, size, steps=n)[1].color)
        for n in (1, 2, 4)
    ]
    # Measured on llvmpipe (dB): fan 25.6 / 30.3 / 35.9 (filter), 17.4 / 22.2 / 27.9 (box);
    # fast_fan 19.5 / 26.8 / 31.5 and 18.5 / 21.1 / 25.6.
    assert psnr[0] + 1.0 < psnr[1] and psnr[1] + 1.0 < psnr[2], psnr


def test_as_many_steps_as_reference_samples_is_the_uniform_reference(ctx):
    """With N steps each sub-interval moves less than a pixel, so the filter returns the sharp
    render at the sub-interval's center — the reference's uniform sample time — and both
    accumulate the same N images with weight 1/N in the same order."""
    scene = bl.scenes.get("teapot_pass")
    size = (64, 36)
    frame = ctx.render(scene, size)
    n = 2 * math.ceil(np.linalg.norm(frame.motion, axis=-1).max())
    frames, stepped = bl.render_and_blur(ctx, scene, FILTER, size, steps=n)
    assert len(frames) == n
    assert max(np.linalg.norm(f.motion, axis=-1).max() for f in frames) <= 1.0
    reference = ctx.reference(scene, size, samples=n, stratified=False, progress=False)
    assert stepped.color.tobytes() == reference.color.tobytes()


def test_sub_intervals_tile_the_shutter_and_timings_add_up(ctx):
    scene = bl.scenes.get("fan")
    frames = bl.render_steps(ctx, scene, BOX, 3, (48, 32))
    t0, t1 = scene.shutter
    assert frames[0].shutter[0] == t0 and frames[-1].shutter[1] == t1
    for a, b in zip(frames, frames[1:], strict=False):
        assert a.shutter[1] == b.shutter[0]
    assert all(f.time == f.shutter[1] for f in frames)  # the gather's instant: close
    result = bl.blur_steps(ctx, frames, BOX)
    assert result.params["steps"] == 3
    passes = set(bl.blur(ctx, frames[0], BOX).timings)  # the gather's own, once per step
    assert set(result.timings) == passes | {"steps_accumulate", "extra_gbuffers"}
    assert result.timings["extra_gbuffers"].ms == pytest.approx(
        sum(f.timings["gbuffer"].ms for f in frames[1:])
    )


def test_sweeps_vary_steps(ctx):
    table = bl.sweep(
        ctx,
        ["fan"],
        {BOX: {"steps": [1, 2]}, FILTER: {}},
        size=(48, 32),
        reference_samples=64,
        metrics=("psnr",),
        progress=False,
        repeats=1,
    )
    boxes = table[table["method"] == BOX].set_index("param_steps")
    assert boxes.loc[2, "psnr"] > boxes.loc[1, "psnr"]
    assert "ms_extra_gbuffers" in table.columns
    filters = table[table["method"] == FILTER]
    assert len(filters) == 1 and np.isfinite(filters["psnr"]).all()
    plain = bl.sweep(
        ctx,
        ["fan"],
        {BOX: {}},
        size=(48, 32),
        reference_samples=64,
        metrics=("psnr",),
        progress=False,
        repeats=1,
    )
    assert plain["psnr"].iloc[0] == boxes.loc[1, "psnr"]


@pytest.mark.parametrize(
    ("call", "error", "message"),
    [
        (
            lambda ctx, s: bl.render_and_blur(ctx, s, FILTER, (16, 16), steps=0),
            ValueError,
            r"steps = 0 is outside 1\.\.256",
        ),
        (
            lambda ctx, s: bl.render_and_blur(ctx, s, FILTER, (16, 16), steps=2.0),
            TypeError,
            "steps must be an integer",
        ),
        (
            lambda ctx, s: bl.render_and_blur(ctx, s, RENDERS[0], (16, 16), steps=2),
            ValueError,
            "renders its own sub-frames",
        ),
        (
            lambda ctx, s: bl.blur(ctx, ctx.render(s, (16, 16)), FILTER, steps=2),
            TypeError,
            "no parameter",
        ),
        (
            lambda ctx, s: bl.sweep(ctx, [s], {RENDERS[-1]: {"steps": [2]}}, progress=False),
            ValueError,
            "renders its own sub-frames",
        ),
    ],
)
def test_bad_steps_are_named(ctx, call, error, message):
    with pytest.raises(error, match=message):
        call(ctx, bl.scenes.get("fan"))
