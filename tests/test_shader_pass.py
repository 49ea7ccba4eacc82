"""The generic pass (src/passes/shader_pass.h, ctx.shader_pass): what reflect() lists, that a
read-modify-write output and tile restriction behave, and that bad names and value counts are
refused naming the shader and the name. That every method's passes give the same bits as the
dedicated pass classes they replaced is tests/test_golden.py's job (its hashes were recorded
with those classes)."""

from __future__ import annotations

import numpy as np
import pytest
from method_picks import pick

import blurlab as bl
from blurlab.methods.core import choice_defines, pass_uniforms

W, H, K = 53, 37, 8  # sizes that are no multiple of any work-group size
GRID = (-(-H // K), -(-W // K))
# tests/shaders/probe_gather.glsl: a gather shaped as a method's pass (a method's own passes are
# checked in its folder, python/blurlab/methods/<name>/test_<name>_shader.py).
PROBE = "probe_gather.glsl"
PROBE_DEFINES = {"EDGE_IGNORE": 1, "DIRECTION_CENTERED": 1}


def test_reflect_lists_what_a_pass_takes(ctx, test_shader):
    p = ctx.shader_pass(str(test_shader(PROBE)), PROBE_DEFINES)
    compute = p.reflect("compute")
    assert compute["samplers"] == {
        name: {"type": "sampler2D", "unit": unit} for unit, name in enumerate(("color", "motion"))
    }
    assert compute["images"] == {"result": {"type": "image2D", "unit": 0, "format": "rgba32f"}}
    assert compute["fragment_outputs"] == {}
    assert set(compute["uniforms"]) == {"taps", "intensity", "direction", "edge"}
    assert compute["uniforms"]["taps"] == {"type": "int", "count": 1}
    assert compute["uniforms"]["intensity"] == {"type": "float", "count": 1}
    fragment = p.reflect("fragment")
    assert fragment["images"] == {}
    assert fragment["fragment_outputs"] == {"result": {"type": "vec4", "location": 0}}
    camera = ctx.shader_pass(str(test_shader("probe_camera_motion.comp"))).reflect()
    assert camera["uniforms"]["clip_from_world"] == {"type": "mat4", "count": 32}
    assert camera["images"]["motion"]["format"] == "rg32f"
    # The format of the #ifdef branch the defines take (common/pass_main.glsl's HALF_RESULT).
    half = ctx.shader_pass(str(test_shader(PROBE)), {**PROBE_DEFINES, "HALF_RESULT": 1})
    assert half.reflect("compute")["images"]["result"]["format"] == "rgba16f"


def test_read_modify_write_output_accumulates(ctx, rng):
    color = rng.random((H, W, 4), dtype=np.float32)
    start = rng.random((H, W, 4), dtype=np.float32)
    total = ctx.upload(start)
    add = ctx.shader_pass("passes/accumulate.comp")
    add.run({"color": ctx.upload(color)}, {"sum": total}, {"weight": 0.25})
    np.testing.assert_allclose(total.download(), start + 0.25 * color, rtol=1e-6)


def test_errors_name_the_shader_and_the_name(ctx, rng, test_shader):
    p = ctx.shader_pass(str(test_shader(PROBE)), PROBE_DEFINES)
    out = ctx.empty((H, W, 4))
    inputs = {
        "color": ctx.upload(rng.random((H, W, 4), dtype=np.float32)),
        "motion": ctx.empty((H, W, 2)),
    }
    uniforms = {"taps": 5, "intensity": 1.0, "direction": 0, "edge": 0}
    with pytest.raises(
        ValueError, match=r"probe_gather.glsl has no sampler 'colour'.*color, motion"
    ):
        p.run({"colour": inputs["color"], "motion": inputs["motion"]}, {"result": out}, uniforms)
    with pytest.raises(
        ValueError, match=r"probe_gather.glsl: no texture given for its sampler\(s\) motion"
    ):
        p.run({"color": inputs["color"]}, {"result": out}, uniforms)
    with pytest.raises(ValueError, match=r"probe_gather.glsl has no image 'out'.*result"):
        p.run(inputs, {"out": out}, uniforms)
    with pytest.raises(ValueError, match=r"probe_gather.glsl has no uniform 'tap'.*taps"):
        p.run(inputs, {"result": out}, {**uniforms, "tap": 5})
    with pytest.raises(ValueError, match=r"probe_gather.glsl: uniform 'taps' takes 1 value.*got 2"):
        p.run(inputs, {"result": out}, {**uniforms, "taps": [5, 6]})
    with pytest.raises(ValueError, match=r"probe_gather.glsl: uniform 'taps' takes numbers"):
        p.run(inputs, {"result": out}, {**uniforms, "taps": "5"})
    with pytest.raises(ValueError, match=r"probe_gather.glsl draws one output.*result"):
        p.run(inputs, {"result": out, "more": out}, uniforms, "fragment")
    assert ctx.gl_errors() == []


def test_a_choice_parameter_reaches_the_shader_as_its_index():
    """edge = "ignore" is uniform 1 and EDGE_IGNORE = 1: both come from the one declaration."""
    name = pick(params=("edge", "direction"))  # a gather with both choices
    params = bl.method(name).params
    values = bl.method(name).defaults(None, edge="ignore", direction="centered")
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
