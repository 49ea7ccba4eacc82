"""gather_pixel's untimed calls are recorded as a dispatch plan and replayed with the ordinary
path's bits (blurlab.methods.plans; what every plan does: tests/test_dispatch_plans.py)."""

from __future__ import annotations

import pytest
from plan_replay import check_replay

METHOD = "gather_pixel"


@pytest.mark.parametrize(
    ("backend", "params"),
    [
        ("compute", {}),
        ("fragment", {"samples": 4}),
    ],
)
def test_a_replay_gives_the_ordinary_bits(ctx, backend, params):
    check_replay(ctx, METHOD, backend, params)
