"""accumulation (docs/spec.md §4; spec.md here): the reference of docs/spec.md §11 with a small N,
uniform sub-frame times by default."""

from __future__ import annotations

import pytest

import blurlab as bl


def test_it_is_the_small_n_reference(ctx):
    scene = bl.scenes.fan()
    frame = ctx.render(scene, (64, 64))
    result = bl.blur(ctx, frame, "accumulation", samples=4)
    reference = ctx.reference(scene, (64, 64), samples=4, stratified=False, progress=False)
    assert result.color.tobytes() == reference.color.tobytes()
    with pytest.raises(ValueError, match=r"samples = 0 is outside 1\.\.4096"):
        bl.blur(ctx, frame, "accumulation", samples=0)
