"""engine_unity's untimed calls are recorded as a dispatch plan and replayed with the ordinary
path's bits (blurlab.methods.plans; what every plan does: tests/test_dispatch_plans.py)."""

from __future__ import annotations

from plan_replay import check_replay

METHOD = "engine_unity"


def test_a_replay_gives_the_ordinary_bits(ctx):
    check_replay(ctx, METHOD, "compute", {})
