"""stochastic (the OGRE paper): K time slices, each rendered at a hashed time inside its part of
the shutter with four rotated-grid sub-pixel offsets, combined per pixel with weights 5/32
inside and 3/32 from the neighbors (combine.comp here; NumPy twin twin.py here). Noise instead
of banding. docs/spec.md §4; spec.md here.
"""

from __future__ import annotations

import math
from contextlib import nullcontext

from ...core.context import Context
from ...core.frame import Frame
from ...core.gl import Timing
from ...core.render import render_targets
from ..core import SEED, Param, Pass, shader_beside
from ..folders import Declaration
from ..passes import timing_on as pass_timing_on
from .twin import ROTATED_GRID, slice_times

# Adds one jittered slice render into the sum; its time is summed over the 4 K renders.
COMBINE = Pass("stochastic", shader_beside(__file__, "combine.comp"), ("slices", "seed"))


def run(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str, passes: dict):
    slices, seed = values["slices"], values["seed"]
    if frame.scene is None:
        raise ValueError("blurlab: stochastic renders time slices: use a frame made by ctx.render")
    height, width = frame.shape
    result = ctx.pooled((height, width, 4))
    result.clear()
    combine = ctx.shader_pass(passes[COMBINE.name].shader)
    timed = pass_timing_on()
    timings = []
    # As a reference's sub-frames (blurlab.core.references): the renders draw the colour alone
    # and no timer is waited for inside the loop, so the CPU issues the 4 K renders while the GPU
    # works through them; an untimed call (a sweep's scoring run) takes no timers at all.
    with ctx.deferred_timers() as batch:
        for slice_index, t in enumerate(slice_times(frame.shutter, slices, seed)):
            for position, p in enumerate(ROTATED_GRID):
                jitter = (0.5 - p[0], 0.5 - p[1])
                targets, _, render = render_targets(
                    ctx,
                    frame.scene,
                    frame.size,
                    frame.shutter,
                    float(t),
                    0,
                    jitter,
                    timers=batch if timed else False,
                    color_only=True,  # the combine reads the colour alone
                )
                uniforms = {"slice": slice_index, "position": position, "slices": slices}
                with batch.timer() if timed else nullcontext() as add:
                    combine.run(
                        {"color": targets["color"]}, {"sum": result}, {**uniforms, "seed": seed}
                    )
                ctx.recycle(*targets.values())
                timings.append((render, add))
    if not timed:
        untimed = Timing(math.nan, "untimed")
        return {"color": result}, {"slice_renders": untimed, COMBINE.name: untimed}
    clock = timings[-1][1].clock
    return {"color": result}, {
        "slice_renders": Timing(sum(render.ms for render, _ in timings), clock),
        COMBINE.name: Timing(sum(add.ms for _, add in timings), clock),
    }


METHOD = Declaration(
    name="stochastic",
    kind="render",
    order=9,
    params={
        "slices": Param(4, int, "time slices K; 4 K jittered renders", 1, 64),
        "seed": SEED,
    },
    passes=(COMBINE,),
    run=run,
    default_grid={"slices": [2, 4, 8]},
    renders_for=lambda n: {"slices": max(1, n // len(ROTATED_GRID))},  # 4 renders a slice
    gallery=True,
    doc="The OGRE paper's stochastic blur: K time slices, rotated-grid samples in and "
    "around each pixel, weights 5/32 and 3/32. docs/spec.md §4.",
)
