"""engine_jimenez2014: the reconstruction filter of Jimenez's SIGGRAPH 2014 talk "Next
Generation Post Processing in Call of Duty: Advanced Warfare", the common root of HDRP's,
Unreal's and many smaller engines' motion blur, written from the talk (spec.md here,
docs/spec.md §17.8), not from any engine's source. §3's TileMax and NeighborMax
(methods/tile_filter.py), then one pass (reconstruct.glsl beside this file): mirrored pairs
along NeighborMax, the soft depth split of whose blur reaches whom, the weight the taps leave
to the pixel (the foreground's alpha, growing and shrinking its silhouette) and interleaved
gradient noise for the jitter. NumPy twin: twin.engine_jimenez2014.

engine_unreal (§17.5) already has the talk's weights, pairs and alpha on Unreal 4's own tiles
and packed velocities; this method is the talk's filter without them, on §3's parameters, so it
stands beside reconstruct_mcguire2012 and reconstruct_guertin2014 as a filter.
"""

from __future__ import annotations

from ..core import Pass, PassRunner, shader_beside
from ..folders import Declaration
from ..tile_filter import TILE_FILTER_PARAMS, reconstruct_on_tiles
from .twin import engine_jimenez2014

PARAMS = dict(TILE_FILTER_PARAMS)
RECONSTRUCT = Pass("reconstruct", shader_beside(__file__, "reconstruct.glsl"), tuple(PARAMS))


def run(ctx, frame, inputs: dict, values: dict, backend: str, passes: dict):
    runner = PassRunner(ctx, PARAMS, values)
    textures = {name: inputs[name] for name in ("color", "depth", "motion")}
    return reconstruct_on_tiles(runner, RECONSTRUCT, textures, inputs["motion"], backend)


METHOD = Declaration(
    name="engine_jimenez2014",
    kind="filter",
    order=16,
    params=PARAMS,
    passes=(RECONSTRUCT,),
    backends=("compute", "fragment"),
    run=run,
    default_grid={"k": [10, 20, 40], "samples": [8, 16]},
    twin=engine_jimenez2014,
    doc="Jimenez 2014 (Call of Duty: Advanced Warfare): mirrored pairs along NeighborMax, "
    "soft depth split of whose blur reaches whom, the weight left to the pixel as the "
    "foreground's alpha, interleaved gradient noise. docs/spec.md §17.8.",
)
