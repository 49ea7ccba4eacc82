"""engine_unreal: the motion blur of Unreal Engine 4, written from the algorithm of docs/spec.md
§17.5, from Unreal's public documentation of its settings and from Jimenez 2014 ("Next
Generation Post Processing in Call of Duty: Advanced Warfare", whose filter UE4's follows), not
from Epic's sources. Velocity flatten into the 11:11:10 polar texel
(shaders/passes/unreal_velocity_flatten.glsl), min/max per 16 x 16 tile (unreal_tile_minmax.glsl),
scatter-as-gather over the 7 x 7 tiles around each tile with the tile's class
(unreal_neighbor_dilate.glsl), and the reconstruction whose path (skip, fast, slow) is chosen
per tile (unreal_reconstruct.glsl). NumPy twin: blurlab.twins.unreal.engine_unreal.

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

from ..core.context import Context
from ..core.frame import Frame
from ..twins import unreal as twin
from .core import FLOAT32_MAX, SEED, Method, Param, Pass, PassRunner, register
from .tile_filter import TILE_FILTER_PARAMS

PARAMS = {
    "quality": Param(3, int, "r.MotionBlurQuality: 4, 6, 8 or 16 samples", 1, 4),
    "max_blur": Param(
        5.0, float, "Unreal's Max: longest blur radius, % of the image width", 0, 100, low_open=True
    ),
    "depth_extent": Param(
        1.0, float, "soft depth extent, depth units", 0, FLOAT32_MAX, low_open=True
    ),
    "exposure": TILE_FILTER_PARAMS["exposure"],
    "seed": SEED,
}
FLATTEN = Pass("velocity_flatten", "passes/unreal_velocity_flatten.glsl", ("exposure",))
TILE_MINMAX = Pass("tile_minmax", "passes/unreal_tile_minmax.glsl")
NEIGHBOR_DILATE = Pass("neighbor_dilate", "passes/unreal_neighbor_dilate.glsl")
RECONSTRUCT = Pass("reconstruct", "passes/unreal_reconstruct.glsl", ("depth_extent", "seed"))


def _run_unreal(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
    height, width = inputs["color"].shape[:2]
    radius = twin.max_radius_px(width, values["max_blur"])
    grid = (-(-height // twin.TILE), -(-width // twin.TILE), 4)
    velocity = ctx.pooled((height, width, 4))
    tiles, neighbors = ctx.pooled(grid), ctx.pooled(grid)
    passes = PassRunner(ctx, PARAMS, values)
    depth_motion = {"depth": inputs["depth"], "motion": inputs["motion"]}
    at_radius = {"radius": radius}
    passes.run(FLATTEN, depth_motion, {"velocity": velocity}, uniforms=at_radius)
    passes.run(TILE_MINMAX, {"velocity": velocity}, {"tiles": tiles})
    passes.run(NEIGHBOR_DILATE, {"tiles": tiles}, {"neighbors": neighbors}, uniforms=at_radius)
    textures = {"color": inputs["color"], "velocity": velocity, "neighbors": neighbors}
    uniforms = {**at_radius, "taps": twin.SAMPLES_BY_QUALITY[values["quality"]]}
    result = passes.run_result(RECONSTRUCT, textures, backend, uniforms=uniforms)
    outputs = {"color": result, "velocity": velocity, "tiles": tiles, "neighbors": neighbors}
    return outputs, passes.timings


register(
    Method(
        name="engine_unreal",
        kind="gather",
        params=PARAMS,
        run=_run_unreal,
        default_grid={"quality": [1, 2, 3, 4]},
        twin=twin.engine_unreal,
        doc="Unreal Engine 4's motion blur, from its described algorithm: polar 11:11:10 "
        "velocity, min/max per 16 px tile, 7x7 scatter-as-gather, skip/fast/slow path per "
        "tile, mirrored pairs, soft depth extent 1. docs/spec.md §17.5.",
    )
)
