"""engine_unreal5's calls take the ordinary path, never a recorded dispatch plan: its passes run
over tile lists (blurlab.methods.plans; what every plan does: tests/test_dispatch_plans.py)."""

from __future__ import annotations

from plan_replay import check_no_plan

METHOD = "engine_unreal5"


def test_its_runs_take_the_ordinary_path(ctx):
    check_no_plan(ctx, METHOD, {"directions": 2})
