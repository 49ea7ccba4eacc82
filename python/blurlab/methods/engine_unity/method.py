"""engine_unity: the motion blur of Unity's PostProcessing v2 (the KinoMotion lineage, after
McGuire et al. 2012), written from the algorithm of docs/spec.md §17.3, not from Unity's
sources (spec.md here). Its passes, beside this file: velocity setup with 10-bit velocity and
depth (velocity_setup.glsl), TileMax by three 2 x 2 reductions and one of tile/8
(tile_reduce.glsl), NeighborMax with a 1.01 bias toward the center (neighbor_max.glsl),
reconstruction along NeighborMax and v_alt (reconstruct.glsl); what they share is unity.glsl.
NumPy twin: twin.engine_unity. Parameters below, at the engine's defaults.

What it leaves out: the engine's shutter angle (blurlab's shutter is the exposure interval
itself; `exposure` scales it), its frame blending, the real 10:10:10:2 texture format (the
codes are kept exactly in RGBA32F) and the engine's exact sample weights, which its
description does not give: the weights here are §3.4's cones with the engine's depth factor.
"""

from __future__ import annotations

from ..core import FLOAT32_MAX, SEED, Param, Pass, PassRunner, shader_beside
from ..folders import Declaration
from ..tile_filter import FAR, TILE_FILTER_PARAMS
from . import twin

PARAMS = {
    "samples": Param(10, int, "sample count (quality); fewer where NeighborMax is short", 4, 32),
    "max_radius": Param(
        5.0, float, "largest blur radius, % of the image height", 0, 50, low_open=True
    ),
    "depth_factor": Param(
        20.0, float, "soft depth comparison factor on the 10-bit linear depth", 0, FLOAT32_MAX
    ),
    "exposure": TILE_FILTER_PARAMS["exposure"],
    "far": FAR,  # depth = Z / far, as the Urho3D pass reads depth
    "seed": SEED,
}
SETUP = Pass("velocity_setup", shader_beside(__file__, "velocity_setup.glsl"), ("exposure", "far"))
REDUCE = shader_beside(__file__, "tile_reduce.glsl")
REDUCTIONS = tuple(Pass(f"tile_max_{i}", REDUCE) for i in (2, 4, 8))
TILE_MAX = Pass("tile_max", REDUCE)
NEIGHBOR_MAX = Pass("neighbor_max", shader_beside(__file__, "neighbor_max.glsl"))
RECONSTRUCT = Pass(
    "reconstruct", shader_beside(__file__, "reconstruct.glsl"), ("samples", "depth_factor", "seed")
)


def run(ctx, frame, inputs: dict, values: dict, backend: str, passes: dict):
    height, width = inputs["color"].shape[:2]
    radius = twin.max_radius_px(height, values["max_radius"])
    tile = twin.tile_size(height, values["max_radius"])
    runner = PassRunner(ctx, PARAMS, values)
    velocity = ctx.pooled((height, width, 4))
    runner.run(
        SETUP,
        {"depth": inputs["depth"], "motion": inputs["motion"]},
        {"velocity": velocity},
        uniforms={"radius": radius},
    )
    level, made = velocity, []
    for step, block in [*((r, 2) for r in REDUCTIONS), (TILE_MAX, tile // 8)]:
        h, w = level.shape[:2]
        reduced = ctx.pooled((-(-h // block), -(-w // block), 4))
        runner.run(step, {"codes": level}, {"reduced": reduced}, uniforms={"block": block})
        made.append(reduced)
        level = reduced
    neighbors = ctx.pooled(level.shape[:2] + (4,))
    runner.run(NEIGHBOR_MAX, {"tiles": level}, {"neighbor_max": neighbors})
    textures = {"color": inputs["color"], "velocity": velocity, "neighbor_max": neighbors}
    uniforms = {"radius": radius, "tile": tile}
    result = runner.run_result(RECONSTRUCT, textures, backend, uniforms=uniforms)
    for texture in made[:-1]:
        ctx.recycle(texture)
    outputs = {"color": result, "velocity": velocity, "tile_max": level, "neighbor_max": neighbors}
    return outputs, runner.timings


METHOD = Declaration(
    name="engine_unity",
    kind="gather",
    order=12,
    params=PARAMS,
    passes=(SETUP, *REDUCTIONS, TILE_MAX, NEIGHBOR_MAX, RECONSTRUCT),
    run=run,
    default_grid={"samples": [4, 10, 32]},
    twin=twin.engine_unity,
    doc="Unity PostProcessing v2 / KinoMotion motion blur, from its described algorithm: "
    "10-bit velocity and depth, tiles of 5 % of the height by 2x reductions, NeighborMax "
    "biased to the center, mirrored pairs along NeighborMax and v_alt. docs/spec.md §17.3.",
)
