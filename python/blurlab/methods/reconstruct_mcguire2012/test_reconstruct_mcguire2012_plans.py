"""reconstruct_mcguire2012's untimed calls are recorded as a dispatch plan and replayed with the
ordinary path's bits (blurlab.methods.plans; what every plan does:
tests/test_dispatch_plans.py)."""

from __future__ import annotations

import pytest
from plan_replay import check_replay

METHOD = "reconstruct_mcguire2012"


@pytest.mark.parametrize(
    ("backend", "params"),
    [
        ("compute", {"k": 20, "samples": 15}),
        ("fragment", {"k": 8, "samples": 9, "jitter_tiles": 1}),
    ],
)
def test_a_replay_gives_the_ordinary_bits(ctx, backend, params):
    check_replay(ctx, METHOD, backend, params)
