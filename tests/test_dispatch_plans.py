"""Recorded dispatch plans (blurlab.methods.plans): an untimed call seen before is
replayed by one C++ call. A replay must give the ordinary path's bits, fresh outputs that do not
disturb results still held, and the same errors for bad input; runs a plan cannot replay (tile
classes, tile lists, timed calls, lookup textures) must take the ordinary path."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from method_picks import EXAMPLE
from plan_replay import SIZE, check_no_plan, check_replay, ordinary, plans_of, replayed

import blurlab as bl
from blurlab import _core

# Each method's own recorded plans (its variants, its backends, the runs a plan cannot replay)
# are tested in its folder (python/blurlab/methods/<name>/test_<name>_plans.py); here, what
# every plan does, shown on the example method (a tile filter with k and samples).


@pytest.fixture(scope="module")
def frame(ctx):
    return ctx.render(bl.scenes.teapot_pass(), SIZE)


def test_a_first_call_is_only_remembered_and_a_second_records(ctx):
    frame = ctx.render(bl.scenes.teapot_pass(), SIZE)
    bl.blur(ctx, frame, EXAMPLE, timed=False)
    assert list(frame.plans.values()) == [None]
    bl.blur(ctx, frame, EXAMPLE, timed=False)
    assert len(plans_of(frame)) == 1 and len(frame.plans) == 1


@pytest.mark.parametrize("backend", bl.method(EXAMPLE).backends)
def test_a_replay_gives_the_ordinary_bits(ctx, backend):
    check_replay(ctx, EXAMPLE, backend, {})


def test_outputs_are_fresh_and_results_held_stay_as_they_were(ctx, frame):
    name = EXAMPLE
    wide = replayed(ctx, frame, name, k=20, samples=15)
    narrow = replayed(ctx, frame, name, k=4, samples=5)
    again = bl.blur(ctx, frame, name, timed=False, k=20, samples=15)
    assert wide.textures["color"] is not again.textures["color"]
    np.testing.assert_array_equal(wide.color, ordinary(ctx, frame, name, k=20, samples=15)["color"])
    np.testing.assert_array_equal(narrow.color, ordinary(ctx, frame, name, k=4, samples=5)["color"])
    assert not np.array_equal(wide.color, narrow.color)


def test_each_frame_replays_its_own_textures(ctx):
    first = ctx.render(bl.scenes.teapot_pass(), SIZE)
    second = ctx.render(bl.scenes.fan(), SIZE)
    name = EXAMPLE
    for frame in (first, second, first, second):
        result = replayed(ctx, frame, name)
        np.testing.assert_array_equal(result.color, ordinary(ctx, frame, name)["color"])


def test_bad_parameters_still_raise_after_a_recording(ctx, frame):
    replayed(ctx, frame, EXAMPLE, k=20)
    with pytest.raises(TypeError, match="k must be an integer"):
        bl.blur(ctx, frame, EXAMPLE, timed=False, k=20.0)
    with pytest.raises(TypeError, match="k must be an integer"):
        bl.blur(ctx, frame, EXAMPLE, timed=False, k=True)
    with pytest.raises(TypeError, match="no parameter"):
        bl.blur(ctx, frame, EXAMPLE, timed=False, k=20, kk=1)


@pytest.mark.parametrize(
    ("params", "timed"),
    [
        ({"k": np.int64(20)}, False),  # not a plain int
        ({}, True),  # timed calls time each pass
    ],
)
def test_runs_a_plan_cannot_replay_take_the_ordinary_path(ctx, params, timed):
    check_no_plan(ctx, EXAMPLE, params, timed)


def test_a_copied_frame_starts_without_plans(ctx, frame):
    replayed(ctx, frame, EXAMPLE)
    copy = dataclasses.replace(frame)
    assert plans_of(frame) and copy.plans == {} and copy.plans is not frame.plans


def test_the_core_plan_refuses_textures_unlike_the_recorded_ones(ctx, frame):
    replayed(ctx, frame, EXAMPLE)
    plan = next(p for k, p in frame.plans.items() if k[0] == EXAMPLE and p)
    good = [t.native for _, t in plan.inputs] + [
        ctx.pooled(shape, dtype).native for _, shape, dtype in plan.outputs
    ]
    plan.core.run(good)  # the recorded shapes: runs
    with pytest.raises(ValueError, match=f"takes {len(good)} textures, got {len(good) - 1}"):
        plan.core.run(good[:-1])
    wrong = ctx.empty((SIZE[1] + 1, SIZE[0], 4)).native
    with pytest.raises(ValueError, match="differs in size or format"):
        plan.core.run([wrong, *good[1:]])
    half = ctx.empty((SIZE[1], SIZE[0], 4), "float16").native
    with pytest.raises(ValueError, match="differs in size or format"):
        plan.core.run([half, *good[1:]])
    with pytest.raises(ValueError, match="texture 0 of the dispatch plan is None"):
        plan.core.run([None, *good[1:]])
    assert ctx.gl_errors() == []


def test_a_plan_is_recorded_only_from_the_runs_it_was_given(ctx, frame):
    shader = ctx.shader_pass("passes/accumulate.comp")
    color, total = ctx.empty((4, 4, 4)), ctx.empty((4, 4, 4))
    plan = _core.DispatchPlan(ctx.native, [color.native])
    with pytest.raises(ValueError, match="not among the plan's textures"):
        plan.add(
            shader.native, {"color": color.native}, {"sum": total.native}, {}, "compute", False
        )
    with pytest.raises(ValueError, match="has no uniform 'weigth'"):
        plan = _core.DispatchPlan(ctx.native, [color.native, total.native])
        plan.add(
            shader.native,
            {"color": color.native},
            {"sum": total.native},
            {"weigth": 0.5},
            "compute",
            False,
        )
    assert plan.steps == 0


@pytest.fixture(scope="module")
def frames(ctx):
    """A frame at each instant the methods expect, so that none of them warns."""
    scene = bl.scenes.teapot_pass()
    return {i: ctx.render(scene, SIZE, instant=i) for i in ("center", "close")}


@pytest.mark.parametrize("name", bl.methods())
def test_every_method_gives_the_same_bits_on_its_third_untimed_call(ctx, frames, name):
    """Replayed or not, a method's third untimed call is its first's bits (a method added
    later is covered without a line here)."""
    frame = frames[bl.method_instant(name, {})]
    expected = ordinary(ctx, frame, name)
    result = replayed(ctx, frame, name)
    for key, array in expected.items():
        np.testing.assert_array_equal(result.textures[key].download(), array, err_msg=key)
