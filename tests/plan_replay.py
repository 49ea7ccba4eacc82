"""What the tests of recorded dispatch plans share (tests/test_dispatch_plans.py and each
method's folder's test_<name>_plans.py): the ordinary path's bits, the third untimed call that
replays a recorded plan, and the checks that a method's call replays with the ordinary bits or,
where a plan cannot replay it, always takes the ordinary path."""

from __future__ import annotations

import numpy as np

import blurlab as bl
from blurlab.methods import plans

SIZE = (48, 32)


def ordinary(ctx, frame, name, **params):
    with plans.disabled():
        result = bl.blur(ctx, frame, name, timed=False, **params)
    return {k: result.textures[k].download() for k in result.textures}


def plans_of(frame) -> list:
    """The frame's recorded plans (a key seen once holds None)."""
    return [plan for plan in frame.plans.values() if plan is not None]


def replayed(ctx, frame, name, **params):
    """The third untimed call, which replays the plan the second one recorded (the first is
    only remembered)."""
    bl.blur(ctx, frame, name, timed=False, **params)
    assert len(plans_of(frame)) == len(set(map(id, plans_of(frame))))
    bl.blur(ctx, frame, name, timed=False, **params)
    before = dict(frame.plans)
    result = bl.blur(ctx, frame, name, timed=False, **params)
    assert frame.plans == before  # nothing recorded again
    return result


def frame_for(ctx, name, params):
    """A frame at the instant the method expects, so that it does not warn."""
    instant = bl.method_instant(name, params)
    return ctx.render(bl.scenes.teapot_pass(), SIZE, instant=instant)


def check_replay(ctx, name, backend, params, frame=None):
    """The method's call records a plan, and its replay gives the ordinary path's bits, with
    untimed timings and the parameters a timed call resolves."""
    frame = frame_for(ctx, name, params) if frame is None else frame
    expected = ordinary(ctx, frame, name, backend=backend, **params)
    result = replayed(ctx, frame, name, backend=backend, **params)
    recorded = [k for k, p in frame.plans.items() if p is not None]
    assert any(key[0] == name and key[1] == backend for key in recorded), "no plan recorded"
    assert set(result.textures) == set(expected)
    for key, array in expected.items():
        np.testing.assert_array_equal(result.textures[key].download(), array, err_msg=key)
    assert set(result.timings) and all(t.clock == "untimed" for t in result.timings.values())
    assert result.params == bl.blur(ctx, frame, name, backend=backend, **params).params


def check_no_plan(ctx, name, params, timed=False):
    """A call a plan cannot replay records none and gives the same bits each time."""
    frame = ctx.render(bl.scenes.teapot_pass(), SIZE)
    first = bl.blur(ctx, frame, name, timed=timed, **params)
    second = bl.blur(ctx, frame, name, timed=timed, **params)
    third = bl.blur(ctx, frame, name, timed=timed, **params)
    assert plans_of(frame) == []
    np.testing.assert_array_equal(first.color, second.color)
    np.testing.assert_array_equal(first.color, third.color)
