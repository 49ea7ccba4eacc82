"""The promises of the motion-blur filters (tests/filter_promises.py), one table for all of
them: a still frame comes back unchanged, the output stays inside the input range, zero, tiny and
huge motion give no NaN, the same seed gives the same bits. Each row says how its method is tried:
the frame (engine_eevee reads two-sided motion) and the parameters that let its blur reach far
enough to be tested."""

from __future__ import annotations

import pytest
from filter_promises import PROMISES, Tried, two_sided_frame

TRIED = {
    "engine_eevee": Tried(two_sided_frame, {"tile_size": 16}, {"max_blur": 1e6, "tile_size": 16}),
    "engine_unity": Tried(inside={"max_radius": 15.0}, huge={"max_radius": 50.0}),
    "engine_hdrp": Tried(inside={"fast_ratio": 0.2}, huge={"maximum_velocity": 65024.0}),
    "engine_unreal": Tried(inside={"max_blur": 15.0}, huge={"max_blur": 100.0}),
    "engine_unreal5": Tried(),
    "engine_jimenez2014": Tried(),
    "gather_coverage": Tried(inside={"max_blur": 40.0}, huge={"max_blur": 50.0}),
    "gather_pixel": Tried(),
}


@pytest.mark.parametrize("promise", list(PROMISES))
@pytest.mark.parametrize("method", list(TRIED))
def test_every_filter_keeps_its_promises(ctx, rng, method, promise):
    PROMISES[promise](ctx, rng, method, TRIED[method])
