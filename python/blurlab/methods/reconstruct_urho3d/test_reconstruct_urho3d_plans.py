"""reconstruct_urho3d's calls take the ordinary path, never a recorded dispatch plan: it reads a
cached lookup texture (blurlab.methods.plans; what every plan does:
tests/test_dispatch_plans.py)."""

from __future__ import annotations

from plan_replay import check_no_plan

METHOD = "reconstruct_urho3d"


def test_its_runs_take_the_ordinary_path(ctx):
    check_no_plan(ctx, METHOD, {})
