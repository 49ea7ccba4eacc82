"""engine_eevee: the post-process motion blur of Blender EEVEE-Next, written from the algorithm
as Blender's user manual (Render > Motion Blur) describes it, not from Blender's
sources: spec.md here, docs/spec.md §17.2. Three passes on the two-sided motion of §17.1: tile
flatten (shaders/passes/eevee_tile_flatten.glsl), dilation along each tile's motion
(eevee_tile_dilate.glsl), both shared with another method (blurlab.methods.eevee), and the
gather over both half-shutters (gather.glsl beside this file). NumPy twin: twin.engine_eevee.
Parameters: below, at EEVEE's defaults; `steps` (bl.render_and_blur) gives EEVEE's 2·steps + 1
time points.

What it leaves out: EEVEE's accumulation of render samples (one pass here is one sample), its
shutter curve, its atomic scatter (replaced by a gather with the same result) and the
packing of its velocity buffer (the G-buffer's float32 motion is read as it is).
"""

from __future__ import annotations

from ..core import SEED, Param, Pass, PassRunner, shader_beside
from ..eevee import dilated_tiles
from ..folders import Declaration
from ..tile_filter import TILE_FILTER_PARAMS
from .twin import engine_eevee

PARAMS = {
    "tile_size": Param(32, int, "tile side, pixels", 4, 256),
    "samples": Param(8, int, "samples on each side (prev and next half-shutter)", 1, 64),
    "max_blur": Param(32.0, float, "longest half-motion, pixels (Blender's Max Blur)", 0, 2**20),
    "depth_scale": Param(
        100.0, float, "1 / soft depth extent, per depth unit (Background Separation)", 2**-20, 2**20
    ),
    "exposure": TILE_FILTER_PARAMS["exposure"],
    "seed": SEED,
}
GATHER = Pass("gather", shader_beside(__file__, "gather.glsl"), tuple(PARAMS))


def run(ctx, frame, inputs: dict, values: dict, backend: str, passes: dict):
    size = inputs["color"].shape[:2]
    runner = PassRunner(ctx, PARAMS, values)
    sides, tiles, dilated, _ = dilated_tiles(
        ctx, frame, runner.timings, PARAMS, values, size, values["tile_size"], values["max_blur"]
    )
    textures = {
        "color": inputs["color"],
        "depth": inputs["depth"],
        "motion_sides": sides,
        "dilated": dilated,
    }
    result = runner.run_result(GATHER, textures, backend)
    return {"color": result, "tiles": tiles, "dilated": dilated}, runner.timings


METHOD = Declaration(
    name="engine_eevee",
    kind="gather",
    order=11,
    params=PARAMS,
    passes=(GATHER,),
    run=run,
    default_grid={"samples": [4, 8, 16], "max_blur": [32.0, 128.0]},
    twin=engine_eevee,
    doc="Blender EEVEE-Next's post-process motion blur, from its described algorithm: 32 px "
    "tiles, dilation along each tile's motion, 8 samples on each half-shutter of the "
    "two-sided motion, jittered tile lookup, soft depth comparison. docs/spec.md §17.2.",
)
