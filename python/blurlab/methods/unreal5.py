"""engine_unreal5: the motion blur of Unreal Engine 5, written from the algorithm as its
console-variable documentation and public talks describe it (docs/spec.md §17.7), never from
Epic's sources. engine_unreal's velocity flatten (11:11:10 codes), then tiles that keep their
smallest length, their longest velocity and, with r.MotionBlur.Directions = 2, their longest
velocity along a second axis (shaders/passes/unreal5_tile_minmax.glsl); the 7 x 7
scatter-as-gather that also classifies each tile: skip, uniform (the cheap path), gather along
one velocity or along two (unreal5_neighbor_dilate.glsl); the colour at half size for the long
blurs (unreal5_half_color.glsl); and the gather, its sample count chosen per tile from the
tile's motion (unreal5_reconstruct.glsl). NumPy twin: blurlab.twins.unreal5.engine_unreal5.

Unreal's settings here: r.MotionBlurQuality is `quality` (the most taps on one line, 4/6/8/16),
Max is `max_blur` (engine_unreal's reading, §17.5), r.MotionBlur.Directions is `directions`
and r.MotionBlur.HalfResGather is `half_res_gather`, each at its default as documented or
recalled (§17.7 says which).
"""

from __future__ import annotations

from ..core.context import Context
from ..core.frame import Frame
from ..twins import unreal5 as twin
from ..twins.unreal import SAMPLES_BY_QUALITY, TILE, max_radius_px
from .core import Method, Param, Pass, PassRunner, register
from .unreal import FLATTEN
from .unreal import PARAMS as UNREAL_PARAMS

PARAMS = {
    "quality": UNREAL_PARAMS["quality"],
    "max_blur": UNREAL_PARAMS["max_blur"],
    "directions": Param(1, int, "r.MotionBlur.Directions: velocity directions per tile", 1, 2),
    "half_res_gather": Param(
        1, int, "r.MotionBlur.HalfResGather: long blurs read the colour at half size", 0, 1
    ),
    "depth_extent": UNREAL_PARAMS["depth_extent"],
    "exposure": UNREAL_PARAMS["exposure"],
    "seed": UNREAL_PARAMS["seed"],
}
TILE_MINMAX = Pass("tile_minmax", "passes/unreal5_tile_minmax.glsl")
NEIGHBOR_DILATE = Pass("neighbor_dilate", "passes/unreal5_neighbor_dilate.glsl", ("directions",))
HALF_COLOR = Pass("half_color", "passes/unreal5_half_color.glsl")
RECONSTRUCT = Pass(
    "reconstruct",
    "passes/unreal5_reconstruct.glsl",
    ("half_res_gather", "depth_extent", "seed"),
)


def _run_unreal5(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
    height, width = inputs["color"].shape[:2]
    radius = max_radius_px(width, values["max_blur"])
    grid = (-(-height // TILE), -(-width // TILE), 4)
    velocity = ctx.pooled((height, width, 4))
    tiles, neighbors = ctx.pooled(grid), ctx.pooled(grid)
    result = ctx.pooled((height, width, 4))
    passes = PassRunner(ctx, PARAMS, values)
    at_radius = {"radius": radius}
    depth_motion = {"depth": inputs["depth"], "motion": inputs["motion"]}
    passes.run(FLATTEN, depth_motion, {"velocity": velocity}, uniforms=at_radius)
    passes.run(TILE_MINMAX, {"velocity": velocity}, {"tiles": tiles})
    passes.run(NEIGHBOR_DILATE, {"tiles": tiles}, {"neighbors": neighbors}, uniforms=at_radius)
    outputs = {"velocity": velocity, "tiles": tiles, "neighbors": neighbors}
    half = inputs["color"]  # bound but never read where half_res_gather is off
    if values["half_res_gather"]:
        half = ctx.pooled((-(-height // 2), -(-width // 2), 4))
        passes.run(HALF_COLOR, {"color": inputs["color"]}, {"half_color": half})
        outputs["half_color"] = half
    textures = {
        "color": inputs["color"],
        "velocity": velocity,
        "neighbors": neighbors,
        "half_color": half,
    }
    uniforms = {**at_radius, "taps": SAMPLES_BY_QUALITY[values["quality"]]}
    passes.run(RECONSTRUCT, textures, {"result": result}, backend, uniforms=uniforms)
    return {"color": result, **outputs}, passes.timings


register(
    Method(
        name="engine_unreal5",
        kind="gather",
        params=PARAMS,
        run=_run_unreal5,
        default_grid={"quality": [1, 2, 3, 4], "directions": [1, 2]},
        twin=twin.engine_unreal5,
        doc="Unreal Engine 5's motion blur, from its described algorithm: min/max tiles with up "
        "to two directions, 7x7 scatter-as-gather, tiles classed skip/uniform/gather/two "
        "velocities, per-tile sample counts, a half-resolution colour for long blurs. "
        "docs/spec.md §17.7.",
    )
)
