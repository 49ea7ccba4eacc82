"""reconstruct_mcguire2012's reconstruct pass as ctx.shader_pass reflects it: the tile filter's
inputs and uniforms, its variant defines, and exactly the parameters the method hands over,
under their own names (what reflect() lists for any pass: tests/test_shader_pass.py)."""

from __future__ import annotations

import pytest

import blurlab as bl
from blurlab.methods.reconstruct_mcguire2012 import method as declared
from blurlab.methods.tile_filter import variant_defines

FILTER_INPUTS = ("color", "depth", "motion", "neighbor_max")
FILTER_UNIFORMS = {"k", "samples", "soft_z", "exposure", "seed", "early_exit"}


def test_reflect_lists_what_the_reconstruct_pass_takes(ctx):
    # The options that pick a variant are #defines (tile_filter.variant_defines), not uniforms.
    shader = declared.RECONSTRUCT.shader
    p = ctx.shader_pass(shader, {"JITTER_TILES": 0, "ADAPTIVE_SAMPLES": 1})
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
    half = ctx.shader_pass(shader, {"JITTER_TILES": 0, "ADAPTIVE_SAMPLES": 0, "HALF_RESULT": 1})
    assert half.reflect("compute")["images"]["result"]["format"] == "rgba16f"


def test_the_pass_takes_its_parameters_under_their_own_names(ctx):
    """The uniforms the reconstruct pass declares are exactly the parameters it hands over,
    named as in Python."""
    values = {
        "jitter_tiles": 0,
        "adaptive_samples": 0,
        "packed_inputs": False,
        "half_result": False,
    }
    shader = ctx.shader_pass(declared.RECONSTRUCT.shader, variant_defines(values))
    assert set(shader.reflect()["uniforms"]) == set(declared.RECONSTRUCT.params)
    with pytest.raises(bl.ShaderError, match="JITTER_TILES and ADAPTIVE_SAMPLES"):
        ctx.shader_pass(declared.RECONSTRUCT.shader).reflect()
