"""engine_unreal5: the motion blur of Unreal Engine 5, written from the algorithm as its
console-variable documentation and public talks describe it (docs/spec.md §17.7), never from
Epic's sources, with the engine's structure: tiles classified on the GPU, each class's pass
dispatched over its own tile list (docs/spec.md §9.3, blurlab.methods.tiles); spec.md here.
engine_unreal's velocity flatten (11:11:10 codes, shaders/passes/unreal_velocity_flatten.glsl),
then tiles that keep their smallest length, their longest velocity and, with
r.MotionBlur.Directions = 2, their longest velocity along a second axis (tile_minmax.glsl),
listing the tiles whose velocity passes 3 tiles; the scatter of those velocities past the 7 x 7
(tile_scatter.glsl); the 7 x 7 scatter-as-gather that classifies each tile: skip, uniform (the
cheap path), gather along one velocity or along two, and uniform or gather at half resolution
where the taps lie far apart (neighbor_dilate.glsl); the colour at half size (half_color.glsl);
and the reconstruction, one pass per class over its list, the half-resolution classes with
their upsample and composite (reconstruct.glsl); what they share is unreal5.glsl. NumPy twin:
twin.engine_unreal5.

Unreal's settings here: r.MotionBlurQuality is `quality` (the most taps on one line, 4/6/8/16),
Max is `max_blur` (engine_unreal's reading, §17.5), r.MotionBlur.Directions is `directions`
and r.MotionBlur.HalfResGather is `half_res_gather`, each at its default as documented or
recalled (§17.7 says which).
"""

from __future__ import annotations

from ...core.context import Context
from ...core.frame import Frame
from ...twins import unreal5 as passes_twin
from ...twins.unreal import SAMPLES_BY_QUALITY, TILE, max_radius_px
from .. import tiles as tile_lists
from ..core import Param, Pass, PassRunner, shader_beside
from ..folders import Declaration
from ..unreal import FLATTEN
from ..unreal import PARAMS as UNREAL_PARAMS
from .twin import engine_unreal5

PARAMS = {
    "quality": UNREAL_PARAMS["quality"],
    "max_blur": UNREAL_PARAMS["max_blur"],
    "directions": Param(1, int, "r.MotionBlur.Directions: velocity directions per tile", 1, 2),
    "half_res_gather": Param(
        1, int, "r.MotionBlur.HalfResGather: long blurs gather at half resolution", 0, 1
    ),
    "depth_extent": UNREAL_PARAMS["depth_extent"],
    "exposure": UNREAL_PARAMS["exposure"],
    "seed": UNREAL_PARAMS["seed"],
    "tile_dispatch": tile_lists.TILE_DISPATCH,
}
TILE_MINMAX = Pass("tile_minmax", shader_beside(__file__, "tile_minmax.glsl"))
TILE_SCATTER = Pass("tile_scatter", shader_beside(__file__, "tile_scatter.glsl"))
NEIGHBOR_DILATE = Pass(
    "neighbor_dilate",
    shader_beside(__file__, "neighbor_dilate.glsl"),
    ("directions", "half_res_gather"),
)
HALF_COLOR = Pass("half_color", shader_beside(__file__, "half_color.glsl"))
RECONSTRUCT = Pass(
    "reconstruct",
    shader_beside(__file__, "reconstruct.glsl"),
    ("half_res_gather", "depth_extent", "seed"),
)
# The tile lists (docs/spec.md §9.3): one per class, in the order of the class values, and the
# tiles whose velocity reaches past the 7 x 7 (the scatter's sources).
LISTS = (*passes_twin.CLASS_NAMES, "far")


