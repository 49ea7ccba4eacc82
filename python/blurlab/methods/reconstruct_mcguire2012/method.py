"""reconstruct_mcguire2012: the reconstruction filter of McGuire, Hennessy, Bukowski and Osman,
"A Reconstruction Filter for Plausible Motion Blur" (I3D 2012), docs/spec.md §3 (spec.md here).

TileMax → NeighborMax → reconstruct (reconstruct.glsl beside this file), with the engines'
options of docs/guertin2014.md. NumPy twin: twin.reconstruct_mcguire2012. Parameters:
TILE_FILTER_PARAMS and FILTER_OPTIONS (blurlab/methods/tile_filter.py); `blurlab methods` lists
them with defaults and ranges. Tile classification was built as an option and removed: it
measured slower (docs/classify_and_steps.md).
"""

from __future__ import annotations

from ..core import Pass, shader_beside
from ..folders import Declaration
from ..tile_filter import FILTER_OPTIONS, TILE_FILTER_PARAMS, options_filter, uniform_names
from .twin import reconstruct_mcguire2012

PARAMS = {**TILE_FILTER_PARAMS, **FILTER_OPTIONS}
RECONSTRUCT = Pass(
    "reconstruct", shader_beside(__file__, "reconstruct.glsl"), uniform_names(PARAMS)
)

METHOD = Declaration(
    name="reconstruct_mcguire2012",
    order=1,
    **options_filter(
        PARAMS,
        RECONSTRUCT,
        diagonal_reach=False,
        grid={"k": [10, 20, 40], "samples": [5, 9, 15, 25]},
    ),
    twin=reconstruct_mcguire2012,
    study_curves=("samples", "k"),
    gallery=True,
    example=True,
    doc="McGuire, Hennessy, Bukowski, Osman: A Reconstruction Filter for Plausible Motion "
    "Blur (I3D 2012). docs/spec.md §3; options in docs/guertin2014.md.",
)
