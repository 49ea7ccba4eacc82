"""engine_jimenez2014: the reconstruction filter of Jimenez's SIGGRAPH 2014 talk "Next
Generation Post Processing in Call of Duty: Advanced Warfare", the common root of HDRP's,
Unreal's and many smaller engines' motion blur, written from the talk (docs/spec.md §17.8), not
from any engine's source. §3's TileMax and NeighborMax (methods/tile_filter.py), then one pass
(shaders/passes/jimenez2014_reconstruct.glsl): mirrored pairs along NeighborMax, the soft depth
split of whose blur reaches whom, the weight the taps leave to the pixel (the foreground's
alpha, growing and shrinking its silhouette) and interleaved gradient noise for the jitter.
NumPy twin: blurlab.twins.jimenez2014.engine_jimenez2014.

engine_unreal (§17.5) already has the talk's weights, pairs and alpha on Unreal 4's own tiles
and packed velocities; this method is the talk's filter without them, on §3's parameters, so it
stands beside reconstruct_mcguire2012 and reconstruct_guertin2014 as a filter.
"""

from __future__ import annotations

from ..core.context import Context
from ..core.frame import Frame
from ..twins import jimenez2014 as twin
from .core import Method, Pass, PassRunner, register
from .tile_filter import TILE_FILTER_PARAMS, reconstruct_on_tiles

PARAMS = dict(TILE_FILTER_PARAMS)
RECONSTRUCT = Pass("reconstruct", "passes/jimenez2014_reconstruct.glsl", tuple(PARAMS))


def _run_jimenez2014(ctx: Context, frame: Frame, inputs: dict, values: dict, backend: str):
    passes = PassRunner(ctx, PARAMS, values)
    textures = {name: inputs[name] for name in ("color", "depth", "motion")}
    return reconstruct_on_tiles(passes, RECONSTRUCT, textures, inputs["motion"], backend)


register(
    Method(
        name="engine_jimenez2014",
        kind="filter",
        params=PARAMS,
        backends=("compute", "fragment"),
        run=_run_jimenez2014,
        default_grid={"k": [10, 20, 40], "samples": [8, 16]},
        twin=twin.engine_jimenez2014,
        doc="Jimenez 2014 (Call of Duty: Advanced Warfare): mirrored pairs along NeighborMax, "
        "soft depth split of whose blur reaches whom, the weight left to the pixel as the "
        "foreground's alpha, interleaved gradient noise. docs/spec.md §17.8.",
    )
)
