"""Recorded dispatch plans (blurlab.methods.plans): an untimed call seen before is
replayed by one C++ call. A replay must give the ordinary path's bits, fresh outputs that do not
disturb results still held, and the same errors for bad input; runs a plan cannot replay (tile
classes, tile lists, timed calls, lookup textures) must take the ordinary path."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import blurlab as bl
from blurlab import _core
from blurlab.methods import plans

SIZE = (48, 32)


@pytest.fixture(scope="module")
def frame(ctx):
    return ctx.render(bl.scenes.teapot_pass(), SIZE)


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


def test_a_first_call_is_only_remembered_and_a_second_records(ctx):
    frame = ctx.render(bl.scenes.teapot_pass(), SIZE)
    bl.blur(ctx, frame, "reconstruct_guertin2014", timed=False)
    assert list(frame.plans.values()) == [None]
    bl.blur(ctx, frame, "reconstruct_guertin2014", timed=False)
    assert len(plans_of(frame)) == 1 and len(frame.plans) == 1


CASES = [
    ("reconstruct_mcguire2012", "compute", {"k": 20, "samples": 15}),
    ("reconstruct_mcguire2012", "fragment", {"k": 8, "samples": 9, "jitter_tiles": 1}),
    ("reconstruct_guertin2014", "compute", {}),
    ("reconstruct_guertin2014", "fragment", {"adaptive_samples": 1}),
    ("gather_weighted", "compute", {}),
    ("gather_box", "compute", {}),
    ("gather_gaussian", "compute", {}),
    ("engine_unity", "compute", {}),
    ("engine_eevee", "compute", {}),
    ("camera_only", "compute", {}),
    ("gather_pixel", "compute", {}),
    ("engine_jimenez2014", "compute", {}),
    ("engine_jimenez2014", "fragment", {"k": 8}),
    ("gather_pixel", "fragment", {"samples": 4}),
]


@pytest.fixture(scope="module")
def frames(ctx):
    """A frame at each instant the methods expect, so that none of them warns."""
    scene = bl.scenes.teapot_pass()
    return {i: ctx.render(scene, SIZE, instant=i) for i in ("center", "close")}


@pytest.mark.parametrize(("name", "backend", "params"), CASES)
def test_a_replay_gives_the_ordinary_bits(ctx, frames, name, backend, params):
    if backend not in bl.method(name).backends:
        pytest.skip(f"{name} has no {backend} backend")
    frame = frames[bl.method_instant(name, params)]
    expected = ordinary(ctx, frame, name, backend=backend, **params)
    result = replayed(ctx, frame, name, backend=backend, **params)
    recorded = [k for k, p in frame.plans.items() if p is not None]
    assert any(key[0] == name and key[1] == backend for key in recorded), "no plan recorded"
    assert set(result.textures) == set(expected)
    for key, array in expected.items():
        np.testing.assert_array_equal(result.textures[key].download(), array, err_msg=key)
    assert set(result.timings) and all(t.clock == "untimed" for t in result.timings.values())
    assert result.params == bl.blur(ctx, frame, name, backend=backend, **params).params


def test_outputs_are_fresh_and_results_held_stay_as_they_were(ctx, frame):
    name = "reconstruct_mcguire2012"
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
    name = "reconstruct_guertin2014"
    for frame in (first, second, first, second):
        result = replayed(ctx, frame, name)
        np.testing.assert_array_equal(result.color, ordinary(ctx, frame, name)["color"])


def test_bad_parameters_still_raise_after_a_recording(ctx, frame):
    replayed(ctx, frame, "reconstruct_mcguire2012", k=20)
    with pytest.raises(TypeError, match="k must be an integer"):
        bl.blur(ctx, frame, "reconstruct_mcguire2012", timed=False, k=20.0)
    with pytest.raises(TypeError, match="k must be an integer"):
        bl.blur(ctx, frame, "reconstruct_mcguire2012", timed=False, k=True)
    with pytest.raises(TypeError, match="no parameter"):
        bl.blur(ctx, frame, "reconstruct_mcguire2012", timed=False, k=20, kk=1)


@pytest.mark.parametrize(
    ("name", "params", "timed"),
    [
        ("reconstruct_mcguire2012", {"k": np.int64(20)}, False),  # not a plain int
        ("reconstruct_mcguire2012", {}, True),  # timed calls time each pass
        ("reconstruct_urho3d", {}, False),  # reads a cached lookup texture
        ("engine_unreal5", {"directions": 2}, False),  # passes over tile lists
    ],
)
def test_runs_a_plan_cannot_replay_take_the_ordinary_path(ctx, name, params, timed):
    frame = ctx.render(bl.scenes.teapot_pass(), SIZE)
    first = bl.blur(ctx, frame, name, timed=timed, **params)
    second = bl.blur(ctx, frame, name, timed=timed, **params)
    third = bl.blur(ctx, frame, name, timed=timed, **params)
    assert plans_of(frame) == []
    np.testing.assert_array_equal(first.color, second.color)
    np.testing.assert_array_equal(first.color, third.color)


def test_a_copied_frame_starts_without_plans(ctx, frame):
    replayed(ctx, frame, "reconstruct_guertin2014")
    copy = dataclasses.replace(frame)
    assert plans_of(frame) and copy.plans == {} and copy.plans is not frame.plans


def test_the_core_plan_refuses_textures_unlike_the_recorded_ones(ctx, frame):
    replayed(ctx, frame, "reconstruct_guertin2014")
    plan = next(p for k, p in frame.plans.items() if k[0] == "reconstruct_guertin2014" and p)
    good = [t.native for _, t in plan.inputs] + [
        ctx.pooled(shape, dtype).native for _, shape, dtype in plan.outputs
    ]
    plan.core.run(good)  # the recorded shapes: runs
    with pytest.raises(ValueError, match="takes 6 textures, got 5"):
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


@pytest.mark.parametrize("name", bl.methods())
def test_every_method_gives_the_same_bits_on_its_third_untimed_call(ctx, frames, name):
    """Replayed or not, a method's third untimed call is its first's bits (a method added
    later is covered without a line here)."""
    frame = frames[bl.method_instant(name, {})]
    expected = ordinary(ctx, frame, name)
    result = replayed(ctx, frame, name)
    for key, array in expected.items():
        np.testing.assert_array_equal(result.textures[key].download(), array, err_msg=key)
