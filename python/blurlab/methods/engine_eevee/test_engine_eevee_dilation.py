"""engine_eevee's tile dilation: its exact tile lengths do not fit the scatter dilation's keys
(docs/spec.md §17.6, "Steps 1–2 by scatter"), so it gathers whatever the dilation layout says.
The dilation passes themselves are tested in tests/test_scatter_dilation.py."""

from __future__ import annotations

import pytest
from conftest import random_frame

import blurlab as bl
from blurlab.methods import eevee

METHOD = "engine_eevee"


@pytest.mark.parametrize("layout", [None, *eevee.DILATION_VARIANTS])
def test_it_gathers_under_every_dilation_layout(ctx, rng, layout):
    frame = random_frame(rng, 72, 40, k=8)
    with eevee.DILATION_LAYOUT.use(layout or eevee.DILATION_LAYOUT.default):
        result = bl.blur(ctx, frame, METHOD, tile_size=8)
    assert "tile_dilate" in result.timings
    assert "tile_resolve" not in result.timings and "reach_keys_clear" not in result.timings
