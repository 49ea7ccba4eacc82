"""gather_coverage's tile dilation by scatter (docs/spec.md §17.6, "Steps 1–2 by scatter"):
by default its gather resolves the reach keys itself, matching its twin, with the same bits as
the gather dilation and the separate resolve pass. The dilation passes themselves are tested in
tests/test_scatter_dilation.py."""

from __future__ import annotations

import numpy as np
import pytest

import blurlab as bl
from blurlab.methods import eevee
from blurlab.twins import eevee as twin

METHOD = "gather_coverage"
# Its gather over its still and moving blocks (docs/spec.md §17.6.2)
GATHER = ["block_classify", "gather[still]", "gather[moving]"]


def test_it_scatters_by_default_and_matches_its_twin(ctx):
    frame = ctx.render(bl.scenes.get("fast_fan"), (160, 90))
    result = bl.blur(ctx, frame, METHOD)
    assert eevee.DILATION_LAYOUT.default == "scatter_in_gather"
    assert list(result.timings) == ["reach_keys_clear", "tile_flatten", *GATHER]
    expected = bl.method(METHOD).twin_output(frame, **result.params)
    within = (np.abs(result.color - expected).max(axis=-1) <= 1e-3).mean()
    assert within >= 0.999
    with eevee.DILATION_LAYOUT.use("gather"):
        gathered = bl.blur(ctx, frame, METHOD)
    assert gathered.color.tobytes() == result.color.tobytes()


@pytest.mark.parametrize("scene", ["fast_fan", "camera_yaw"])
def test_the_gather_can_resolve_the_keys_itself(ctx, scene):
    # scatter_in_gather: no resolve pass; the keys come back as a buffer, and decoded as the
    # gather decodes them they are the dilated tiles; the image is the same bits.
    frame = ctx.render(bl.scenes.get(scene), (160, 90))
    with eevee.DILATION_LAYOUT.use("scatter"):
        resolved = bl.blur(ctx, frame, METHOD)
    with eevee.DILATION_LAYOUT.use("scatter_in_gather"):
        in_gather = bl.blur(ctx, frame, METHOD)
    assert list(in_gather.timings) == ["reach_keys_clear", "tile_flatten", *GATHER]
    assert in_gather.color.tobytes() == resolved.color.tobytes()
    keys = in_gather.buffers["reach_keys"]
    assert keys.dtype == np.uint32 and keys.shape == (2 * 12, 20)  # 8 px tiles, 12 x 20
    decoded = twin.resolve_reach_keys(keys, in_gather.buffers["tiles"])
    assert decoded.tobytes() == resolved.buffers["dilated"].tobytes()
    assert "dilated" not in in_gather.buffers
