"""Context.deferred_timers (issue 19): timers read together after one wait, as the reference
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
