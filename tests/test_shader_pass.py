"""The generic pass (src/passes/shader_pass.h, ctx.shader_pass): what reflect() lists, that a
read-modify-write output and tile restriction behave, and that bad names and value counts are
refused naming the shader and the name. That every method's passes give the same bits as the
dedicated pass classes they replaced is tests/test_golden.py's job (its hashes were recorded
with those classes)."""

from __future__ import annotations

import numpy as np
import pytest

import blurlab as bl
from blurlab.methods.core import choice_defines, pass_uniforms
from blurlab.methods.reconstruct_mcguire2012 import method as mcguire2012
from blurlab.methods.tile_filter import variant_defines

W, H, K = 53, 37, 8  # sizes that are no multiple of any work-group size
GRID = (-(-H // K), -(-W // K))
FILTER_INPUTS = ("color", "depth", "motion", "neighbor_max")
FILTER_UNIFORMS = {
    "k",
    "samples",
    "soft_z",
    "exposure",
    "seed",
    "early_exit",
}


def test_reflect_lists_what_a_pass_takes(ctx):
    # The options that pick a variant are #defines (tile_filter.variant_defines), not uniforms.
    p = ctx.shader_pass(mcguire2012.RECONSTRUCT.shader, {"JITTER_TILES": 0, "ADAPTIVE_SAMPLES": 1})
    compute = p.reflect("compute")
    assert compute["samplers"] == {
        name: {"type": "sampler2D", "unit": unit} for unit, name in enumerate(FILTER_INPUTS)
    }
    assert compute["images"] == {"result": {"type": "image2D", "unit": 0, "format": "rgba32f"}}
    assert compute["fragment_outputs"] == {}
    assert set(compute["uniforms"]) == FILTER_UNIFORMS
    assert compute["uniforms"]["seed"] == {"type": "uint", "count": 1}
    fragment = p.reflect("fragment")
    assert fragment["images"] == {}
    assert fragment["fragment_outputs"] == {"result": {"type": "vec4", "location": 0}}
    camera = ctx.shader_pass("passes/camera_motion.glsl").reflect()
    assert camera["uniforms"]["clip_from_world"] == {"type": "mat4", "count": 32}
    assert camera["images"]["motion"]["format"] == "rg32f"
    # The format of the #ifdef branch the defines take (common/pass_main.glsl's HALF_RESULT).
    half = ctx.shader_pass(
        mcguire2012.RECONSTRUCT.shader,
        {"JITTER_TILES": 0, "ADAPTIVE_SAMPLES": 0, "HALF_RESULT": 1},
    )
    assert half.reflect("compute")["images"]["result"]["format"] == "rgba16f"


def test_a_method_pass_takes_its_parameters_under_their_own_names(ctx):
    """The uniforms a method's reconstruct pass declares are exactly the parameters it hands
    over (blurlab/methods/reconstruct_mcguire2012/method.py), named as in Python."""

    values = {
        "jitter_tiles": 0,
        "adaptive_samples": 0,
        "packed_inputs": False,
        "half_result": False,
    }
    shader = ctx.shader_pass(mcguire2012.RECONSTRUCT.shader, variant_defines(values))
    assert set(shader.reflect()["uniforms"]) == set(mcguire2012.RECONSTRUCT.params)
    with pytest.raises(bl.ShaderError, match="JITTER_TILES and ADAPTIVE_SAMPLES"):
        ctx.shader_pass(mcguire2012.RECONSTRUCT.shader).reflect()


def test_read_modify_write_output_accumulates(ctx, rng):
    color = rng.random((H, W, 4), dtype=np.float32)
    start = rng.random((H, W, 4), dtype=np.float32)
    total = ctx.upload(start)
    add = ctx.shader_pass("passes/accumulate.comp")
    add.run({"color": ctx.upload(color)}, {"sum": total}, {"weight": 0.25})
    np.testing.assert_allclose(total.download(), start + 0.25 * color, rtol=1e-6)


def test_errors_name_the_shader_and_the_name(ctx, rng):
    p = ctx.shader_pass("passes/gather_box.glsl", {"EDGE_IGNORE": 1, "DIRECTION_CENTERED": 1})
    out = ctx.empty((H, W, 4))
    inputs = {
        "color": ctx.upload(rng.random((H, W, 4), dtype=np.float32)),
        "motion": ctx.empty((H, W, 2)),
    }
    uniforms = {"taps": 5, "intensity": 1.0, "direction": 0, "edge": 0}
    with pytest.raises(ValueError, match=r"gather_box.glsl has no sampler 'colour'.*color, motion"):
        p.run({"colour": inputs["color"], "motion": inputs["motion"]}, {"result": out}, uniforms)
    with pytest.raises(
        ValueError, match=r"gather_box.glsl: no texture given for its sampler\(s\) motion"
    ):
        p.run({"color": inputs["color"]}, {"result": out}, uniforms)
    with pytest.raises(ValueError, match=r"gather_box.glsl has no image 'out'.*result"):
        p.run(inputs, {"out": out}, uniforms)
    with pytest.raises(ValueError, match=r"gather_box.glsl has no uniform 'tap'.*taps"):
        p.run(inputs, {"result": out}, {**uniforms, "tap": 5})
    with pytest.raises(ValueError, match=r"gather_box.glsl: uniform 'taps' takes 1 value.*got 2"):
        p.run(inputs, {"result": out}, {**uniforms, "taps": [5, 6]})
    with pytest.raises(ValueError, match=r"gather_box.glsl: uniform 'taps' takes numbers"):
        p.run(inputs, {"result": out}, {**uniforms, "taps": "5"})
    with pytest.raises(ValueError, match=r"gather_box.glsl draws one output.*result"):
        p.run(inputs, {"result": out, "more": out}, uniforms, "fragment")
    assert ctx.gl_errors() == []


def test_a_choice_parameter_reaches_the_shader_as_its_index():
    """edge = "ignore" is uniform 1 and EDGE_IGNORE = 1: both come from the one declaration."""

    params = bl.method("gather_box").params
    values = bl.method("gather_box").defaults(None, edge="ignore", direction="centered")
    uniforms = pass_uniforms(params, values, ("edge", "direction"))
    defines = choice_defines(params, ("edge", "direction"))
    assert uniforms == {"edge": defines["EDGE_IGNORE"], "direction": defines["DIRECTION_CENTERED"]}
    assert defines == {
        "EDGE_CLAMP": 0,
        "EDGE_IGNORE": 1,
        "EDGE_GUARD": 2,
        "DIRECTION_BACKWARD": 0,
        "DIRECTION_CENTERED": 1,
    }
