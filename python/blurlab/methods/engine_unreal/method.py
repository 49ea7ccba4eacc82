"""engine_unreal: the motion blur of Unreal Engine 4, written from the algorithm of spec.md here
(docs/spec.md §17.5), from Unreal's public documentation of its settings and from Jimenez 2014
("Next Generation Post Processing in Call of Duty: Advanced Warfare", whose filter UE4's
follows), not from Epic's sources. Velocity flatten into the 11:11:10 polar texel
(shaders/passes/unreal_velocity_flatten.glsl, shared with engine_unreal5), min/max per 16 x 16
tile (tile_minmax.glsl), scatter-as-gather over the 7 x 7 tiles around each tile with the
tile's class (neighbor_dilate.glsl), and the reconstruction whose path (skip, fast, slow) is
chosen per tile (reconstruct.glsl). NumPy twin: twin.engine_unreal.

Unreal's settings here: r.MotionBlurQuality 1..4 is `quality` (4/6/8/16 samples); Max, the
longest blur "in percent of the screen width", is `max_blur`, read as the blur radius (the
longest half-vector); Amount, the fraction of the frame time the shutter is open, is blurlab's
shutter itself, whose motion the G-buffer already spans: `exposure` scales it, 1 by default.

What it leaves out: Per Object Size (blurlab's G-buffer has every object's motion), Target FPS
(a frame here has no frame rate), the engine's temporal AA and half-resolution passes, the
real R11G11B10 texture (the codes are kept exactly in RGBA32F) and the engine's exact sample
weights, which its description does not give (the choices are listed in §17.5).
"""

from __future__ import annotations

from ...core.context import Context
from ...core.frame import Frame
from ...twins import unreal as passes_twin
from ..core import Pass, PassRunner, shader_beside
from ..folders import Declaration
from ..unreal import FLATTEN, PARAMS
from .twin import engine_unreal

TILE_MINMAX = Pass("tile_minmax", shader_beside(__file__, "tile_minmax.glsl"))
NEIGHBOR_DILATE = Pass("neighbor_dilate", shader_beside(__file__, "neighbor_dilate.glsl"))
RECONSTRUCT = Pass(
    "reconstruct", shader_beside(__file__, "reconstruct.glsl"), ("depth_extent", "seed")
)


def run(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str, passes: dict):
    height, width = inputs["color"].shape[:2]
    radius = passes_twin.max_radius_px(width, values["max_blur"])
    grid = (-(-height // passes_twin.TILE), -(-width // passes_twin.TILE), 4)
    velocity = ctx.pooled((height, width, 4))
    tiles, neighbors = ctx.pooled(grid), ctx.pooled(grid)
    runner = PassRunner(ctx, PARAMS, values)
    depth_motion = {"depth": inputs["depth"], "motion": inputs["motion"]}
    at_radius = {"radius": radius}
    runner.run(FLATTEN, depth_motion, {"velocity": velocity}, uniforms=at_radius)
    runner.run(passes["tile_minmax"], {"velocity": velocity}, {"tiles": tiles})
    runner.run(
        passes["neighbor_dilate"], {"tiles": tiles}, {"neighbors": neighbors}, uniforms=at_radius
    )
    textures = {"color": inputs["color"], "velocity": velocity, "neighbors": neighbors}
    uniforms = {**at_radius, "taps": passes_twin.SAMPLES_BY_QUALITY[values["quality"]]}
    result = runner.run_result(passes["reconstruct"], textures, backend, uniforms=uniforms)
    outputs = {"color": result, "velocity": velocity, "tiles": tiles, "neighbors": neighbors}
    return outputs, runner.timings


METHOD = Declaration(
    name="engine_unreal",
    kind="gather",
    order=14,
    params=PARAMS,
    # The velocity flatten, shared with engine_unreal5, runs from shaders/passes (FLATTEN).
    passes=(TILE_MINMAX, NEIGHBOR_DILATE, RECONSTRUCT),
    run=run,
    default_grid={"quality": [1, 2, 3, 4]},
    twin=engine_unreal,
    doc="Unreal Engine 4's motion blur, from its described algorithm: polar 11:11:10 "
    "velocity, min/max per 16 px tile, 7x7 scatter-as-gather, skip/fast/slow path per "
    "tile, mirrored pairs, soft depth extent 1. docs/spec.md §17.5.",
)
