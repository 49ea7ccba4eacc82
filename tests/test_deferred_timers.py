"""Context.deferred_timers: timers read together after one wait, as the reference
loop uses them instead of waiting twice per sub-frame."""

from __future__ import annotations

import math

import numpy as np
import pytest

import blurlab as bl
from blurlab import _core


def test_timings_are_filled_when_the_block_ends(ctx):
    color, total = ctx.empty((32, 48, 4)), ctx.empty((32, 48, 4))
    step = ctx.shader_pass("passes/accumulate.comp")
    with ctx.timer() as waited:
        step.run({"color": color}, {"sum": total}, {"weight": 0.5})
    with ctx.deferred_timers() as timers:
        timings = []
        for _ in range(3):
            with timers.timer() as timing:
                step.run({"color": color}, {"sum": total}, {"weight": 0.5})
            timings.append(timing)
        if waited.clock == "gl_time_elapsed":  # a GPU clock: nothing read yet
            assert all(math.isnan(t.ms) for t in timings)
    assert all(t.clock == waited.clock for t in timings)
    assert all(math.isfinite(t.ms) and t.ms >= 0 for t in timings)


def test_a_timer_is_read_only_after_it_ended(ctx):
    timer = _core.Timer(ctx.native)
    with pytest.raises(RuntimeError, match="before the timer ended"):
        timer.result()
    timer.start()
    with pytest.raises(RuntimeError, match="before the timer ended"):
        timer.result()
    timer.end()
    assert timer.result() >= 0
    with pytest.raises(RuntimeError, match="before start"):
        timer.end()


def test_an_error_inside_the_block_still_reads_the_timers_that_ended(ctx):
    kept = []
    with pytest.raises(ValueError, match="inside"):
        with ctx.deferred_timers() as timers:
            with timers.timer() as timing:
                ctx.finish()
            kept.append(timing)
            raise ValueError("inside")
    assert math.isfinite(kept[0].ms)


def test_the_reference_reports_its_sub_frames_time(ctx):
    scene = bl.scenes.teapot_pass()
    reference = ctx.reference(scene, (32, 18), samples=8, progress=False)
    assert math.isfinite(reference.ms_per_subframe) and reference.ms_per_subframe > 0
    with ctx.timer() as timing:
        pass
    assert reference.clock == timing.clock
    again = ctx.reference(scene, (32, 18), samples=8, progress=False)
    np.testing.assert_array_equal(reference.color, again.color)


def test_waits_counts_the_cpu_stopping_for_the_gpu(ctx):
    texture = ctx.empty((4, 4))
    before = ctx.waits()
    ctx.finish()
    texture.download()
    assert ctx.waits() == before + 2
    with ctx.deferred_timers() as timers:
        for _ in range(5):
            with timers.timer():
                texture.clear()
    waited = ctx.waits() - before - 2
    if ctx.software:  # the wall clock waits at both ends of every block
        assert waited == 10
    else:  # at most once for the five, the last one read first
        assert waited <= 1


def test_the_reference_waits_for_the_gpu_the_same_number_of_times_for_any_n(ctx):
    """No wait per sub-frame: 4 and 12 sub-frames stop the CPU at most twice each, and hold the
    same textures (the targets come from the pool, once)."""
    scene = bl.scenes.teapot_pass()
    ctx.reference(scene, (32, 18), samples=2, progress=False)  # shaders built, pool filled
    waits, textures = [], []
    for samples in (4, 12):
        before, live = ctx.waits(), ctx.live_objects().get("texture", 0)
        reference = ctx.reference(scene, (32, 18), samples=samples, progress=False)
        waits.append(ctx.waits() - before)
        textures.append(ctx.live_objects().get("texture", 0) - live)
        assert math.isfinite(reference.ms_per_subframe) and reference.ms_per_subframe > 0
        del reference
    # At most the loop's own: on llvmpipe the spanning timer's two glFinish, on a GPU one read of
    # the last timer (none when the GPU was already done, so the counts may differ by one there).
    assert max(waits) <= 2, waits
    if ctx.software:
        assert waits == [2, 2]
    assert textures[0] == textures[1], textures
