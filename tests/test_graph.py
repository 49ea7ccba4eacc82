"""The pass graph (blurlab.core.graph, docs/spec.md §1.2): passes bound by their shaders' names,
images pooled at the size of what they read and given back after their last reader unless kept."""

from __future__ import annotations

import numpy as np
import pytest

from blurlab.core.graph import Node, run_graph, wire


def _inputs(ctx, rng, height=9, width=13):
    rgb = rng.random((height, width, 4), dtype=np.float32)
    alpha = rng.random((height, width, 4), dtype=np.float32)
    return rgb, alpha, {"rgb": ctx.upload(rgb), "alpha": ctx.upload(alpha)}


def test_a_chain_binds_by_name_and_gives_back_what_no_later_pass_reads(ctx, rng):
    rgb, alpha, textures = _inputs(ctx, rng)
    nodes = [
        # rgb_alpha reads `rgb` and `alpha` and writes `result`: renamed to `combined`, read next
        Node("first", "passes/rgb_alpha.comp", writes=(("result", "combined"),)),
        Node("second", "passes/rgb_alpha.comp", reads=(("rgb", "combined"),)),
    ]
    wired = wire(ctx, nodes)
    assert wired[1].inputs == {"rgb": "combined", "alpha": "alpha"}
    made = []
    run = lambda w, inputs, outputs, uniforms: (  # noqa: E731
        made.append(outputs) or w.shader.run(inputs, outputs, uniforms)
    )
    kept = run_graph(ctx, wired, textures, keep={"result"}, run=run)
    assert set(kept) == {"result"}
    expected = np.concatenate([rgb[..., :3], alpha[..., 3:]], axis=2)
    np.testing.assert_array_equal(kept["result"].download(), expected)
    # `combined` went back to the pool after its last reader: the next texture of its shape is it
    combined = made[0]["result"]
    assert ctx.pooled(combined.shape) is combined


def test_every_image_is_returned_when_nothing_is_named(ctx, rng):
    _, _, textures = _inputs(ctx, rng)
    nodes = [Node("first", "passes/rgb_alpha.comp", writes=(("result", "combined"),))]
    kept = run_graph(ctx, wire(ctx, nodes), textures)
    assert set(kept) == {"combined"} and kept["combined"].shape == (9, 13, 4)


def test_a_missing_input_and_a_taken_name_are_refused_by_name(ctx, rng):
    _, _, textures = _inputs(ctx, rng)
    reads_nothing_given = [Node("lonely", "passes/rgb_alpha.comp", reads=(("rgb", "nowhere"),))]
    with pytest.raises(ValueError, match=r"pass lonely reads \['nowhere'\]"):
        run_graph(ctx, wire(ctx, reads_nothing_given), textures)
    overwrites = [Node("clash", "passes/rgb_alpha.comp", writes=(("result", "rgb"),))]
    with pytest.raises(ValueError, match="pass clash writes 'rgb'"):
        run_graph(ctx, wire(ctx, overwrites), textures)
    with pytest.raises(ValueError, match="no image 'nothing' to dispatch over"):
        wire(ctx, [Node("bad", "passes/rgb_alpha.comp", first_output="nothing")])