def run(
    ctx: Context,
    frame: Frame,
    inputs: dict,
    values: dict,
    backend: str,
    passes: dict | None = None,
):
    """The method's passes (docs/spec.md §17.7). The reconstruction runs once per tile class
    that the settings allow, over that class's list by an indirect dispatch; with
    tile_dispatch="one" as one dispatch over every tile instead, each tile taking its class's
    path: the same bits. It runs the module's passes; `passes`, the declared ones by name, is
    not read."""
    height, width = inputs["color"].shape[:2]
    radius = max_radius_px(width, values["max_blur"])
    grid = (-(-height // TILE), -(-width // TILE), 4)
    velocity = ctx.pooled((height, width, 4))
    tiles, neighbors = ctx.pooled(grid), ctx.pooled(grid)
    result = ctx.pooled((height, width, 4))
    lists = tile_lists.empty_lists(ctx, (height, width), TILE, LISTS)
    appended = {"tile_counts": lists.counts, "tile_lists": lists.lists}
    runner = PassRunner(ctx, PARAMS, values)
    at_radius = {"radius": radius}
    taps = SAMPLES_BY_QUALITY[values["quality"]]
    depth_motion = {"depth": inputs["depth"], "motion": inputs["motion"]}
    runner.run(FLATTEN, depth_motion, {"velocity": velocity}, uniforms=at_radius)
    # A velocity can pass the 7 x 7 only where R can: then the dilation scatters too.
    scatter = radius >= passes_twin.SCATTER_BEYOND * TILE
    scattered = {}
    if scatter:
        far_key = ctx.pooled(grid[:2] + (1,), "uint32")
        far_min = ctx.pooled(grid[:2] + (1,), "uint32")
        scattered = {"far_key_out": far_key, "far_min_out": far_min}
        runner.run(
            TILE_MINMAX,
            {"velocity": velocity},
            {"tiles": tiles, **appended, **scattered},
            uniforms={**at_radius, "directions": values["directions"]},
            defines={"SCATTER": 1},
            group_per_texel=True,
        )
        tile_lists.run_over_list(
            ctx,
            runner.timings,
            TILE_SCATTER,
            lists,
            LISTS.index("far"),
            {"tiles": tiles},
            scattered,
            {**at_radius, "directions": values["directions"]},
        )
        dilate_inputs = {"tiles": tiles, "far_key_in": far_key, "far_min_in": far_min}
    else:
        runner.run(TILE_MINMAX, {"velocity": velocity}, {"tiles": tiles}, group_per_texel=True)
        dilate_inputs = {"tiles": tiles}
    runner.run(
        NEIGHBOR_DILATE,
        dilate_inputs,
        {"neighbors": neighbors, **appended},
        uniforms={**at_radius, "taps": taps},
        defines={"SCATTER": 1} if scatter else None,
    )
    outputs = {"velocity": velocity, "tiles": tiles, "neighbors": neighbors}
    half = inputs["color"]  # bound but never read where half_res_gather is off
    if values["half_res_gather"]:
        half = ctx.pooled((-(-height // 2), -(-width // 2), 4))
        runner.run(HALF_COLOR, {"color": inputs["color"]}, {"half_color": half})
        outputs["half_color"] = half
    textures = {
        "color": inputs["color"],
        "velocity": velocity,
        "neighbors": neighbors,
        "half_color": half,
    }
    uniforms = {**at_radius, "taps": taps}
    if values["tile_dispatch"] == "lists":
        classes = _possible_classes(values)
        into = {"result": result}
        tile_lists.run_per_class(runner, RECONSTRUCT, lists, classes, textures, into, uniforms)
    else:
        runner.run(RECONSTRUCT, textures, {"result": result}, backend, uniforms=uniforms)
    ctx.recycle(lists.classes, lists.lists, *scattered.values())
    return {"color": result, **outputs, "tile_counts": lists.counts}, runner.timings


def _possible_classes(values: dict) -> list[int]:
    """The classes a tile may take under these settings: gather_2 needs two directions, the
    half-resolution classes half_res_gather."""
    classes = [passes_twin.SKIP, passes_twin.UNIFORM, passes_twin.GATHER]
    if values["directions"] == 2:
        classes.append(passes_twin.GATHER_2)
    if values["half_res_gather"]:
        classes += [passes_twin.UNIFORM_HALF, passes_twin.GATHER_HALF]
    return classes


METHOD = Declaration(
    name="engine_unreal5",
    kind="gather",
    order=15,
    params=PARAMS,
    # The passes a call at the defaults runs under their own names (the contract checks each
    # is timed): the scatter runs only for long blurs (as tile_scatter[far]), the half-size
    # colour only with half_res_gather, and the reconstruction is timed per tile class
    # (reconstruct[class]); the velocity flatten is engine_unreal's, shared (methods/unreal.py).
    passes=(TILE_MINMAX, NEIGHBOR_DILATE, HALF_COLOR),
    run=run,
    default_grid={"quality": [1, 2, 3, 4], "directions": [1, 2]},
    twin=engine_unreal5,
    doc="Unreal Engine 5's motion blur, from its described algorithm: min/max tiles with up "
    "to two directions, 7x7 scatter-as-gather and a scatter past 3 tiles, tiles classed "
    "skip/uniform/gather/two velocities/half-resolution uniform and gather, each class "
    "dispatched over its own tile list, per-tile sample counts. docs/spec.md §17.7.",
    tile_lists=LISTS,
)
